"""Plausibility: input that is valid for the model but looks like a slip.

Validity (a ``ValueError``) is what the model cannot evaluate; plausibility is what it can
evaluate but no bed designer means: a coating of 5 m where 5 um was meant, a 500 m particle,
a pressure of 1.5 Pa. Each check warns with a :class:`PlausibilityWarning` naming the field,
the value and why it looks wrong. The category is filterable, and can be made an error::

    import warnings, agglomtool as at
    warnings.simplefilter("error", at.PlausibilityWarning)   # or "ignore"

(on the command line: ``agglomtool --strict ...``).
"""

from __future__ import annotations

import warnings

import numpy as np

from ._validate import PlausibilityWarning

__all__ = ["PlausibilityWarning", "scene_findings", "component_findings", "bed_findings",
           "warn_findings", "ASPERITY_RANGE", "COATING_FRACTION", "PRESSURE_RANGE",
           "MELT_T_MIN", "BED_OWN"]

#: Asperity heights outside this range [m] are implausible for bed solids.
ASPERITY_RANGE = (1e-9, 10e-6)
#: A coating thicker than this fraction of the particle diameter is not a film.
COATING_FRACTION = 0.1
#: Absolute pressures outside this range [Pa] are implausible for a fluidized bed.
PRESSURE_RANGE = (1e4, 1e7)
#: Water's triple-point pressure [Pa]: no liquid water below it.
_WATER_P_TRIPLE = 611.655
#: A melt (an oxide melt of the materials database: ash, slag) below this temperature [K]
#: (600 degC) is not liquid: the lowest eutectics of the alkali silicates are near 700 degC.
#: Below it a temperature in degC typed as K is the likely slip.
MELT_T_MIN = 873.15


def _extreme(values: dict, name: str, how):
    v = values.get(name)
    if v is None:
        return None
    arr = np.asarray(v, dtype=float)
    return float(how(arr)) if arr.size else None


def _coating(h: str, hmax, dmin, where: str = ""):
    """The finding for a coating ``hmax`` [m] thicker than a film on diameter ``dmin``."""
    if hmax is None or dmin is None or not hmax > COATING_FRACTION * dmin * (1.0 + 1e-9):
        return None  # (the tolerance: not for a grid that ends exactly at the fraction)
    return (h, f"{h} = {hmax:g} m is more than {COATING_FRACTION:g} of the particle diameter "
               f"({dmin:g} m{where}): not a thin coating on a particle (the model assumes "
               "one); a unit slip? Lengths are in m: write 5e-6 or \"5 um\"")


def _size(field: str, label: str, solid_name: str, smallest, largest):
    """The finding for sizes outside the typical range of the solid ``solid_name``."""
    from . import materials

    entry = materials.solid(str(solid_name))
    r_lo, r_hi = entry.size_range
    for val, side in ((smallest, "below"), (largest, "above")):
        if val is not None and ((side == "below" and val < r_lo)
                                or (side == "above" and val > r_hi)):
            return (field, f"{label} = {val:g} m is {side} the typical size range of "
                           f"{entry.name} ({r_lo:g}-{r_hi:g} m, materials database); a unit "
                           "slip? Lengths are in m: write 500e-6 or \"500 um\"")
    return None


def _asperity(field: str, smallest, largest):
    for val in (smallest, largest):
        if val is not None and val > 0.0 and not ASPERITY_RANGE[0] <= val <= ASPERITY_RANGE[1]:
            return (field, f"{field} = {val:g} m is outside the plausible asperity heights "
                           f"{ASPERITY_RANGE[0]:g}-{ASPERITY_RANGE[1]:g} m")
    return None


def _emulsion(values: dict):
    """The emulsion's gas velocity ``U_e = U_e_Umf U_mf`` (the drag of the body forces)
    above the gas fed, ``U = U_Umf U_mf``: where a fluidized bed (``U_Umf > 1``) has
    ``U_Umf < U_e_Umf``. (A ``U`` given in m/s is not judged here: its ``U_mf`` is not
    known yet; ``U_Umf <= 1`` is not a fluidized bed, said where a speed needs one.)"""
    if not values.get("body_forces", True):
        return None
    u, ue = values.get("U_Umf"), _extreme(values, "U_e_Umf", np.max)
    if u is None or values.get("U") is not None or ue is None:
        return None
    u = np.asarray(u, dtype=float)
    inside = u[(u > 1.0) & (u < ue)]
    if not inside.size:
        return None
    return ("U_Umf", f"U_Umf = {float(inside.min()):g} is below U_e_Umf = {ue:g}: the "
                       "emulsion's gas velocity (the drag on the particles) would exceed U, "
                       "more gas than the bed is fed; near minimum fluidization set U_e_Umf "
                       "to at most U_Umf")


def scene_findings(values: dict) -> list[tuple[str, str]]:
    """``[(field, message), ...]`` for the plausibility checks of a scene's values.

    Numeric fields may be arrays (a sweep's axes): a check fires if any value fails it, and
    the message gives the extreme value. Names must be valid already. A field missing
    from ``values`` is not checked (a bed leaves out the fields its components set).
    """
    from . import materials

    found = []
    lo, hi = np.min, np.max
    for h, d, solid in (("h0", "d_i", "solid_i"), ("h0_j", "d_j", "solid_j")):
        dmin = _extreme(values, d, lo) if values.get(d) is not None else _extreme(
            values, "d_i", lo)
        found.append(_coating(h, _extreme(values, h, hi), dmin))
        name = values.get(solid) or values.get("solid_i")
        size = d if values.get(d) is not None else "d_i"  # d_j defaults to d_i
        if values.get(size) is None or name is None:
            continue
        if d == "d_j" and size == "d_i" and str(name) == str(values.get("solid_i")):
            continue  # the same size of the same solid: said once, for d_i
        label = d if size == d else f"{d} (= d_i)"
        found.append(_size(d, label, name, _extreme(values, size, lo),
                           _extreme(values, size, hi)))
    for ha in ("ha_i", "ha_j"):
        found.append(_asperity(ha, _extreme(values, ha, lo), _extreme(values, ha, hi)))
    found.append(_emulsion(values))
    pmin, pmax = _extreme(values, "P", lo), _extreme(values, "P", hi)
    if pmin is not None and pmin < PRESSURE_RANGE[0]:
        found.append(("P", f"P = {pmin:g} Pa is below {PRESSURE_RANGE[0]:g} Pa: pressures are "
                           "absolute, in Pa (write 1.5e5 or \"1.5 bar\")"))
    if pmax is not None and pmax > PRESSURE_RANGE[1]:
        found.append(("P", f"P = {pmax:g} Pa is above {PRESSURE_RANGE[1]:g} Pa (100 bar)"))
    liquid = values.get("liquid")
    entry = materials.liquid_entry(str(liquid)) if liquid is not None else None
    tmin, tmax = _extreme(values, "T", lo), _extreme(values, "T", hi)
    if entry is not None and entry.model == "water":
        # (below the triple point there is no boiling point: the properties refuse P)
        if tmax is not None and pmin is not None and pmin >= _WATER_P_TRIPLE:
            t_boil = _water_boiling_point(pmin)
            if tmax >= t_boil:
                found.append(("T", f"T = {tmax:g} K is at or above water's boiling point at "
                                   f"P = {pmin:g} Pa ({t_boil:.2f} K): a water film would "
                                   "evaporate (the properties are those of superheated "
                                   "liquid)"))
    if entry is not None and entry.model == "melt" and tmin is not None and tmin < MELT_T_MIN:
        # (the value as read, in K and in degC: whoever typed "500 degC" sees it was read
        # so, and the slip's remedy is said as a condition, not as a guess)
        found.append(("T", f"T = {tmin:g} K ({tmin - 273.15:g} degC) is below "
                           f"{MELT_T_MIN:g} K ({MELT_T_MIN - 273.15:g} degC): no oxide melt "
                           f"such as {entry.name} is liquid there (the lowest alkali-silicate "
                           "eutectics are near 700 degC). Temperatures without a unit are in "
                           f"K: if {tmin:g} was meant in degC, write {tmin + 273.15:g} or "
                           f"\"{tmin:g} degC\""))
    umax, ceiling = _extreme(values, "u0", hi), _extreme(values, "u_ceiling", lo)
    if (isinstance(values.get("speed"), str) and values["speed"] in ("fixed", "lognormal")
            and umax is not None
            and ceiling is not None and umax > ceiling):
        found.append(("u0", f"u0 = {umax:g} m/s is above the u0* ceiling ({ceiling:g} m/s): "
                            "no bubbling bed gives such impact speeds (raise u_ceiling if "
                            "yours does)"))
    return [f for f in found if f is not None]


#: Scene fields a bed takes from its components and the direction average (its solids,
#: sizes, coatings of j, asperities, collision angle): not the bed's scene's to judge.
BED_OWN = ("solid_i", "solid_j", "d_i", "d_j", "h0_j", "ha_i", "ha_j", "beta_deg")


def component_findings(component) -> list[tuple[str, str]]:
    """The plausibility findings of one bed component alone (an
    :class:`agglomtool.bed.Component`): its sizes against its solid's typical range (the
    ``d50`` given, or the extremes of ``d``), its own coating against its smallest class,
    its asperity height."""
    d = np.asarray(component.size_classes()[0], dtype=float)
    if component.d50 is not None:
        size = _size("d50", "d50", component.solid, component.d50, component.d50)
    else:
        size = _size("d", "d", component.solid, float(d.min()), float(d.max()))
    ha = None if component.ha is None else float(component.ha)
    found = [size, _asperity("ha", ha, ha)]
    if component.h0 is not None:
        found.append(_coating("h0", float(component.h0), float(d.min()),
                              f", the smallest class of {component.name}"))
    return [f for f in found if f is not None]


def bed_findings(values: dict, components=(), grid=None) -> list[tuple[str, str]]:
    """The plausibility findings of a bed that its Scene and components have not said
    already: the scene's at the values a grid sweeps (``grid``: field -> values; the
    fields of :data:`BED_OWN` are the components'), and the scene's coating ``h0`` on
    every component that takes it, against that component's smallest class."""
    own = set(BED_OWN) | {"fraction"}
    base = {k: v for k, v in values.items() if k not in own}
    swept = {**base, **{k: v for k, v in (grid or {}).items() if k not in own}}
    said = set(scene_findings(base))  # the Scene's own, said when it was made
    found = [f for f in scene_findings(swept) if f not in said]
    hmax = _extreme(swept, "h0", np.max)
    for comp in components:
        if comp.h0 is None:
            dmin = float(np.min(comp.size_classes()[0]))
            found.append(_coating("h0", hmax, dmin, f", the smallest class of {comp.name}"))
    return list(dict.fromkeys(f for f in found if f is not None))


def warn_findings(findings, stacklevel: int = 3) -> None:
    """Issue one :class:`PlausibilityWarning` per finding."""
    for _field, message in findings:
        warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel + 1)


def _water_boiling_point(P: float) -> float:
    """Saturation temperature of water at ``P`` [Pa] (IAPWS-95 through CoolProp) [K]."""
    from .properties._gas_tables import _cp

    P = min(max(P, _WATER_P_TRIPLE), 22.06e6)  # the triple point to the critical pressure
    return float(_cp().PropsSI("T", "P", P, "Q", 0, "Water"))
