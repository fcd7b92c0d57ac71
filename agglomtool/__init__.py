"""agglomtool: will wet or ash-coated particles in a fluidized bed stick together?

The collision model is the generalized analytical energy balance of Shabanian, Duchesne,
Syamlal and Runstedtler (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397.

The public names are imported on first use (PEP 562), so that ``import agglomtool`` and the
command line's ``--help`` do not pay for CoolProp, Numba, xarray and dask up front.
"""

from importlib import import_module

from ._version import __version__ as __version__

#: public name -> module that defines it
_LAZY = {
    "Bed": ".inputs", "Gas": ".inputs", "Liquid": ".inputs", "Particle": ".inputs",
    "MODES": ".api", "CollisionResult": ".api", "collide": ".api",
    "critical_impact_speed": ".api",
    "Path": ".collision.outcome", "Stage": ".collision.outcome",
    "sweep": ".maps.grid", "write_map": ".maps.export",
    "gas_properties": ".properties", "umf": ".properties",
    "Scene": ".scene", "impact_speed_methods": ".scene",
    "PlausibilityWarning": ".plausibility",
    "LogNormal": ".uncertainty", "Normal": ".uncertainty", "Uniform": ".uncertainty",
    "monte_carlo": ".uncertainty", "sobol_indices": ".uncertainty", "compare": ".uncertainty",
    "Component": ".bed.mixture", "bed_propensity": ".bed.propensity",
    "bed_sweep": ".bed.propensity",
}
_SUBMODULES = ("bed", "examples", "materials", "maps", "plots", "properties", "collision",
               "uncertainty")

__all__ = sorted([*_LAZY, "examples", "materials", "__version__"])


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name], __name__), name)
    elif name in _SUBMODULES:
        value = import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY) | set(_SUBMODULES))
