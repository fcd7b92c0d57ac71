"""The materials database: bed solids, coating liquids and melts, fluidizing gases.

Entries live in TOML files, one table per entry under its kind::

    [solid.silica-sand]
    density = 2650.0            # kg/m3
    ...
    source = "..."
    confidence = "..."

The package's own files are found inside an installed wheel (``agglomtool/_materials``) or,
in a source checkout or editable install, in the repository's top-level ``materials/``.
A user adds entries, without touching the package, with TOML files in directories passed as
``extra_dirs`` or listed in the environment variable ``AGGLOMTOOL_MATERIALS`` (separated by
``os.pathsep``). A name defined twice is an error that names both files; a user entry
cannot replace a built-in one (give it a name of its own).

Names are normalised when a file is loaded: lower case, with runs of spaces, hyphens and
underscores turned into one hyphen (``[solid.My_Sand]`` is the solid ``my-sand``, and
``[solid.silica_sand]`` clashes with the built-in ``silica-sand``). :func:`names` lists the
normalised names, and every look-up accepts any spelling that normalises to one of them.

Loading validates every entry: an error names the file, the entry and the field. Files are
read with :mod:`tomllib` only, as UTF-8; a file that is not UTF-8 or not TOML is an error
naming it.
"""

from __future__ import annotations

import contextlib
import hashlib
import math
import os
import re
import threading
import tomllib
from dataclasses import dataclass, replace
from functools import cache
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any, cast

from ._validate import material_key as _key
from ._validate import unknown_name
from .inputs import Liquid, Particle

__all__ = [
    "MaterialsError",
    "AssumedLaw",
    "Solid",
    "LiquidEntry",
    "GasEntry",
    "names",
    "solid",
    "liquid",
    "liquid_entry",
    "gas",
    "load",
    "builtin_dir",
    "fingerprint",
    "snapshot",
    "pinned",
    "Snapshot",
    "MaterialsChangedWarning",
    "ENV_VAR",
]

#: Environment variable listing extra TOML directories (``os.pathsep``-separated).
ENV_VAR = "AGGLOMTOOL_MATERIALS"

KINDS = ("solid", "liquid", "gas")


class MaterialsError(ValueError):
    """A materials file or entry is malformed; the message names file, entry and field."""


@dataclass(frozen=True)
class AssumedLaw:
    """The plausible law of one assumed database value, as the database states it.

    Plain data (the uncertainty layer turns it into a distribution): ``law`` is
    ``"lognormal"`` with ``params = (p05, p95)``, its 5 and 95 % quantiles, or
    ``"uniform"`` with ``params = (lo, hi)``; values in the field's SI unit. A melt's
    composition takes ``"logratio"`` with ``params = (factor_p05, factor_p95)``: the 5 and
    95 % quantiles of the lognormal factor on each oxide's share (see
    ``COMPOSITION_LAW``).
    """

    field: str
    law: str
    params: tuple[float, float]
    reason: str


#: Laws an assumed value may be given, with the names of their two parameters.
ASSUMED_LAWS = {"lognormal": ("p05", "p95"), "uniform": ("lo", "hi"),
                "logratio": ("factor_p05", "factor_p95")}
#: The law of an assumed composition (a melt's ``composition_wt``): each oxide's share
#: multiplied by its own lognormal factor (5 and 95 % quantiles ``factor_p05``,
#: ``factor_p95``), then the whole rescaled to 100 wt % (a log-ratio normal law, the
#: usual law of compositional data: Aitchison, The Statistical Analysis of Compositional
#: Data, 1986). Numbers take the other laws.
COMPOSITION_LAW = "logratio"
_COMPOSITION_FIELDS = ("composition_wt",)


@dataclass(frozen=True)
class Solid:
    """A bed solid: typical properties of one material, with their source."""

    name: str
    density: float  #: [kg/m3]
    asperity_height: float  #: [m]
    restitution_dry: float  #: dry coefficient of restitution [-]
    size_range: tuple[float, float]  #: typical particle diameters [m]
    source: str
    confidence: str
    file: str
    #: Fields of this entry that are assumptions (not measured or published values).
    assumed: tuple[str, ...] = ()
    #: The plausible law of each assumed numeric field (:class:`AssumedLaw`, one a field).
    uncertainty: tuple[AssumedLaw, ...] = ()

    def particle(self, d, h0=0.0, ha=None) -> Particle:
        """A :class:`~agglomtool.Particle` of this solid with diameter ``d`` [m].

        ``h0`` is the coating thickness [m]; ``ha`` defaults to the entry's asperity height.
        """
        return Particle(d=d, rho=self.density, h0=h0, ha=self.asperity_height if ha is None else ha)


@dataclass(frozen=True)
class LiquidEntry:
    """A coating liquid: fixed properties, water (CoolProp), or a melt of given oxides."""

    name: str
    model: str  #: "fixed", "water" or "melt"
    theta_deg: float  #: contact angle on the bed solid [deg]
    source: str
    confidence: str
    file: str
    mu: float | None = None  #: [Pa s], fixed liquids
    gamma: float | None = None  #: [N/m], fixed liquids
    rho: float | None = None  #: [kg/m3], fixed liquids
    composition_wt: MappingProxyType | None = None  #: oxide -> wt %, melts
    viscosity_model: str = "auto"  #: melts
    #: Fields of this entry that are assumptions (not measured or published values).
    assumed: tuple[str, ...] = ()
    #: The plausible law of each assumed numeric field (:class:`AssumedLaw`, one a field).
    uncertainty: tuple[AssumedLaw, ...] = ()


@dataclass(frozen=True)
class GasEntry:
    """A fluidizing gas: its composition in mole fractions, keyed by species formula."""

    name: str
    composition: MappingProxyType
    source: str
    confidence: str
    file: str


# ---------------------------------------------------------------------------------------
# Field validation


def _fail(file, kind, key, field, msg) -> MaterialsError:
    return MaterialsError(f"{file}: [{kind}.{key}] field '{field}': {msg}")


def _number(ctx, entry, field, lo=None, hi=None, *, lo_open=False, required=True, default=None):
    file, kind, key = ctx
    if field not in entry:
        if required:
            raise _fail(file, kind, key, field, "is missing")
        return default
    value = entry[field]
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _fail(file, kind, key, field, f"must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise _fail(file, kind, key, field, f"must be finite, got {value!r}")
    too_low = lo is not None and (value <= lo if lo_open else value < lo)
    if too_low or (hi is not None and value > hi):
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        raise _fail(
            file, kind, key, field,
            f"{value!r} is outside the allowed range {'(' if lo_open else '['}{lo_s}, {hi_s}]",
        )
    return value


def _text(ctx, entry, field, *, required=True, default=""):
    file, kind, key = ctx
    if field not in entry:
        if required:
            raise _fail(file, kind, key, field, "is missing")
        return default
    value = entry[field]
    if not isinstance(value, str) or not value.strip():
        raise _fail(file, kind, key, field, f"must be a non-empty string, got {value!r}")
    return value


def _no_unknown(ctx, entry, allowed):
    file, kind, key = ctx
    unknown = sorted(set(entry) - set(allowed))
    if unknown:
        raise _fail(file, kind, key, unknown[0],
                    f"is not a known field; allowed: {sorted(allowed)}")


def _fractions(ctx, entry, field, check_key, total, tol):
    file, kind, key = ctx
    table = entry.get(field)
    if not isinstance(table, dict) or not table:
        raise _fail(file, kind, key, field, "must be a non-empty table of component = amount")
    out = {}
    for comp in table:
        try:
            check_key(comp)
        except ValueError as exc:
            raise _fail(file, kind, key, f"{field}.{comp}", str(exc)) from None
        out[comp] = _number(ctx, table, comp, 0.0, total)
    s = sum(out.values())
    if abs(s - total) > tol:
        raise _fail(file, kind, key, field, f"amounts sum to {s:g}, expected {total:g} +- {tol:g}")
    return MappingProxyType(out)


_COMMON = ("source", "confidence", "description", "assumed", "uncertainty")


def _assumed(ctx, entry, fields) -> tuple[str, ...]:
    """The optional ``assumed = [field, ...]`` list: which values are assumptions."""
    value = entry.get("assumed", [])
    file, kind, key = ctx
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise _fail(file, kind, key, "assumed", f"must be a list of field names, got {value!r}")
    unknown = sorted(set(value) - set(fields))
    if unknown:
        raise _fail(file, kind, key, "assumed",
                    f"{unknown[0]!r} is not a field of a {kind}; fields: {', '.join(fields)}")
    return tuple(value)


def _uncertainty(ctx, entry, assumed, ranges) -> tuple[AssumedLaw, ...]:
    """The ``[KIND.NAME.uncertainty.FIELD]`` tables: a law for every assumed numeric field.

    ``ranges`` maps each numeric field to ``(lo, hi, lo_open)``, its allowed range; the law
    must lie inside it and hold the entry's own value.
    """
    file, kind, key = ctx
    table = entry.get("uncertainty", {})
    if not isinstance(table, dict):
        raise _fail(file, kind, key, "uncertainty",
                    f"must be a table of field = {{law, ...}}, got {table!r}")
    out = {}
    for field_name, spec in table.items():
        where = f"uncertainty.{field_name}"
        if field_name not in assumed:
            raise _fail(file, kind, key, where,
                        f"only a field listed in assumed ({list(assumed)}) takes a law")
        composition = field_name in _COMPOSITION_FIELDS
        if field_name not in ranges and not composition:
            raise _fail(file, kind, key, where,
                        f"{field_name!r} is not a number: no law can be drawn for it")
        if not isinstance(spec, dict):
            raise _fail(file, kind, key, where, f"must be a table, got {spec!r}")
        sub = (file, kind, f"{key}.{where}")
        law = _text(sub, spec, "law")
        if law not in ASSUMED_LAWS:
            raise _fail(*sub, "law", f"{law!r} is not one of {sorted(ASSUMED_LAWS)}")
        if composition != (law == COMPOSITION_LAW):
            allowed = ([COMPOSITION_LAW] if composition
                       else sorted(set(ASSUMED_LAWS) - {COMPOSITION_LAW}))
            raise _fail(*sub, "law", f"{law!r} is not a law of {field_name} (a "
                        f"{'composition' if composition else 'number'}); allowed: "
                        f"{', '.join(allowed)}")
        names_ = ASSUMED_LAWS[law]
        _no_unknown(sub, spec, ("law", "reason", *names_))
        # a composition's factors: positive, and the band must hold 1 (the entry's own)
        lo, hi, lo_open = (0.0, None, True) if composition else ranges[field_name]
        a = _number(sub, spec, names_[0], lo, hi, lo_open=lo_open or law == "lognormal")
        b = _number(sub, spec, names_[1], lo, hi, lo_open=lo_open)
        if not a < b:
            raise _fail(*sub, names_[1], f"{b!r} must be greater than {names_[0]} = {a!r}")
        if composition and not a <= 1.0 <= b:
            raise _fail(*sub, names_[0],
                        f"[{names_[0]}, {names_[1]}] = [{a!r}, {b!r}] must hold 1, the "
                        "factor of the entry's own composition")
        value = entry.get(field_name)
        if isinstance(value, int | float) and not a <= float(value) <= b:
            raise _fail(*sub, names_[0],
                        f"the entry's own {field_name} = {value!r} lies outside "
                        f"[{names_[0]}, {names_[1]}] = [{a!r}, {b!r}]")
        out[field_name] = AssumedLaw(field_name, law, (a, b), _text(sub, spec, "reason"))
    missing = [f for f in assumed
               if (f in ranges or f in _COMPOSITION_FIELDS) and f not in out]
    if missing:
        raise _fail(file, kind, key, f"uncertainty.{missing[0]}",
                    f"is missing: {missing[0]!r} is listed in assumed, so the entry states "
                    f"its plausible law ([{kind}.{key}.uncertainty.{missing[0]}] with law = "
                    + (repr(COMPOSITION_LAW) if missing[0] in _COMPOSITION_FIELDS else
                       " or ".join(repr(k) for k in ASSUMED_LAWS if k != COMPOSITION_LAW))
                    + " and reason)")
    return tuple(out.values())


#: Allowed range ``(lo, hi, lo_open)`` of each numeric field of a solid and of a liquid.
_SOLID_RANGES = {"density": (0.0, 25000.0, True), "asperity_height": (0.0, 1e-3, False),
                 "restitution_dry": (0.0, 1.0, True)}
_LIQUID_RANGES = {"theta_deg": (0.0, 89.999, False), "mu": (0.0, None, True),
                  "gamma": (0.0, 5.0, True), "rho": (0.0, 25000.0, True)}


def _solid(ctx, entry) -> Solid:
    _no_unknown(ctx, entry, ("density", "asperity_height", "restitution_dry", "size_range")
                + _COMMON)
    density = _number(ctx, entry, "density", *_SOLID_RANGES["density"][:2], lo_open=True)
    asperity = _number(ctx, entry, "asperity_height", *_SOLID_RANGES["asperity_height"][:2])
    restitution = _number(ctx, entry, "restitution_dry", *_SOLID_RANGES["restitution_dry"][:2],
                          lo_open=True)
    size = entry.get("size_range")
    file, kind, key = ctx
    if (
        not isinstance(size, list)
        or len(size) != 2
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in size)
        or not 0.0 < size[0] <= size[1] < 0.1
    ):
        raise _fail(file, kind, key, "size_range",
                    f"must be [d_min, d_max] in m with 0 < d_min <= d_max < 0.1, got {size!r}")
    assumed = _assumed(ctx, entry, ("density", "asperity_height", "restitution_dry",
                                     "size_range"))
    return Solid(
        name=key,
        density=density,
        asperity_height=asperity,
        restitution_dry=restitution,
        size_range=(float(size[0]), float(size[1])),
        source=_text(ctx, entry, "source"),
        confidence=_text(ctx, entry, "confidence"),
        file=str(file),
        assumed=assumed,
        uncertainty=_uncertainty(ctx, entry, assumed, _SOLID_RANGES),
    )


def _liquid(ctx, entry) -> LiquidEntry:
    from .properties.slag_composition import oxide_info

    file, kind, key = ctx
    model = _text(ctx, entry, "model")
    assumed = _assumed(ctx, entry, ("theta_deg", "mu", "gamma", "rho", "composition_wt",
                                    "viscosity_model"))
    common = {
        "name": key,
        "model": model,
        "theta_deg": _number(ctx, entry, "theta_deg", *_LIQUID_RANGES["theta_deg"][:2]),
        "source": _text(ctx, entry, "source"),
        "confidence": _text(ctx, entry, "confidence"),
        "file": str(file),
        "assumed": assumed,
        "uncertainty": _uncertainty(ctx, entry, assumed, _LIQUID_RANGES),
    }
    if model == "fixed":
        _no_unknown(ctx, entry, ("model", "theta_deg", "mu", "gamma", "rho") + _COMMON)
        return LiquidEntry(
            mu=_number(ctx, entry, "mu", *_LIQUID_RANGES["mu"][:2], lo_open=True),
            gamma=_number(ctx, entry, "gamma", *_LIQUID_RANGES["gamma"][:2], lo_open=True),
            rho=_number(ctx, entry, "rho", *_LIQUID_RANGES["rho"][:2], lo_open=True),
            **common,
        )
    if model == "water":
        _no_unknown(ctx, entry, ("model", "theta_deg") + _COMMON)
        return LiquidEntry(**common)
    if model == "melt":
        from .properties.melt import VISCOSITY_MODELS

        _no_unknown(ctx, entry, ("model", "theta_deg", "composition_wt", "viscosity_model")
                    + _COMMON)
        vm = _text(ctx, entry, "viscosity_model", required=False, default="auto")
        if vm not in ("auto", *VISCOSITY_MODELS):
            raise _fail(file, kind, key, "viscosity_model",
                        f"{vm!r} is not one of {['auto', *VISCOSITY_MODELS]}")
        return LiquidEntry(
            composition_wt=_fractions(ctx, entry, "composition_wt", oxide_info, 100.0, 1.0),
            viscosity_model=vm,
            **common,
        )
    raise _fail(file, kind, key, "model", f"{model!r} is not one of 'fixed', 'water', 'melt'")


def _gas(ctx, entry) -> GasEntry:
    from .properties._gas_tables import check_species

    _no_unknown(ctx, entry, ("composition",) + _COMMON)
    return GasEntry(
        name=ctx[2],
        composition=_fractions(ctx, entry, "composition", check_species, 1.0, 1e-3),
        source=_text(ctx, entry, "source"),
        confidence=_text(ctx, entry, "confidence"),
        file=str(ctx[0]),
    )


_BUILDERS: dict[str, Any] = {"solid": _solid, "liquid": _liquid, "gas": _gas}

#: What a normalised entry name may hold (see :func:`_key`).
_NAME = re.compile(r"[a-z0-9][a-z0-9.+()-]*")


# ---------------------------------------------------------------------------------------
# Files and directories


@cache
def builtin_dir() -> Path:
    """The directory of the package's own TOML files (wheel or source checkout); found once
    per process (the package does not move while it runs), not on every look-up."""
    packaged = resources.files("agglomtool") / "_materials"
    if packaged.is_dir():
        return Path(str(packaged))
    source = Path(__file__).resolve().parent.parent / "materials"
    if source.is_dir():
        return source
    raise MaterialsError(
        "the materials database is missing: neither agglomtool/_materials (installed "
        f"wheel) nor {source} (source checkout) exists"
    )


def load_file(path: Path) -> dict[str, dict[str, object]]:
    """Parse and validate one TOML file: ``{kind: {name: entry}}``."""
    path = Path(path)
    return _parse(path, _read(path))


def _read(path: Path) -> bytes:
    try:
        return path.read_bytes()
    except OSError as exc:
        raise MaterialsError(f"{path}: cannot be read: {exc.strerror or exc}") from None


def _parse(path: Path, raw: bytes) -> dict[str, dict[str, object]]:
    """Parse and validate the bytes ``raw`` of the TOML file ``path`` (not read again)."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MaterialsError(
            f"{path}: is not UTF-8 text (byte {raw[exc.start]:#04x} at offset {exc.start}); "
            "TOML files must be saved as UTF-8") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise MaterialsError(f"{path}: not valid TOML: {exc}") from None
    except RecursionError:
        raise MaterialsError(
            f"{path}: tables or arrays are nested too deeply to read; a materials file needs "
            "two levels ([kind.name]) plus one for composition tables") from None
    out: dict[str, dict[str, object]] = {k: {} for k in KINDS}
    for kind, entries in data.items():
        if kind not in KINDS:
            raise MaterialsError(
                f"{path}: top-level table [{kind}] is not one of {list(KINDS)}; write "
                "entries as [solid.NAME], [liquid.NAME] or [gas.NAME]"
            )
        if not isinstance(entries, dict):
            raise MaterialsError(f"{path}: [{kind}] must hold tables of entries")
        for key, entry in entries.items():
            if not isinstance(entry, dict):
                raise MaterialsError(f"{path}: [{kind}.{key}] must be a table of fields")
            name = _check_name(path, kind, key)
            if name in out[kind]:
                raise MaterialsError(
                    f"{path}: [{kind}.{key}] and another entry of this file are both named "
                    f"{name!r} (case, spaces, hyphens and underscores are interchangeable)")
            out[kind][name] = replace(_BUILDERS[kind]((path, kind, key), entry), name=name)
            _SPELLING[(str(path), kind, name)] = key
    return out


#: (file, kind, normalised name) -> the name as written in the file, for messages.
_SPELLING: dict[tuple[str, str, str], str] = {}


def _check_name(path, kind: str, key: str) -> str:
    """The normalised name of entry ``[kind.key]``: lower case, words joined by hyphens."""
    name = _key(key)
    if not _NAME.fullmatch(name):
        raise MaterialsError(
            f"{path}: [{kind}.{key}]: the name {key!r} must start with a letter or digit and "
            "hold only letters, digits, spaces, '-', '_', '.', '+' and parentheses")
    return name


def _dirs(extra_dirs) -> list[Path]:
    dirs = [builtin_dir()]
    env = os.environ.get(ENV_VAR, "")
    dirs += [Path(p) for p in env.split(os.pathsep) if p.strip()]
    if extra_dirs is not None:
        if isinstance(extra_dirs, str | os.PathLike):
            extra_dirs = [extra_dirs]
        dirs += [Path(p) for p in extra_dirs]
    for d in dirs[1:]:
        if not d.is_dir():
            raise MaterialsError(f"materials directory {d} does not exist or is not a directory")
    return dirs


def _state(dirs: tuple[Path, ...]) -> tuple:
    """The TOML files of ``dirs`` with their inode, modification and change times and sizes:
    a cheap sign that a file was edited, added or removed, so that :func:`load` reads the
    files again (an edit keeping size and mtime, as ``cp -p`` or ``rsync -a`` make, still
    changes the change time or the inode). What is computed is keyed on the files' content
    (:func:`_content_db`), never on these."""
    out: list[tuple[str, int | None, int | None, int | None, int | None]] = []
    for d in dirs:
        for path in sorted(d.glob("*.toml")):
            try:
                st = path.stat()
                out.append((str(path), st.st_ino, st.st_mtime_ns, st.st_ctime_ns, st.st_size))
            except OSError:
                out.append((str(path), None, None, None, None))
    return tuple(out)


def _read_all(dirs: tuple[Path, ...]) -> tuple[tuple[str, bytes], ...]:
    """``(path, bytes)`` of every TOML file of ``dirs``, each read once."""
    return tuple((str(path), _read(path)) for d in dirs for path in sorted(d.glob("*.toml")))


#: Parsed databases by content: (dirs, ((path, sha256), ...)) -> entries; a few kept.
_BY_CONTENT: dict[tuple, MappingProxyType] = {}
_BY_CONTENT_MAX = 16


def _content_db(dirs: tuple[Path, ...], files) -> tuple[tuple, MappingProxyType]:
    """``(content key, entries)`` of the files ``files`` (``(path, bytes)``): parsed once per
    content, from these bytes."""
    key = (dirs, tuple((p, hashlib.sha256(raw).hexdigest()) for p, raw in files))
    db = _BY_CONTENT.get(key)
    if db is None:
        db = _merge(dirs, files)
        if len(_BY_CONTENT) >= _BY_CONTENT_MAX:
            _BY_CONTENT.pop(next(iter(_BY_CONTENT)))
        _BY_CONTENT[key] = db
    return key, db


def _merge(dirs: tuple[Path, ...], files) -> MappingProxyType:
    merged: dict[str, dict[str, Any]] = {k: {} for k in KINDS}
    for name, raw in files:
        path = Path(name)
        for kind, entries in _parse(path, raw).items():
            for key, entry in entries.items():
                if key in merged[kind]:
                    first = merged[kind][key].file
                    builtin = Path(first).parent == dirs[0]
                    written = _SPELLING.get((str(path), kind, key), key)
                    raise MaterialsError(
                        f"{path}: [{kind}.{written}] is already defined in {first}"
                        + (f" as [{kind}.{key}]" if written != key else "")
                        + (" (a built-in entry, which a user file cannot replace)"
                           if builtin else "")
                        + "; choose another name (case, spaces, hyphens and underscores "
                        "are interchangeable in names)"
                    )
                merged[kind][key] = entry
    return MappingProxyType({k: MappingProxyType(v) for k, v in merged.items()})


class Snapshot:
    """The materials files of a run, read and hashed once at its start.

    Every look-up of the run (:func:`load`, :func:`solid`, ...) inside :func:`pinned` is
    answered from the entries parsed from these bytes, without touching the file system;
    the store's fingerprint is made from their SHA-256. A snapshot pickles with the
    files' bytes, so the workers of a cluster compute from the same content (their own
    files are not read).
    """

    def __init__(self, dirs: tuple[Path, ...], files, lookup_key):
        self.dirs, self.files, self.lookup_key = dirs, tuple(files), lookup_key
        self.key, self.db = _content_db(dirs, self.files)
        self.sha256 = dict(self.key[1])
        builtin = dirs[0]
        self.labels = {p: f"agglomtool:{Path(p).name}" if Path(p).parent == builtin else p
                       for p, _ in self.files}

    def __getstate__(self):
        return {"dirs": self.dirs, "files": self.files, "lookup_key": self.lookup_key}

    def __setstate__(self, state):
        self.__init__(state["dirs"], state["files"], state["lookup_key"])

    def changed(self) -> list[str]:
        """The files whose content now differs from the snapshot's (added, removed or
        edited), read again now."""
        now = dict((p, hashlib.sha256(raw).hexdigest()) for p, raw in _read_all_quiet(self.dirs))
        return sorted(p for p in set(now) | set(self.sha256) if now.get(p) != self.sha256.get(p))


def _read_all_quiet(dirs):
    out = []
    for d in dirs:
        for path in sorted(d.glob("*.toml")):
            try:
                out.append((str(path), path.read_bytes()))
            except OSError:
                out.append((str(path), b""))
    return out


def _lookup_key(extra_dirs) -> tuple:
    """What decides the directories of a look-up, without touching the file system."""
    if extra_dirs is None:
        return os.environ.get(ENV_VAR, ""), None
    if isinstance(extra_dirs, str | os.PathLike):
        extra_dirs = [extra_dirs]
    return os.environ.get(ENV_VAR, ""), tuple(str(p) for p in extra_dirs)


def snapshot(extra_dirs=None) -> Snapshot:
    """Read, hash and parse the materials files now (:class:`Snapshot`)."""
    dirs = tuple(p.resolve() for p in _dirs(extra_dirs))
    return Snapshot(dirs, _read_all(dirs), _lookup_key(extra_dirs))


_PINNED = threading.local()


@contextlib.contextmanager
def pinned(snap: Snapshot | None = None):
    """Answer every look-up in this thread from the snapshot ``snap`` (default: one taken
    now, or the one already pinned) while open; yields the snapshot.

    Look-ups with ``extra_dirs=None`` use it always; others where their directories are
    those of the snapshot.
    """
    stack = getattr(_PINNED, "stack", None)
    if stack is None:
        stack = _PINNED.stack = []
    if snap is None:
        snap = stack[-1] if stack else snapshot()
    stack.append(snap)
    try:
        yield snap
    finally:
        stack.pop()


def current() -> Snapshot | None:
    """The snapshot pinned in this thread (:func:`pinned`), if any."""
    stack = getattr(_PINNED, "stack", None)
    return stack[-1] if stack else None


class MaterialsChangedWarning(UserWarning):
    """A materials file changed while a run was computing from its snapshot."""


def warn_if_changed(snap: Snapshot | None, what: str = "the run") -> None:
    """Say (:class:`MaterialsChangedWarning`) which files changed since ``snap`` was
    taken: the run computed from their content at its start (no snapshot: nothing to say)."""
    changed = snap.changed() if snap is not None else []
    if changed:
        import warnings

        warnings.warn(
            f"materials file {changed[0]}"
            + (f" (and {len(changed) - 1} more)" if len(changed) > 1 else "")
            + f" changed while {what} was computing; every value of it comes from the files "
            "as read at its start (recorded in its fingerprint); run again to use the new "
            "content", MaterialsChangedWarning, stacklevel=3)


#: Per set of directories: (their state, the entries read then) for look-ups outside a run.
_LAST: dict[tuple, tuple] = {}


def load(extra_dirs=None) -> MappingProxyType:
    """All entries, validated: ``{kind: {name: entry}}``.

    Inside a run (:func:`pinned`) the run's snapshot, without touching the file system.
    Elsewhere the files are read again when one of them is edited, added or removed (so a
    long session sees the files as they are now); parsed entries are kept by content.
    """
    snap = current()
    if snap is not None and (extra_dirs is None or _lookup_key(extra_dirs) == snap.lookup_key):
        return snap.db
    dirs = tuple(p.resolve() for p in _dirs(extra_dirs))
    state = _state(dirs)
    last = _LAST.get(dirs)
    if last is not None and last[0] == state:
        return last[1]
    _, db = _content_db(dirs, _read_all(dirs))
    _LAST[dirs] = (state, db)
    return db


def _get(kind: str, name: str, extra_dirs):
    entries = load(extra_dirs)[kind]
    key = _key(name)
    if key not in entries:
        raise unknown_name(kind, name, kind, entries)
    return entries[key]


def fingerprint(used: dict, extra_dirs=None) -> dict[str, str]:
    """Where the materials ``used`` come from and what those files hold.

    Parameters
    ----------
    used : dict of str to list of str
        ``{kind: [names]}`` of the entries a computation uses.
    extra_dirs : optional
        As for :func:`load`.

    Returns
    -------
    dict of str to str
        ``"kind name" -> "file sha256"``: the file defining each entry (built-in files as
        ``agglomtool:<file name>``) and the SHA-256 of its bytes: those of the snapshot
        pinned for the run (:func:`pinned`), else as they are now.
    """
    snap = current()
    if snap is None or not (extra_dirs is None or _lookup_key(extra_dirs) == snap.lookup_key):
        snap = snapshot(extra_dirs)  # read now: entries and hashes of the same bytes
    out = {}
    for kind in sorted(used):
        for name in sorted(used[kind]):
            entries = snap.db[kind]
            key = _key(name)
            if key not in entries:
                _get(kind, name, extra_dirs)  # the error naming the known entries
            file = str(entries[key].file)
            out[f"{kind} {key}"] = f"{snap.labels[file]} {snap.sha256[file]}"
    return out


def names(kind: str, extra_dirs=None) -> list[str]:
    """Sorted names of the entries of one kind: ``"solid"``, ``"liquid"`` or ``"gas"``."""
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r} is not one of {list(KINDS)}")
    return sorted(load(extra_dirs)[kind])


def solid(name: str, extra_dirs=None) -> Solid:
    """The bed solid ``name`` (case, spaces, hyphens and underscores are interchangeable)."""
    return _get("solid", name, extra_dirs)


def gas(name: str, extra_dirs=None) -> GasEntry:
    """The gas ``name``; pass it to :func:`agglomtool.properties.gas_properties`."""
    return _get("gas", name, extra_dirs)


def liquid_entry(name: str, extra_dirs=None) -> LiquidEntry:
    """The raw database entry of the liquid ``name``."""
    return _get("liquid", name, extra_dirs)


def liquid(name: str, T=None, *, P=101325.0, theta_deg=None, extra_dirs=None,
           viscosity_model=None) -> Liquid:
    """The coating liquid ``name`` at temperature ``T`` [K] as an :class:`~agglomtool.Liquid`.

    Parameters
    ----------
    name : str
        A liquid in the database (``names("liquid")``).
    T : array_like, optional
        Temperature [K]; required for water and melts, ignored by fixed-property liquids.
    P : float
        Pressure [Pa], used for water only.
    theta_deg : float, optional
        Contact angle [deg]; defaults to the entry's.
    viscosity_model : str, optional
        For melts: overrides the entry's viscosity model ("grd", "urbain-mills", "riboud").
    """
    from ._validate import check_field

    entry = liquid_entry(name, extra_dirs)
    if T is not None:  # the Scene's physical ranges, for a call without a Scene
        T = check_field("T", T)
    P = check_field("P", P)
    theta = entry.theta_deg if theta_deg is None else theta_deg
    label = f"{entry.name} ({entry.file})"
    if entry.model == "fixed":
        # A fixed entry has its three values (the loader requires them).
        return Liquid(mu=cast(float, entry.mu), gamma=cast(float, entry.gamma),
                      rho=cast(float, entry.rho), theta_deg=theta,
                      name=entry.name, source=f"fixed values: {entry.source}")
    if T is None:
        raise ValueError(f"liquid {label} depends on temperature: pass T [K]")
    if entry.model == "water":
        from .properties.water import water_liquid

        return water_liquid(T, P, theta_deg=theta)
    from .properties.melt import melt_liquid

    return melt_liquid(
        dict(cast(MappingProxyType, entry.composition_wt)), T, theta_deg=theta,
        viscosity_model=viscosity_model or entry.viscosity_model, name=entry.name,
    )

