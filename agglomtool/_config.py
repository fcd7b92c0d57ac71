"""The pieces of TOML configuration files that map files (:mod:`agglomtool.maps.config`)
and bed files (:mod:`agglomtool.bed.config`) share: the error, reading the file, a grid
axis (values, or a range with units) and the ``[scene]`` table.

They live here, beside the scene and below both kinds of file, so that neither the maps
nor the bed mixtures import the other.
"""

from __future__ import annotations

import tomllib
import warnings
from pathlib import Path

import numpy as np

from ._fields import FIELD_META, SPEED_LAW_NEEDS
from ._validate import suggestion
from .plausibility import PlausibilityWarning, scene_findings
from .scene import Scene, field_names, typed_without_effect
from .units import to_si

__all__ = ["ConfigError", "check_field_key", "check_tables", "parse_scene", "read_toml",
           "warn_scene_findings"]


class ConfigError(ValueError):
    """A configuration file (a map's or a bed's) is malformed; the message names the key."""


def _number(where: str, key: str, value):
    """A numeric field's value: a number (SI) or a unit string ("5 um", "850 degC")."""
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise ConfigError(f"{where}: must be a number or a quantity with units, got {value!r}")
    if isinstance(value, str):
        unit, long_name = FIELD_META[key]
        try:
            return to_si(key, value, unit, long_name)
        except ValueError as exc:
            raise ConfigError(f"{where}: {exc}") from None
    return float(value)


def _plain_number(text: str) -> bool:
    """``"2"``, ``"1e-6"``: a number written as a string, no unit."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _same_kind(where: str, key: str, values: list, *, in_range: bool = False) -> None:
    """A list of values of a numeric field (or a range's start and stop) holds quantities with
    units or bare SI numbers, not both: ``["20 degC", "80 degC", 5]`` reads as a range written
    as a list (5 would be 5 K), ``{ start = "800 degC", stop = 1200 }`` as 800-1200 degC."""
    unit = FIELD_META[key][0]
    if unit in ("", "-", "1", "dimensionless"):
        return  # a number is a number: "2" and 4.0 mean what they say
    texts = [v for v in values if isinstance(v, str) and not _plain_number(v)]
    bare = [v for v in values if isinstance(v, int | float) and not isinstance(v, bool)]
    if texts and bare and in_range:
        raise ConfigError(
            (f"{where}: start and stop mix quantities with units ({texts[0]!r}) and bare "
             f"numbers ({bare[0]!r}, read as {bare[0]!r} {unit}); give both with their "
             "unit").replace("'", '"'))
    if texts and bare:
        ranged = (f", or a range: {key} = {{ start = {texts[0]!r}, stop = {texts[-1]!r}, "
                  "num = ... }" if len(texts) > 1 else "")
        raise ConfigError(
            (f"{where}: {key} = {values!r} mixes quantities with units ({texts[0]!r}) and bare "
             f"numbers ({bare[0]!r}, read as {bare[0]!r} {unit}); a list holds the values "
             f"themselves. Give every value with its unit{ranged}").replace("'", '"'))


def _axis(where: str, value, key: str = ""):
    numeric = key in FIELD_META
    if isinstance(value, list):
        if not value:
            raise ConfigError(f"{where}: {key or 'the axis'} = [] is empty; allowed: a list "
                              "of one or more values")
        if numeric:
            _same_kind(where, key, value)
            return np.asarray([_number(where, key, v) for v in value], dtype=float)
        if all(isinstance(v, str) for v in value):
            return list(value)
        raise ConfigError(f"{where}: values must be all numbers or all names, got {value!r}")
    if isinstance(value, dict):
        unknown = sorted(set(value) - {"start", "stop", "num", "log"})
        if unknown:
            raise ConfigError(f"{where}: unknown key {unknown[0]!r}; a range takes start, "
                              "stop, num and optionally log")
        for k in ("start", "stop", "num"):
            if k not in value:
                raise ConfigError(f"{where}: a range needs {k!r}")
        if not numeric:
            raise ConfigError(f"{where}: a range (start, stop, num) needs a numeric field")
        _same_kind(where, key, [value["start"], value["stop"]], in_range=True)
        start = _number(f"{where}.start", key, value["start"])
        stop = _number(f"{where}.stop", key, value["stop"])
        num = value["num"]
        if isinstance(num, bool) or not isinstance(num, int) or num < 1:
            raise ConfigError(f"{where}.num: must be an integer >= 1, got {num!r}")
        if num == 1 and start != stop:
            raise ConfigError(f"{where}: num = 1 with start != stop would ignore stop; give "
                              "num >= 2, or one value")
        log = value.get("log", False)
        if not isinstance(log, bool):
            raise ConfigError(f"{where}.log: must be true or false, got {log!r}")
        if log:
            if start <= 0.0 or stop <= 0.0:
                raise ConfigError(f"{where}: log = true needs start and stop > 0")
            return np.geomspace(start, stop, num)
        return np.linspace(start, stop, num)
    if isinstance(value, int | float | str) and not isinstance(value, bool):
        if numeric:
            return np.asarray([_number(where, key, value)])
        return [value]
    raise ConfigError(f"{where}: must be a list of values or a table start/stop/num, "
                      f"got {value!r}")


def check_tables(data: dict, source: str, allowed: tuple[str, ...]) -> None:
    """Refuse a table the file kind does not know; ``allowed`` as a reader writes them
    (``"[scene]"``, ``"[[component]]"``)."""
    names = {a.strip("[]") for a in allowed}
    unknown = sorted(set(data) - names)
    if unknown:
        raise ConfigError(f"{source}: unknown table [{unknown[0]}]; allowed: "
                          f"{', '.join(allowed)}")


def check_field_key(where: str, key: str) -> None:
    """A :class:`ConfigError` where the key ``key`` of a table (``where``: the file and the
    table, as ``"map.toml: [grid]"``) is not a Scene field, with the field it may have
    meant and the fields there are (the ``[scene]``, ``[grid]`` and ``[compare]`` keys)."""
    fields = field_names()
    if key not in fields:
        raise ConfigError(f"{where} {key}: not a Scene field"
                          f"{suggestion(key, fields, material=False)}; fields: "
                          f"{', '.join(fields)}")


def parse_scene(scene_data, source: str = "config", grid: dict | None = None) -> Scene:
    """The :class:`~agglomtool.Scene` of a configuration's ``[scene]`` table.

    Every field must be a Scene field with one value (numbers SI, or quantities with units
    as strings); an error is a :class:`ConfigError` naming ``source`` and the key. Its
    plausibility findings are not said here: a field that a grid sweeps has no scene value
    to judge (see :func:`warn_scene_findings`). The value that the speed law the table
    names needs (``u0`` of ``speed = "fixed"``), where the ``grid`` (``{name: SI values}``)
    sweeps it and the table does not give it, is the grid's first: the sweep replaces it.
    """
    if not isinstance(scene_data, dict):
        raise ConfigError(f"{source}: [scene] must be a table of field = value")
    for key, value in scene_data.items():
        check_field_key(f"{source}: [scene]", key)
        if isinstance(value, list | dict):
            raise ConfigError(f"{source}: [scene] {key} = {value!r} must be a single value; "
                              "put ranges in [grid]")
    needed = SPEED_LAW_NEEDS.get(str(scene_data.get("speed")))
    if grid and needed in grid and needed not in scene_data:
        scene_data = {**scene_data, needed: float(np.ravel(grid[needed])[0])}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            scene = Scene(**scene_data)
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{source}: [scene]: {exc}") from None
    found = typed_without_effect(scene, scene_data)
    if found:
        raise ConfigError(f"{source}: [scene] {found[0]}: {found[1]}")
    return scene


def warn_scene_findings(scene: Scene, source: str, swept: list, stacklevel: int = 2) -> None:
    """Say the plausibility findings of the ``[scene]`` that still hold at the values swept
    (``swept``: the findings of the scene over its grid), naming the file and the table;
    the others are the sweep's to say. ``stacklevel`` counts from the caller, as for
    ``warnings.warn``."""
    deferred = getattr(scene, "_deferred_findings", ())  # about defaults: the sweep's
    for finding in scene_findings(scene.values()):
        if finding in swept and finding not in deferred:
            warnings.warn(f"{source}: [scene]: {finding[1]}", PlausibilityWarning,
                          stacklevel=stacklevel + 1)


def read_toml(path) -> dict:
    """The parsed TOML file ``path``; every failure a :class:`ConfigError` naming it."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ConfigError(f"{path}: is a directory, not a TOML file") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML: {exc}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: not UTF-8 text (byte {exc.start}): TOML files are "
                          "UTF-8") from None
    except RecursionError:
        raise ConfigError(f"{path}: nested too deeply to be a configuration") from None
    return data

