"""Map configurations in TOML: a scene, a grid and options.

Example::

    [scene]                      # any Scene field; numbers are SI (T in K, h0 in m),
    liquid = "k-silicate-ash-melt"   # or quantities with units as strings
    d_i = "500 um"

    [grid]                       # one dimension per key, in this order
    T = { start = "800 degC", stop = "1200 degC", num = 41 }   # evenly spaced
    h0 = { start = 0.12e-6, stop = 10e-6, num = 41, log = true } # evenly spaced in log
    U_Umf = [2.0, 4.0, 8.0]                                     # explicit values
    solid_j = ["silica-sand", "ilmenite"]                       # names

    [options]
    nodes = 16                   # quadrature nodes of the speed distribution
    chunks = "auto"              # or a number of points per block

Every error names the file, the table and the key.
"""

from __future__ import annotations

from .._config import (
    ConfigError,
    _axis,
    check_field_key,
    check_tables,
    parse_scene,
    read_toml,
    warn_scene_findings,
)
from ..scene import CATEGORICAL_FIELDS, Scene

__all__ = ["ConfigError", "MapConfig", "load_config", "parse_config", "parse_scene",
           "warn_scene_findings", "read_toml"]


class MapConfig:
    """A parsed configuration: ``scene`` (Scene), ``grid`` (dict), ``options`` (dict), and
    ``uncertain`` (the ``[uncertain]`` table as ``sweep(uncertain=...)`` takes it, or
    ``None``: a robust map when given)."""

    def __init__(self, scene: Scene, grid: dict, options: dict, uncertain=None):
        self.scene, self.grid, self.options = scene, grid, options
        self.uncertain = uncertain


def parse_config(data: dict, source: str = "config") -> MapConfig:
    """Build a :class:`MapConfig` from a parsed TOML mapping."""
    check_tables(data, source, ("[scene]", "[grid]", "[uncertain]", "[options]"))
    grid_data = data.get("grid", {})
    if not isinstance(grid_data, dict) or not grid_data:
        raise ConfigError(f"{source}: [grid] must hold at least one field = values")
    grid = {}
    for key, value in grid_data.items():
        check_field_key(f"{source}: [grid]", key)
        where = f"{source}: [grid] {key}"
        axis = _axis(where, value, key)
        if key in CATEGORICAL_FIELDS and not isinstance(axis, list):
            raise ConfigError(f"{where}: {key} takes names, e.g. [\"silica-sand\"]")
        if key not in CATEGORICAL_FIELDS and isinstance(axis, list):
            raise ConfigError(f"{where}: {key} takes numbers")
        grid[key] = axis
    scene = parse_scene(data.get("scene", {}), source, grid)
    opts = dict(data.get("options", {}))
    robust = ("samples", "threshold", "seed")
    allowed = {"nodes", "chunks", *(robust if "uncertain" in data else ())}
    unknown = sorted(set(opts) - allowed)
    if unknown:
        hint = (f" ({unknown[0]} is for a robust map: add an [uncertain] table)"
                if unknown[0] in robust else "")
        raise ConfigError(f"{source}: [options] {unknown[0]}: unknown; allowed: "
                          f"{', '.join(sorted(allowed))}{hint}")
    nodes = opts.get("nodes", 16)
    if not isinstance(nodes, int) or isinstance(nodes, bool) or nodes < 1:
        raise ConfigError(f"{source}: [options] nodes: must be an integer >= 1, got {nodes!r}")
    chunks = opts.get("chunks", "auto")
    if chunks != "auto" and (isinstance(chunks, bool) or not isinstance(chunks, int)
                             or chunks < 1):
        raise ConfigError(f"{source}: [options] chunks: must be \"auto\" or an integer >= 1, "
                          f"got {chunks!r}")
    # The grid is validated now, once, at the values it sweeps (not at the scene's values
    # of the fields it sweeps), so that an error names the key.
    from .layout import GridError, _grid_values, grid_findings

    uncertain = None
    if "uncertain" in data:
        from ..uncertainty.config import parse_uncertain

        uncertain = parse_uncertain(data["uncertain"], source)
    from ..uncertainty.scene_mc import drawn_speeds

    try:
        axes = _grid_values(scene, grid, plausibility=False,  # the sweep says those, once
                            drawn=drawn_speeds(scene, uncertain))
    except GridError as exc:
        where = f"[grid] {exc.field}" if exc.field else "[scene]"
        raise ConfigError(f"{source}: {where}: {exc}") from None
    from ..scene import typed_unread

    typed = [k for k in data.get("scene", {}) if k not in grid]
    found = typed_unread(scene, typed, grid.get("speed", ()), drawn_speeds(scene, uncertain))
    if found:
        raise ConfigError(f"{source}: [scene] {found[0]}: {found[1]}")
    warn_scene_findings(scene, source, grid_findings(scene.values(), axes))
    options = {"nodes": nodes, "chunks": chunks}
    if uncertain is not None:
        swept = sorted(set(uncertain if isinstance(uncertain, dict) else ()) & set(grid))
        if swept:
            raise ConfigError(f"{source}: [uncertain] {swept[0]}: it is swept in [grid]; "
                              "sweep it or make it uncertain, not both")
        samples, threshold, seed = (opts.get("samples", 256), opts.get("threshold", 0.5),
                                    opts.get("seed", 0))
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
            raise ConfigError(f"{source}: [options] samples: must be an integer >= 2, got "
                              f"{samples!r}")
        if (isinstance(threshold, bool) or not isinstance(threshold, int | float)
                or not 0.0 <= threshold < 1.0):
            raise ConfigError(f"{source}: [options] threshold: must be a number in [0, 1), "
                              f"got {threshold!r}")
        if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
            raise ConfigError(f"{source}: [options] seed: must be an integer >= 0, got "
                              f"{seed!r}")
        options.update(samples=samples, threshold=float(threshold), seed=seed)
    return MapConfig(scene, grid, options, uncertain)


def load_config(path) -> MapConfig:
    """Read and validate a map configuration file (TOML)."""
    return parse_config(read_toml(path), str(path))
