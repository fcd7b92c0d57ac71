"""Operating maps: sweeps over scenes, resumable stores.

The impact-speed distributions live one layer below the scene, in :mod:`agglomtool.bed.speeds`
(re-exported here for compatibility). The sweep (:mod:`.grid`) uses the scene, so the sweep
functions are imported on first use.
"""

from ..bed.speeds import SPEED_FAMILIES, SpeedModel, sticking_probability

__all__ = ["SPEED_FAMILIES", "SpeedModel", "build", "estimate_sweep", "open_store",
           "sticking_probability", "sweep", "write_map"]


def __getattr__(name):
    if name in ("sweep", "build"):
        from importlib import import_module

        return getattr(import_module(f"{__name__}.grid"), name)
    if name == "estimate_sweep":
        from .estimate import estimate_sweep

        return estimate_sweep
    if name == "write_map":
        from .export import write_map

        return write_map
    if name == "open_store":
        from .store import open_store

        return open_store
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
