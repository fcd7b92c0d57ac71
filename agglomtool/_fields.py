"""The fields of a :class:`~agglomtool.Scene`: names, units, defaults and allowed names.

Kept free of heavy imports (no numpy kernels, CoolProp, xarray) so that the command line can
state its options, true defaults and allowed names in well under a second. The modules that
own each list (the tier registry, the speed models, the drag and ``U_mf`` correlations) are
checked against these names by the tests.
"""

from __future__ import annotations

from typing import TypedDict

__all__ = ["FIELD_META", "DEFAULTS", "CATEGORICAL_FIELDS", "NUMERIC_FIELDS", "CHOICES",
           "U_CEILING", "DEFAULT_MODE", "FIELD_RANGES", "CORE_RANGES", "SPEED_LAW_NEEDS",
           "short_unit"]

#: The model tier used unless one is asked for: the frame-consistent closed forms. Of the
#: tiers that cost about as much as the paper's own ("paper", "relative"), it is the most
#: accurate (max e_w error 0.055 against 0.33, u0* within 1.2 % against 22 % on the fidelity
#: scenes); "auto" is more accurate still (0.004) but measured 50-58x (water) and 2.0x (a
#: viscous melt) the time of "relative" on operating maps (benchmarks/bench_tiers_map.py,
#: 2026-11-26, load 0.9-1.1, its propensity bracketed in one compiled pass: the time is its
#: kernel's, integrating at the speeds the propensity needs), beyond the 3x this default
#: may cost.
#: The paper's model stays one word away: mode="paper".
DEFAULT_MODE = "relative"

#: Default ceiling on the critical impact speed [m/s]: of the order of the fastest impacts
#: in a bubbling bed (particles thrown by bursting bubbles move at a few m/s). A u0* above it
#: would come from physics extrapolated far beyond any bed, so it is reported as ``inf``.
U_CEILING = 10.0

#: Fields holding names (swept as categories, one value per grid block).
CATEGORICAL_FIELDS = ("gas", "solid_i", "solid_j", "liquid", "speed", "mode", "drag_slip",
                      "umf_method")
#: Fields holding numbers (swept as numeric coordinates).
NUMERIC_FIELDS = ("T", "P", "U", "U_Umf", "eps", "U_e_Umf", "d_i", "d_j", "h0", "h0_j",
                  "ha_i", "ha_j", "e", "theta_deg", "beta_deg", "u0", "sigma_ln",
                  "granular_temperature", "fluctuation_ratio", "bed_height", "column_diameter",
                  "orifice_area", "height", "wake_fraction", "u_ceiling")

#: Units and long names of the numeric fields (pint-parsable units).
FIELD_META = {
    "T": ("K", "bed temperature"),
    "P": ("Pa", "absolute pressure"),
    "U": ("m/s", "superficial gas velocity"),
    "U_Umf": ("dimensionless", "fluidization number U/U_mf"),
    "eps": ("dimensionless", "local voidage around the colliding pair"),
    "U_e_Umf": ("dimensionless", "emulsion gas velocity over U_mf (drag)"),
    "d_i": ("m", "solid diameter of particle i"),
    "d_j": ("m", "solid diameter of particle j"),
    "h0": ("m", "coating thickness of particle i"),
    "h0_j": ("m", "coating thickness of particle j"),
    "ha_i": ("m", "asperity height of particle i"),
    "ha_j": ("m", "asperity height of particle j"),
    "e": ("dimensionless", "dry restitution coefficient of the pair"),
    "theta_deg": ("degree", "contact angle of the coating liquid"),
    "beta_deg": ("degree", "collision angle from the horizontal"),
    "u0": ("m/s", "impact speed (fixed value, or lognormal median)"),
    "sigma_ln": ("dimensionless", "lognormal shape of the impact-speed distribution"),
    "granular_temperature": ("m**2/s**2", "granular temperature (Maxwellian speeds)"),
    "fluctuation_ratio": ("dimensionless", "r.m.s. particle velocity over U - U_mf"),
    "bed_height": ("m", "static (settled) bed height"),
    "column_diameter": ("m", "column diameter"),
    "orifice_area": ("m**2", "distributor area per orifice (0: porous plate)"),
    "height": ("m", "height of interest above the distributor"),
    "wake_fraction": ("dimensionless", "bubble wake volume over bubble volume"),
    "u_ceiling": ("m/s", "u0* ceiling: above it the pair sticks at every bed speed"),
}

#: Upper ends of the physical ranges, far beyond any fluidized bed and far below where the
#: model's arithmetic overflows (a value of 1e300 gave e_w = 0, or NaN, silently). Above
#: them a value is refused (a ValueError): it is a slip, never a bed. Within them the
#: plausibility checks (:mod:`agglomtool.plausibility`) still warn about what no bed has.
#: A particle, its coating or asperities, a bed, a column of more than 1 km [m] (a 5 m
#: coating, a 500 m particle are slips the plausibility checks name, with a warning).
MAX_LENGTH = 1e3
#: A density above 1e5 kg/m3 (the densest element, osmium, has 2.26e4) [kg/m3].
MAX_DENSITY = 1e5
#: A speed above 1 km/s (faster than sound in any bed's gas) [m/s].
MAX_SPEED = 1e3
#: A temperature above 1e4 K (the property models end near 2000 K) [K].
MAX_T = 1e4
#: A pressure above 1e9 Pa (10 kbar) [Pa].
MAX_P = 1e9

#: Most quadrature nodes of the impact-speed distribution (16 is the default; more than a
#: thousand only multiplies the work).
MAX_NODES = 1024

#: Valid (physical) range of every numeric Scene field: ``(lo, hi, lo_open, hi_open)``; the
#: messages of a ``ValueError`` state it.
FIELD_RANGES = {
    "T": (0.0, MAX_T, True, False), "P": (0.0, MAX_P, True, False),
    "U": (0.0, MAX_SPEED, False, False), "U_Umf": (0.0, 1e4, True, False),
    "eps": (0.0, 1.0, True, True), "U_e_Umf": (0.0, 1e4, False, False),
    "d_i": (0.0, MAX_LENGTH, True, False),
    "d_j": (0.0, MAX_LENGTH, True, False),
    "h0": (0.0, MAX_LENGTH, False, False),
    "h0_j": (0.0, MAX_LENGTH, False, False),
    "ha_i": (0.0, MAX_LENGTH, False, False),
    "ha_j": (0.0, MAX_LENGTH, False, False),
    "e": (0.0, 1.0, False, False), "theta_deg": (0.0, 90.0, False, True),
    "beta_deg": (-90.0, 90.0, False, False), "u0": (0.0, MAX_SPEED, True, False),
    "sigma_ln": (0.0, 10.0, True, False),
    "granular_temperature": (0.0, MAX_SPEED**2, True, False),
    "fluctuation_ratio": (0.0, 1e3, True, False), "u_ceiling": (0.0, MAX_SPEED, True, False),
    "bed_height": (0.0, MAX_LENGTH, True, False),
    "column_diameter": (0.0, MAX_LENGTH, True, False),
    "orifice_area": (0.0, MAX_LENGTH**2, False, False),
    "height": (0.0, MAX_LENGTH, True, False),
    "wake_fraction": (0.0, 10.0, True, False),
}

#: The collision core's lengths end at 1e10 m (a star): a partner that large is the plate
#: limit (use ``Particle.plate()``); the model's limits are tested up to 1.7e9 m [m].
MAX_CORE_LENGTH = 1e10
#: The core's speeds end at 1e12 m/s [m/s]: the model is classical, but its own
#: consistency is tested where its answers lie, and the critical speed of a 1e6 Pa s bridge
#: on a fine particle exceeds the speed of light (8e8 m/s); 1e300 overflows its energies.
MAX_CORE_SPEED = 1e12

#: Valid range of the collision core's inputs (:mod:`agglomtool.inputs`, the arguments of
#: :func:`agglomtool.collide`): ``(lo, hi, lo_open, hi_open, unit)``. A plate's ``inf``
#: (``Particle.d``, ``Particle.rho``) is allowed besides. Wider than a Scene's: the core is
#: the model, whose limits (a partner a million times larger, speeds 1e9 times the
#: critical one) the tests hold it to; a bed's own bounds are the Scene's.
CORE_RANGES = {
    "Particle.d": (0.0, MAX_CORE_LENGTH, True, False, "m"),
    "Particle.rho": (0.0, MAX_DENSITY, True, False, "kg/m3"),
    "Particle.h0": (0.0, MAX_CORE_LENGTH, False, False, "m"),
    "Particle.ha": (0.0, MAX_CORE_LENGTH, False, False, "m"),
    # a viscosity far above a glass's at its transition (1e12 Pa s): a solid, not a bridge
    "Liquid.mu": (0.0, 1e30, True, False, "Pa s"),
    # molten metals reach 2 N/m
    "Liquid.gamma": (0.0, 10.0, True, False, "N/m"),
    "Liquid.rho": (0.0, MAX_DENSITY, True, False, "kg/m3"),
    "Liquid.theta_deg": (0.0, 90.0, False, True, "deg"),
    # gases have 1e-5 to 1e-4 Pa s; 1 Pa s is a syrup
    "Gas.mu": (0.0, 1.0, True, False, "Pa s"),
    "Gas.rho": (0.0, MAX_DENSITY, True, False, "kg/m3"),
    "Bed.eps": (0.0, 1.0, True, True, "-"),
    "Bed.U": (0.0, MAX_CORE_SPEED, False, False, "m/s"),
    "collide.u0": (-MAX_CORE_SPEED, MAX_CORE_SPEED, False, False, "m/s"),
    "collide.u0_j": (-MAX_CORE_SPEED, MAX_CORE_SPEED, False, False, "m/s"),
    # the collision axis's angle, periodic: ten turns either way (a Scene's is in
    # [-90, 90]); beyond, a slip
    "collide.beta_deg": (-3600.0, 3600.0, False, False, "deg"),
    "collide.e": (0.0, 1.0, False, False, "-"),
}


def short_unit(name: str) -> str:
    """The unit of numeric field ``name`` as messages and help texts print it: ``"deg"``,
    ``"m2/s2"``, and ``""`` for a dimensionless field."""
    unit = FIELD_META[name][0]
    return {"dimensionless": "", "degree": "deg", "m**2/s**2": "m2/s2",
            "m**2": "m2"}.get(unit, unit)


class SceneDefaults(TypedDict):
    """The type of each Scene field's default (the Scene's annotations hold the same)."""

    T: float
    P: float
    gas: str
    U: float | None
    U_Umf: float
    eps: float
    U_e_Umf: float
    solid_i: str
    d_i: float
    solid_j: str | None
    d_j: float | None
    liquid: str
    h0: float
    h0_j: float | None
    ha_i: float | None
    ha_j: float | None
    e: float | None
    theta_deg: float | None
    beta_deg: float
    u0: float | None
    speed: str | None
    sigma_ln: float
    granular_temperature: float | None
    fluctuation_ratio: float
    bed_height: float
    column_diameter: float
    orifice_area: float
    height: float | None
    wake_fraction: float
    mode: str
    body_forces: bool
    drag_slip: str
    umf_method: str
    u_ceiling: float


#: Default of every Scene field; ``None`` means "derived" (see the Scene's docstring).
DEFAULTS: SceneDefaults = {
    "T": 1073.15, "P": 101325.0, "gas": "air", "U": None, "U_Umf": 3.0, "eps": 0.55,
    "U_e_Umf": 1.1, "solid_i": "silica-sand", "d_i": 500e-6, "solid_j": None, "d_j": None,
    "liquid": "hypothetical-slag", "h0": 0.2e-6, "h0_j": None, "ha_i": None, "ha_j": None,
    "e": None, "theta_deg": None, "beta_deg": 0.0, "u0": None, "speed": None,
    "sigma_ln": 0.5, "granular_temperature": None, "fluctuation_ratio": 1.0,
    "bed_height": 0.3, "column_diameter": 0.3, "orifice_area": 0.0, "height": None,
    "wake_fraction": 0.25,
    "mode": DEFAULT_MODE,
    "body_forces": True, "drag_slip": "emulsion", "umf_method": "wen-yu",
    "u_ceiling": U_CEILING,
}

#: Allowed names of the categorical fields that are not database entries.
CHOICES = {
    "speed": ("fixed", "lognormal", "maxwellian", "excess-gas", "bubble-darton",
              "bubble-mori-wen", "collisional-balance"),
    "mode": ("stokes", "paper", "relative", "ode", "ode_selfconsistent", "auto"),
    "drag_slip": ("emulsion", "particle"),
    "umf_method": ("wen-yu", "richardson", "saxena-vogel", "babu", "grace", "chitester"),
}

#: The speed laws given by their own parameter, and the field each needs (no default).
SPEED_LAW_NEEDS = {"fixed": "u0", "lognormal": "u0", "maxwellian": "granular_temperature"}

#: What a ``None`` default means, for help texts.
DERIVED = {
    "U": "U_Umf x U_mf",
    "solid_j": "solid_i",
    "d_j": "d_i",
    "h0_j": "h0",
    "ha_i": "the solid's database value",
    "ha_j": "the solid's database value",
    "e": "the mean of the two solids' database values",
    "theta_deg": "the liquid's database value",
    "u0": "none: the speed distribution is then estimated (see speed)",
    "speed": "fixed with u0, maxwellian with granular_temperature, else excess-gas",
    "granular_temperature": "none",
    "height": "half the bed height",
}
