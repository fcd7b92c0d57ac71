"""agglomtool: will wet or ash-coated particles in a fluidized bed stick together?

The collision model is the generalized analytical energy balance of Shabanian, Duchesne,
Syamlal and Runstedtler (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397.
"""

from . import examples, materials
from ._version import __version__
from .api import MODES, CollisionResult, collide, critical_impact_speed
from .collision.outcome import Path, Stage
from .inputs import Bed, Gas, Liquid, Particle
from .maps.grid import sweep
from .properties import gas_properties, umf
from .scene import Scene
from .uncertainty import LogNormal, Normal, Uniform, monte_carlo, sobol_indices

__all__ = [
    "Bed",
    "LogNormal",
    "Normal",
    "Scene",
    "Uniform",
    "monte_carlo",
    "sobol_indices",
    "sweep",
    "CollisionResult",
    "Gas",
    "Liquid",
    "MODES",
    "Particle",
    "Path",
    "Stage",
    "__version__",
    "collide",
    "critical_impact_speed",
    "examples",
    "gas_properties",
    "materials",
    "umf",
]
