"""Comparison configuration files (TOML) for ``agglomtool compare``::

    [scene]                  # the operating point (as in a map file)
    liquid = "k-silicate-ash-melt"
    T = "875 degC"
    ...

    [compare]                # exactly one field, with its options
    solid_j = ["silica-sand", "ilmenite", "olivine"]

    [uncertain]              # what is uncertain (default: assumed = true)
    assumed = true
    h0 = { law = "normal", mean = "0.5 um", sd = "0.1 um" }

    [options]
    n = 4096                 # paired draws per option
    seed = 0

Every error names the file, the table and the key.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .._config import (
    ConfigError,
    _plain_number,
    check_field_key,
    check_tables,
    parse_scene,
    read_toml,
    warn_scene_findings,
)
from .._fields import FIELD_META
from ..plausibility import scene_findings
from ..scene import Scene
from .compare import BINS
from .distributions import LogNormal, Normal, Uniform

__all__ = ["CompareConfig", "load_compare_config", "parse_compare_config", "parse_uncertain"]


@dataclass
class CompareConfig:
    """A parsed comparison: the Scene, the field and its options, the uncertain inputs."""

    scene: Scene
    field: str
    options: list
    uncertain: object
    n: int
    seed: int | None


def parse_compare_config(data: dict, source: str = "config") -> CompareConfig:
    """Build a :class:`CompareConfig` from a parsed TOML mapping."""
    check_tables(data, source, ("[scene]", "[compare]", "[uncertain]", "[options]"))
    scene = parse_scene(data.get("scene", {}), source)
    comp = data.get("compare")
    if not isinstance(comp, dict) or len(comp) != 1:
        raise ConfigError(f"{source}: [compare] must hold exactly one field with its "
                          "options, e.g. solid_j = [\"silica-sand\", \"ilmenite\"]")
    (field, options), = comp.items()
    check_field_key(f"{source}: [compare]", field)  # with the file and the table
    base = {k: v for k, v in scene.values().items() if k != field}  # the options replace it
    warn_scene_findings(scene, source, scene_findings(base))
    if not isinstance(options, list) or len(options) < 2:
        raise ConfigError(f"{source}: [compare] {field}: must be a list of two or more "
                          f"options, got {options!r}")
    uncertain = (parse_uncertain(data["uncertain"], source) if "uncertain" in data
                 else "assumed")
    from ..scene import typed_unread
    from .scene_mc import drawn_speeds

    found = typed_unread(scene, [k for k in data.get("scene", {}) if k != field],
                         options if field == "speed" else (), drawn_speeds(scene, uncertain))
    if found:
        raise ConfigError(f"{source}: [scene] {found[0]}: {found[1]}")
    opts = dict(data.get("options", {}))
    bad = sorted(set(opts) - {"n", "seed"})
    if bad:
        raise ConfigError(f"{source}: [options] {bad[0]}: unknown; allowed: n, seed")
    n = opts.get("n", 4096)
    least = BINS
    if isinstance(n, bool) or not isinstance(n, int) or n < least:
        raise ConfigError(f"{source}: [options] n: must be an integer >= {least} (the "
                          f"equal-count bins that find the deciding input), got {n!r}")
    seed = opts.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ConfigError(f"{source}: [options] seed: must be an integer >= 0, got {seed!r}")
    return CompareConfig(scene, field, options, uncertain, n, seed)


def load_compare_config(path) -> CompareConfig:
    """Read and validate a comparison file (TOML)."""
    return parse_compare_config(read_toml(path), str(path))


#: The laws an ``[uncertain]`` table may name, with their parameters (required, optional).
UNCERTAIN_LAWS = {
    "normal": (("mean", "sd"), ("lo", "hi", "units")),
    "lognormal": (("mean", "sd"), ("lo", "hi", "units")),
    "uniform": (("low", "high"), ("lo", "hi", "units")),
}


def _one_kind(where: str, key: str, params: dict) -> None:
    """The numbers of a law hold quantities with units or bare SI numbers, not both (as a
    grid's lists and ranges do, :func:`agglomtool._config._same_kind`), unless ``units``
    says what the bare ones are in: ``{ mean = "5 um", sd = 1e-6 }`` would be read as a
    spread of 1 um only by chance, ``sd = 1`` as 1 m."""
    unit = FIELD_META[key][0]
    if "units" in params or unit in ("", "-", "1", "dimensionless"):
        return
    numbers = [k for k in params if k != "units"]
    texts = [k for k in numbers if isinstance(params[k], str) and not _plain_number(params[k])]
    bare = [k for k in numbers if isinstance(params[k], int | float)
            and not isinstance(params[k], bool)]
    if texts and bare:
        t, b = texts[0], bare[0]
        raise ConfigError(
            f"{where}: {t} = \"{params[t]}\" has a unit and {b} = {params[b]!r} has none "
            f"(read as {params[b]!r} {unit}); give each number of the law with its unit, or "
            f"units = \"...\" for the bare ones")


def parse_uncertain(table, source: str = "config"):
    """The ``[uncertain]`` table of a configuration, as ``uncertain=`` takes it.

    ``assumed = true`` draws every value the materials database assumes; every other key
    is a numeric Scene field with its law, e.g. ``h0 = { law = "normal", mean = "5 um",
    sd = "1 um" }`` (numbers SI, or quantities with units as strings). Returns
    ``"assumed"``, or a mapping of field -> distribution (with ``"assumed": True`` when
    both are asked). Errors are :class:`ConfigError` naming the file and the key.
    """
    if not isinstance(table, dict) or not table:
        raise ConfigError(f"{source}: [uncertain] must be a table: assumed = true and/or "
                          "field = { law = ..., ... }")
    laws: dict[str, Any] = {"normal": Normal, "lognormal": LogNormal, "uniform": Uniform}
    out: dict = {}
    for key, spec in table.items():
        where = f"{source}: [uncertain] {key}"
        if key == "assumed":
            if not isinstance(spec, bool):
                raise ConfigError(f"{where}: must be true or false, got {spec!r}")
            if spec:
                out["assumed"] = True
            continue
        if key not in FIELD_META:
            raise ConfigError(f"{where}: not a numeric Scene field; fields: "
                              f"{', '.join(FIELD_META)}, or assumed")
        if not isinstance(spec, dict) or "law" not in spec:
            raise ConfigError(f"{where}: must be a table with a law, e.g. {{ law = "
                              "\"normal\", mean = ..., sd = ... }")
        law = spec["law"]
        if law not in UNCERTAIN_LAWS:
            raise ConfigError(f"{where}: law = {law!r} is not one of "
                              f"{', '.join(UNCERTAIN_LAWS)}")
        required, optional = UNCERTAIN_LAWS[law]
        params = {k: v for k, v in spec.items() if k != "law"}
        unknown = sorted(set(params) - set(required) - set(optional))
        missing = [k for k in required if k not in params]
        if unknown or missing:
            raise ConfigError(f"{where}: law {law!r} takes {', '.join(required)} (and "
                              f"optionally {', '.join(optional)}); "
                              + (f"unknown: {unknown[0]}" if unknown else
                                 f"missing: {missing[0]}"))
        _one_kind(where, key, params)
        try:
            out[key] = laws[law](**params)
        except (ValueError, TypeError) as exc:
            raise ConfigError(f"{where}: {exc}") from None
    if not out:
        raise ConfigError(f"{source}: [uncertain] names no uncertain input (assumed = false "
                          "and no field)")
    if list(out) == ["assumed"]:
        return "assumed"
    return out
