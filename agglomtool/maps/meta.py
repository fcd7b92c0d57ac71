"""Units (pint-parsable) and long names of every variable a sweep writes."""

from __future__ import annotations

import numpy as np

from ..collision.outcome import Stage
from ..scene import CA_VISCOUS, FIELD_META, U_STAR_FLAGS

__all__ = ["VARIABLE_META", "FIELD_META", "variable_attrs", "field_attrs"]

#: name -> (units, long_name, description)
VARIABLE_META = {
    "mu_g": ("Pa*s", "gas viscosity", "gas_properties(T, P, gas)"),
    "rho_g": ("kg/m**3", "gas density", "gas_properties(T, P, gas)"),
    "mu_l": ("Pa*s", "coating liquid viscosity", "materials.liquid(liquid, T, P)"),
    "gamma_l": ("N/m", "coating liquid surface tension", "materials.liquid(liquid, T, P)"),
    "rho_l": ("kg/m**3", "coating liquid density", "materials.liquid(liquid, T, P)"),
    "Umf": ("m/s", "minimum fluidization velocity",
            "larger U_mf of the two wet particles (umf_method)"),
    "U_e": ("m/s", "emulsion gas velocity used in the drag", "U_e_Umf * Umf"),
    "U": ("m/s", "superficial gas velocity", "U, or U_Umf * Umf"),
    "u_star": ("m/s", "critical impact speed u0*",
               "smallest head-on impact speed at which the pair rebounds; inf: the pair "
               "sticks at every speed up to the ceiling u_ceiling (u_star_flag = 2); 0: no "
               "bridge forms (u_star_flag = 1)"),
    "u_star_flag": ("dimensionless", "what u0* means at this point",
                    "; ".join(f"{k}: {v[1]}" for k, v in U_STAR_FLAGS.items())),
    "Ca_star": ("dimensionless", "capillary number at u0*", "mu_l * 2 u0* / gamma_l"),
    "regime": ("dimensionless", "regime at u0* (0 capillary-, 1 viscous-limited)",
               f"viscous-limited where Ca_star > {CA_VISCOUS:g}"),
    "u_typical": ("m/s", "typical (median) impact speed", "median of the speed distribution"),
    "St": ("dimensionless", "viscous Stokes number at the typical speed",
           "m_r 2 u_typical / (1.5 pi mu_l r**2)"),
    "e_w": ("dimensionless", "wet restitution coefficient at the typical speed",
            "0 where the pair sticks"),
    "agglomerated": ("dimensionless", "sticks at the typical speed", "e_w == 0"),
    "stage": ("dimensionless", "stage where the outcome at the typical speed was decided",
              "agglomtool.Stage code"),
    "propensity": ("dimensionless", "agglomeration propensity",
                   "probability that a collision sticks over the impact-speed distribution"),
    "margin": ("dimensionless", "speed margin u_typical / u0*",
               "< 1: typical collisions are slower than the critical speed"),
}


def variable_attrs(name: str) -> dict:
    """``units``, ``long_name`` and ``description`` of output variable ``name``."""
    units, long_name, desc = VARIABLE_META[name]
    attrs = {"units": units, "long_name": long_name, "description": desc}
    if name == "stage":
        attrs["flag_values"] = np.array([s.value for s in Stage], dtype=np.int8)
        attrs["flag_meanings"] = " ".join(s.name.lower() for s in Stage)
    if name == "u_star_flag":
        attrs["flag_values"] = np.array(list(U_STAR_FLAGS), dtype=np.int8)
        attrs["flag_meanings"] = " ".join(v[0] for v in U_STAR_FLAGS.values())
    if name == "regime":
        attrs["flag_values"] = np.array([0, 1], dtype=np.int8)
        attrs["flag_meanings"] = "capillary_limited viscous_limited"
    return attrs


def field_attrs(name: str) -> dict:
    """``units`` and ``long_name`` of a swept Scene field (a coordinate)."""
    if name in FIELD_META:
        units, long_name = FIELD_META[name]
    else:  # categorical fields: names
        units, long_name = "dimensionless", f"{name.replace('_', ' ')} (name)"
    return {"units": units, "long_name": long_name}
