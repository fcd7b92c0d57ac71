"""The bed layer: impact-speed distributions, mixtures of particles and collision rates.

Below the scene in the layering (``collision`` <- ``pair``/``api`` <- ``bed.speeds`` <- ``scene``
<- ``bed`` mixtures <- ``maps``): :mod:`.speeds` is imported by :mod:`agglomtool.scene`, so it
must not import the scene; the mixture functions, which do, are imported on first use.
"""

from importlib import import_module

from .speeds import SPEED_FAMILIES, SpeedModel, sticking_probability

__all__ = ["SPEED_FAMILIES", "SpeedModel", "sticking_probability", "Component",
           "bed_propensity", "bed_sweep", "export_efficiency", "read_efficiency"]

_LAZY = {"Component": ".mixture", "bed_propensity": ".propensity", "bed_sweep": ".propensity",
         "export_efficiency": ".export", "read_efficiency": ".export"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
