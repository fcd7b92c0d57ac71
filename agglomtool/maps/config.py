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

import tomllib
import warnings
from pathlib import Path

import numpy as np

from .._fields import FIELD_META
from ..plausibility import PlausibilityWarning, scene_findings
from ..scene import CATEGORICAL_FIELDS, Scene, field_names
from ..units import to_si

__all__ = ["ConfigError", "MapConfig", "load_config", "parse_config", "parse_scene",
           "warn_scene_findings", "read_toml"]


class ConfigError(ValueError):
    """A map configuration is malformed; the message names the key."""


class MapConfig:
    """A parsed configuration: ``scene`` (Scene), ``grid`` (dict), ``options`` (dict)."""

    def __init__(self, scene: Scene, grid: dict, options: dict):
        self.scene, self.grid, self.options = scene, grid, options


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


def _axis(where: str, value, key: str = ""):
    numeric = key in FIELD_META
    if isinstance(value, list):
        if not value:
            raise ConfigError(f"{where}: the list of values is empty")
        if numeric:
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


def parse_config(data: dict, source: str = "config") -> MapConfig:
    """Build a :class:`MapConfig` from a parsed TOML mapping."""
    unknown = sorted(set(data) - {"scene", "grid", "options"})
    if unknown:
        raise ConfigError(f"{source}: unknown table [{unknown[0]}]; allowed: [scene], [grid], "
                          "[options]")
    fields = field_names()
    scene = parse_scene(data.get("scene", {}), source)
    grid_data = data.get("grid", {})
    if not isinstance(grid_data, dict) or not grid_data:
        raise ConfigError(f"{source}: [grid] must hold at least one field = values")
    grid = {}
    for key, value in grid_data.items():
        where = f"{source}: [grid] {key}"
        if key not in fields:
            raise ConfigError(f"{where}: not a Scene field; fields: {', '.join(fields)}")
        axis = _axis(where, value, key)
        if key in CATEGORICAL_FIELDS and not isinstance(axis, list):
            raise ConfigError(f"{where}: {key} takes names, e.g. [\"silica-sand\"]")
        if key not in CATEGORICAL_FIELDS and isinstance(axis, list):
            raise ConfigError(f"{where}: {key} takes numbers")
        grid[key] = axis
    opts = dict(data.get("options", {}))
    unknown = sorted(set(opts) - {"nodes", "chunks"})
    if unknown:
        raise ConfigError(f"{source}: [options] {unknown[0]}: unknown; allowed: nodes, chunks")
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
    from .grid import GridError, _grid_values, grid_findings

    try:
        axes = _grid_values(scene, grid, plausibility=False)  # the sweep says those, once
    except GridError as exc:
        where = f"[grid] {exc.field}" if exc.field else "[scene]"
        raise ConfigError(f"{source}: {where}: {exc}") from None
    warn_scene_findings(scene, source, grid_findings(scene.values(), axes))
    return MapConfig(scene, grid, {"nodes": nodes, "chunks": chunks})


def parse_scene(scene_data, source: str = "config") -> Scene:
    """The ``[scene]`` table as a :class:`Scene`; an error names the key. Its plausibility
    findings are not said here: a field that a grid sweeps has no scene value to judge
    (see :func:`warn_scene_findings`)."""
    fields = field_names()
    if not isinstance(scene_data, dict):
        raise ConfigError(f"{source}: [scene] must be a table of field = value")
    for key, value in scene_data.items():
        if key not in fields:
            raise ConfigError(f"{source}: [scene] {key}: not a Scene field; fields: "
                              f"{', '.join(fields)}")
        if isinstance(value, list | dict):
            raise ConfigError(f"{source}: [scene] {key}: must be a single value; put ranges "
                              "in [grid]")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            return Scene(**scene_data)
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{source}: [scene]: {exc}") from None


def warn_scene_findings(scene: Scene, source: str, swept: list) -> None:
    """Say the plausibility findings of the ``[scene]`` that still hold at the values swept
    (``swept``: the findings of the scene over its grid), naming the file and the table;
    the others are the sweep's to say."""
    for finding in scene_findings(scene.values()):
        if finding in swept:
            warnings.warn(f"{source}: [scene]: {finding[1]}", PlausibilityWarning,
                          stacklevel=3)


def load_config(path) -> MapConfig:
    """Read and validate a map configuration file (TOML)."""
    return parse_config(read_toml(path), str(path))


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
