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

__all__ = ["PlausibilityWarning", "scene_findings", "warn_findings", "ASPERITY_RANGE",
           "COATING_FRACTION", "PRESSURE_RANGE"]

#: Asperity heights outside this range [m] are implausible for bed solids.
ASPERITY_RANGE = (1e-9, 10e-6)
#: A coating thicker than this fraction of the particle diameter is not a film.
COATING_FRACTION = 0.1
#: Absolute pressures outside this range [Pa] are implausible for a fluidized bed.
PRESSURE_RANGE = (1e4, 1e7)
#: Water's triple-point pressure [Pa]: no liquid water below it.
_WATER_P_TRIPLE = 611.655


class PlausibilityWarning(UserWarning):
    """Valid input that looks wrong (a unit slip, a size outside a solid's range, ...)."""


def _extreme(values: dict, name: str, how):
    v = values.get(name)
    if v is None:
        return None
    arr = np.asarray(v, dtype=float)
    return float(how(arr)) if arr.size else None


def scene_findings(values: dict) -> list[tuple[str, str]]:
    """``[(field, message), ...]`` for the plausibility checks of a scene's values.

    Numeric fields may be arrays (a sweep's axes): a check fires if any value fails it, and
    the message gives the extreme value. Names must be valid already.
    """
    from . import materials

    found = []
    lo, hi = np.min, np.max
    for h, d, solid in (("h0", "d_i", "solid_i"), ("h0_j", "d_j", "solid_j")):
        hmax = _extreme(values, h, hi)
        dmin = _extreme(values, d, lo) if values.get(d) is not None else _extreme(
            values, "d_i", lo)
        if hmax is not None and dmin is not None and hmax > COATING_FRACTION * dmin * (
                1.0 + 1e-9):  # not for a grid that ends exactly at the fraction
            found.append((h, f"{h} = {hmax:g} m is more than {COATING_FRACTION:g} of the "
                             f"particle diameter ({dmin:g} m): not a thin coating on a "
                             "particle (the model assumes one); a unit slip? Lengths are in "
                             "m: write 5e-6 or \"5 um\""))
        name = values.get(solid) or values.get("solid_i")
        size = d if values.get(d) is not None else "d_i"  # d_j defaults to d_i
        if values.get(size) is None or name is None:
            continue
        if d == "d_j" and size == "d_i" and str(name) == str(values.get("solid_i")):
            continue  # the same size of the same solid: said once, for d_i
        label = d if size == d else f"{d} (= d_i)"
        entry = materials.solid(str(name))
        r_lo, r_hi = entry.size_range
        for val, side in ((_extreme(values, size, lo), "below"),
                          (_extreme(values, size, hi), "above")):
            if (side == "below" and val < r_lo) or (side == "above" and val > r_hi):
                found.append((d, f"{label} = {val:g} m is {side} the typical size range of "
                                 f"{entry.name} ({r_lo:g}-{r_hi:g} m, materials database); a "
                                 "unit slip? Lengths are in m: write 500e-6 or \"500 um\""))
                break
    for ha in ("ha_i", "ha_j"):
        for val in (_extreme(values, ha, lo), _extreme(values, ha, hi)):
            if val is not None and val > 0.0 and not (
                    ASPERITY_RANGE[0] <= val <= ASPERITY_RANGE[1]):
                found.append((ha, f"{ha} = {val:g} m is outside the plausible asperity "
                                  f"heights {ASPERITY_RANGE[0]:g}-{ASPERITY_RANGE[1]:g} m"))
                break
    pmin, pmax = _extreme(values, "P", lo), _extreme(values, "P", hi)
    if pmin is not None and pmin < PRESSURE_RANGE[0]:
        found.append(("P", f"P = {pmin:g} Pa is below {PRESSURE_RANGE[0]:g} Pa: pressures are "
                           "absolute, in Pa (write 1.5e5 or \"1.5 bar\")"))
    if pmax is not None and pmax > PRESSURE_RANGE[1]:
        found.append(("P", f"P = {pmax:g} Pa is above {PRESSURE_RANGE[1]:g} Pa (100 bar)"))
    liquid = values.get("liquid")
    if liquid is not None and materials.liquid_entry(str(liquid)).model == "water":
        tmax = _extreme(values, "T", hi)
        pmin = _extreme(values, "P", lo)
        # (below the triple point there is no boiling point: the properties refuse P)
        if tmax is not None and pmin is not None and pmin >= _WATER_P_TRIPLE:
            t_boil = _water_boiling_point(pmin)
            if tmax >= t_boil:
                found.append(("T", f"T = {tmax:g} K is at or above water's boiling point at "
                                   f"P = {pmin:g} Pa ({t_boil:.2f} K): a water film would "
                                   "evaporate (the properties are those of superheated "
                                   "liquid)"))
    umax, ceiling = _extreme(values, "u0", hi), _extreme(values, "u_ceiling", lo)
    if (values.get("speed") in ("fixed", "lognormal") and umax is not None
            and ceiling is not None and umax > ceiling):
        found.append(("u0", f"u0 = {umax:g} m/s is above the u0* ceiling ({ceiling:g} m/s): "
                            "no bubbling bed gives such impact speeds (raise u_ceiling if "
                            "yours does)"))
    return found


def warn_findings(findings, stacklevel: int = 3) -> None:
    """Issue one :class:`PlausibilityWarning` per finding."""
    for _field, message in findings:
        warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel + 1)


def _water_boiling_point(P: float) -> float:
    """Saturation temperature of water at ``P`` [Pa] (IAPWS-95 through CoolProp) [K]."""
    from .properties._gas_tables import _cp

    P = min(max(P, _WATER_P_TRIPLE), 22.06e6)  # the triple point to the critical pressure
    return float(_cp().PropsSI("T", "P", P, "Q", 0, "Water"))
