"""Bed configurations in TOML: a scene, the bed's components, an optional grid and options.

Example::

    [scene]                          # any Scene field (numbers SI, or quantities as strings)
    liquid = "water"
    T = "25 degC"
    h0 = "5 um"
    U_Umf = 2.0

    [[component]]                    # one table per component
    solid = "silica-sand"
    fraction = 0.7                   # mass fraction; all components sum to 1
    d50 = "1000 um"                  # lognormal (d50, gsd, classes) ...
    gsd = 1.3
    classes = 10

    [[component]]
    solid = "ilmenite"
    fraction = 0.3
    d = ["800 um", "1000 um"]        # ... or explicit classes (d, d_fractions)
    h0 = 0.0                         # its own coating (default: the scene's h0)

    [grid]                           # optional: a bed sweep (agglomtool.bed_sweep)
    U_Umf = { start = 1.5, stop = 4.0, num = 11 }
    fraction = [0.0, 0.3, 0.6]       # the mass fraction of options.mix

    [options]
    nodes = 16                       # speed quadrature nodes
    directions = 8                   # Gauss-Legendre nodes in sin(beta)
    mix = "ilmenite"                 # the component the grid's fraction sets

Every error names the file, the table and the key.
"""

from __future__ import annotations

import warnings

from .._config import ConfigError, _axis, check_tables, parse_scene, read_toml, warn_scene_findings
from .._validate import suggestion
from ..plausibility import BED_OWN, PlausibilityWarning, scene_findings
from .mixture import Component

__all__ = ["BedConfig", "load_bed_config", "parse_bed_config"]

_LENGTHS = ("d50", "h0", "ha")
_COMPONENT_KEYS = ("solid", "fraction", "d50", "gsd", "classes", "d", "d_fractions", "h0", "ha")


class BedConfig:
    """A parsed bed configuration: ``scene``, ``components``, ``grid`` (may be empty),
    ``options`` (``nodes``, ``directions``, ``mix``)."""

    def __init__(self, scene, components, grid, options):
        self.scene, self.components, self.grid, self.options = scene, components, grid, options


def _length(where, value):
    if isinstance(value, str):
        return value  # the Component converts it, and names what was typed if refused
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{where}: must be a number [m] or a length with units, got {value!r}")
    return float(value)


def _component(where, table) -> Component:
    if not isinstance(table, dict):
        raise ConfigError(f"{where}: must be a table")
    unknown = sorted(set(table) - set(_COMPONENT_KEYS))
    if unknown:
        raise ConfigError(f"{where} {unknown[0]}: unknown"
                          f"{suggestion(unknown[0], _COMPONENT_KEYS, material=False)}; "
                          f"allowed: {', '.join(_COMPONENT_KEYS)}")
    kw = dict(table)
    for key in _LENGTHS:
        if key in kw:
            kw[key] = _length(f"{where} {key}", kw[key])
    if "d" in kw:
        if not isinstance(kw["d"], list):
            raise ConfigError(f"{where} d: must be a list of diameters")
        kw["d"] = tuple(_length(f"{where} d", v) for v in kw["d"])
    if "d_fractions" in kw and isinstance(kw["d_fractions"], list):
        kw["d_fractions"] = tuple(kw["d_fractions"])
    try:
        with warnings.catch_warnings(record=True) as caught:  # say where, below
            warnings.simplefilter("always", PlausibilityWarning)
            comp = Component(**kw)
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{where}: {exc}") from None
    for w in caught:
        if issubclass(w.category, PlausibilityWarning):
            warnings.warn(f"{where}: {w.message}", PlausibilityWarning, stacklevel=4)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return comp


def parse_bed_config(data: dict, source: str = "config") -> BedConfig:
    """Build a :class:`BedConfig` from a parsed TOML mapping."""
    from ..scene import swept_without_effect, typed_unread
    from .propensity import (
        BED_GRID_FIELDS,
        _check_components,
        _grid_arrays,
        _mix_index,
        check_fraction_axis,
    )

    check_tables(data, source, ("[scene]", "[[component]]", "[grid]", "[options]"))
    tables = data.get("component")
    if not isinstance(tables, list) or not tables:
        raise ConfigError(f"{source}: the bed needs at least one [[component]] table")
    comps = [_component(f"{source}: [[component]] {k + 1}", t) for k, t in enumerate(tables)]
    try:
        _check_components(comps)
    except ValueError as exc:
        raise ConfigError(f"{source}: [[component]]: {exc}") from None
    grid = {}
    grid_data = data.get("grid", {})
    if not isinstance(grid_data, dict):
        raise ConfigError(f"{source}: [grid] must be a table of field = values")
    for key, value in grid_data.items():
        where = f"{source}: [grid] {key}"
        if key not in BED_GRID_FIELDS:
            raise ConfigError(f"{where}: cannot be swept in a bed; allowed: "
                              f"{', '.join(BED_GRID_FIELDS)}")
        axis = _axis(where, value, key) if key != "fraction" else _axis(where, value, "eps")
        try:
            grid.update(_grid_arrays({key: axis}))
        except ValueError as exc:
            raise ConfigError(f"{where}: {exc}") from None
    scene = parse_scene(data.get("scene", {}), source, grid)
    found = swept_without_effect(scene.values(), grid)
    if found:
        raise ConfigError(f"{source}: [grid] {found[0]}: {found[1]}")
    found = typed_unread(scene, [k for k in data.get("scene", {}) if k not in grid])
    if found:
        raise ConfigError(f"{source}: [scene] {found[0]}: {found[1]}")
    # The scene's findings that still hold at the values the grid sweeps (the bed's own
    # findings, its coating on each component, are bed_propensity's and bed_sweep's).
    base = {k: v for k, v in scene.values().items() if k not in BED_OWN}
    warn_scene_findings(scene, source, scene_findings({**base, **grid}))
    opts = dict(data.get("options", {}))
    unknown = sorted(set(opts) - {"nodes", "directions", "mix"})
    if unknown:
        raise ConfigError(f"{source}: [options] {unknown[0]}: unknown; allowed: nodes, "
                          "directions, mix")
    for key, default, hi in (("nodes", 16, 10_000), ("directions", 8, 64)):
        v = opts.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= hi:
            raise ConfigError(f"{source}: [options] {key}: must be an integer 1-{hi}, "
                              f"got {v!r}")
        opts[key] = v
    mix = opts.get("mix")
    if "fraction" in grid and mix is None:
        raise ConfigError(f"{source}: [grid] fraction needs [options] mix = the component "
                          "whose mass fraction it sets")
    if mix is not None:
        try:
            _mix_index(comps, mix)
        except ValueError as exc:
            raise ConfigError(f"{source}: [options] mix: {exc}") from None
    if "fraction" in grid:
        try:
            check_fraction_axis(comps)
        except ValueError as exc:
            raise ConfigError(f"{source}: [grid] {exc}") from None
    opts.setdefault("mix", None)
    return BedConfig(scene, comps, grid, opts)


def load_bed_config(path) -> BedConfig:
    """Read and validate a bed configuration file (TOML)."""
    return parse_bed_config(read_toml(path), str(path))
