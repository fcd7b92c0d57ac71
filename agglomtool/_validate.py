"""Input checks shared by every public entry point.

Bad input fails at the boundary with a ``ValueError`` that names the field, the offending
value and the allowed range. Nothing downstream has to guard against NaN. Input that is
valid but implausible warns with a :class:`PlausibilityWarning`, defined here (low in the
layers) so that the correlations can warn without importing the scene-level checks of
:mod:`agglomtool.plausibility`, which re-exports it.
"""

from __future__ import annotations

import functools
import math

import numpy as np


class PlausibilityWarning(UserWarning):
    """Valid input that looks wrong (a unit slip, a size outside a solid's range, ...)."""


def _first_bad(arr: np.ndarray, bad: np.ndarray) -> float:
    """The first offending value of ``arr`` where ``bad`` is true."""
    return float(np.broadcast_to(arr, bad.shape)[bad].flat[0])


#: SI unit of each input field of the core's API, for pint Quantities given there.
FIELD_UNITS = {
    "d": "m", "h0": "m", "ha": "m", "rho": "kg/m**3", "mu": "Pa*s", "gamma": "N/m",
    "theta_deg": "degree", "eps": "dimensionless", "U": "m/s", "u0": "m/s", "u0_j": "m/s",
    "beta_deg": "degree", "e": "dimensionless", "tol": "dimensionless", "u_max": "m/s",
}


def _from_quantity(name: str, value):
    """A pint Quantity given for field ``name``, in the field's SI unit (a ValueError for a
    field without a unit or a Quantity of another dimension)."""
    from .units import to_si

    unit = FIELD_UNITS.get(name.split(".")[-1].split("[")[0])
    if unit is None:
        raise ValueError(f"{name} = {value!r}: give a plain number (SI) here")
    return to_si(name, value, unit)


def as_float_array(name: str, value, allowed: str = "finite numbers") -> np.ndarray:
    """Convert ``value`` to a float64 array; reject NaN and non-numeric input, naming the
    field, the value and the ``allowed`` range in the message. A pint Quantity is converted
    to the field's SI unit (:data:`FIELD_UNITS`) first: ``d = 500 um`` is 5e-4 m, never
    500 m."""
    if type(value) is float or type(value) is int:  # the common scalar, without numpy
        if value != value:
            raise ValueError(f"{name} = nan is not a number; allowed: {allowed}")
        return np.array(value, dtype=np.float64)
    arr = _float_array(name, value, allowed)
    # One reduction, no mask: the minimum is NaN exactly when some element is.
    if arr.size and math.isnan(arr.min()):
        _raise_nan(name, arr, allowed)
    return arr


def _float_array(name: str, value, allowed: str) -> np.ndarray:
    """:func:`as_float_array` without the NaN check."""
    if type(value) is np.ndarray and value.dtype == np.float64:
        return value  # what np.asarray below would return
    if hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "to"):
        value = _from_quantity(name, value)
    if isinstance(value, (bool, np.bool_)) or getattr(value, "dtype", None) == np.bool_:
        raise ValueError(f"{name} = {value!r} is a boolean, not a number; allowed: {allowed}")
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(
            f"{name} = {value!r} is not a number or an array of numbers; allowed: {allowed}"
        ) from exc


def _raise_nan(name: str, arr: np.ndarray, allowed: str):
    """The ``ValueError`` for ``arr``, which holds a NaN, naming the first one's index."""
    where = ""
    if arr.ndim:
        where = f" at index {tuple(int(i) for i in np.argwhere(np.isnan(arr))[0])}"
    raise ValueError(f"{name} = nan{where} is not a number; allowed: {allowed}")


@functools.lru_cache(maxsize=256)
def _range_text(lo, hi, lo_open, hi_open, unit) -> str:
    """The allowed range as messages state it: ``"(0, inf) m"``, ``"[0, 1]"``."""
    lo_s = "-inf" if lo is None else f"{lo:g}"
    hi_s = "inf" if hi is None else f"{hi:g}"
    rng = f"{'(' if lo_open else '['}{lo_s}, {hi_s}{')' if hi_open or hi is None else ']'}"
    if unit and unit not in ("-", "dimensionless"):
        rng += f" {unit}"
    return rng


def check_range(
    name: str,
    value,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    allow_inf: bool = False,
    unit: str = "",
) -> np.ndarray:
    """Return ``value`` as a float array after checking ``lo <= value <= hi``.

    ``lo_open`` / ``hi_open`` make the bound strict. ``+inf`` is refused unless
    ``allow_inf`` (a plate's diameter, say); ``-inf`` is always refused.
    """
    if type(value) is float or type(value) is int:  # the common scalar, without numpy
        # Python's comparisons decide it; a value they refuse (NaN included) takes the
        # general path below, which names it.
        if (value == value and (lo is None or (value > lo if lo_open else value >= lo))
                and (hi is None or (value < hi if hi_open else value <= hi))
                and value != -math.inf and (allow_inf or value != math.inf)):
            return np.array(value, dtype=np.float64)
    rng = _range_text(lo, hi, lo_open, hi_open, unit)
    arr = _float_array(name, value, rng)
    if arr.size:
        # Two reductions decide the common case (every value allowed) without a mask; the
        # masks below only run to name the first bad value. The minimum is NaN exactly
        # when some element is.
        mn, mx = arr.min(), arr.max()
        if math.isnan(mn):
            _raise_nan(name, arr, rng)
        if ((lo is None or (mn > lo if lo_open else mn >= lo))
                and (hi is None or (mx < hi if hi_open else mx <= hi))
                and mn != -np.inf and (allow_inf or mx != np.inf)):
            return arr
    bad = np.zeros(arr.shape, dtype=bool)
    if lo is not None:
        bad |= (arr <= lo) if lo_open else (arr < lo)
    if hi is not None:
        bad |= (arr >= hi) if hi_open else (arr > hi)
    if not allow_inf:
        bad |= np.isinf(arr)
    else:
        bad |= np.isneginf(arr)
    if bad.any():
        raise ValueError(f"{name} = {_first_bad(arr, bad)!r} is outside the allowed range {rng}")
    return arr
