"""Property layer: gas, liquid and fluidization correlations, one function per correlation."""

from .drag import drag_force_gidaspow
from .fluidization import UMF_C1_C2, umf, umf_ergun, umf_methods, umf_wen_yu
from .gas import gas_properties, mixture_density_dalton, viscosity_wilke
from .melt import VISCOSITY_MODELS, choose_viscosity_model, fixed_liquid, melt_liquid
from .slag_surface import density_mills_keene, surface_tension_kucuk, surface_tension_mills
from .slag_viscosity import (
    viscosity_giordano_russell_dingwell,
    viscosity_riboud,
    viscosity_urbain_mills,
)
from .water import (
    water_density_wagner_pruss,
    water_liquid,
    water_surface_tension_iapws,
    water_viscosity_huber,
)

__all__ = [
    "UMF_C1_C2",
    "VISCOSITY_MODELS",
    "choose_viscosity_model",
    "density_mills_keene",
    "drag_force_gidaspow",
    "fixed_liquid",
    "gas_properties",
    "melt_liquid",
    "mixture_density_dalton",
    "surface_tension_kucuk",
    "surface_tension_mills",
    "umf",
    "umf_ergun",
    "umf_methods",
    "umf_wen_yu",
    "viscosity_giordano_russell_dingwell",
    "viscosity_riboud",
    "viscosity_urbain_mills",
    "viscosity_wilke",
    "water_density_wagner_pruss",
    "water_liquid",
    "water_surface_tension_iapws",
    "water_viscosity_huber",
]
