"""Property layer: gas, liquid and fluidization correlations, one function per correlation.

Names are imported on first use (PEP 562): the materials loader and the command line use
parts of this package without paying for CoolProp.
"""

from importlib import import_module

#: public name -> module of this package that defines it
_LAZY = {
    "drag_force_gidaspow": "drag",
    "UMF_C1_C2": "fluidization",
    "umf": "fluidization",
    "umf_ergun": "fluidization",
    "umf_methods": "fluidization",
    "umf_wen_yu": "fluidization",
    "gas_properties": "gas",
    "mixture_density_dalton": "gas",
    "viscosity_wilke": "gas",
    "VISCOSITY_MODELS": "melt",
    "choose_viscosity_model": "melt",
    "fixed_liquid": "melt",
    "melt_liquid": "melt",
    "density_mills_keene": "slag_surface",
    "surface_tension_kucuk": "slag_surface",
    "surface_tension_mills": "slag_surface",
    "viscosity_giordano_russell_dingwell": "slag_viscosity",
    "viscosity_riboud": "slag_viscosity",
    "viscosity_urbain_mills": "slag_viscosity",
    "water_density_wagner_pruss": "water",
    "water_liquid": "water",
    "water_surface_tension_iapws": "water",
    "water_viscosity_huber": "water",
}

__all__ = sorted(_LAZY)


def __getattr__(name):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(import_module(f".{_LAZY[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
