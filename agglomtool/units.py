"""Units at the edge: pint Quantities and unit strings ("5 um", "850 degC", "1.5 bar") in, SI
floats out, converted once where a person's numbers enter (Scene fields, sweep grids, map
configurations, command-line options).

Plain numbers are SI already and pass through untouched. pint is imported only when a
Quantity or a unit string is actually given, so plain-number use pays nothing for it.

Conversions by a power of ten shift the decimal exponent of the number as typed rather
than multiply by an inexact factor, so that ``"5 um"`` is exactly ``5e-6`` m and
``"0.1 um"`` exactly ``1e-7`` m, as the plain numbers are.
"""

from __future__ import annotations

import math
import re
from functools import cache

import numpy as np

#: Arrays up to this size get the exact decimal power-of-ten conversion (a grid axis, a
#: few parameters); larger ones are multiplied (within one rounding of it).
_EXACT_MAX = 100_000

__all__ = ["is_quantity", "to_si", "to_si_array", "quantity", "registry", "ALIASES"]

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")

#: Spellings accepted besides pint's own (pint reads ``m3`` as a unit named "m3").
ALIASES = {"kg/m3": "kg/m**3", "g/cm3": "g/cm**3", "m2/s2": "m**2/s**2", "-": "dimensionless"}

#: Units that pint reads as something else than a person typing them after a temperature
#: often means: pint's symbol -> (what pint takes it for, the temperature meant).
_TEMPERATURE_SLIPS = {"C": ("coulomb", "degC"), "F": ("farad", "degF")}


@cache
def registry():
    """The registry that reads what a person types: pint's default definitions, private to
    agglomtool, so that "50 C" means the same (a coulomb, with a hint) whatever other
    library has replaced pint's application registry (cf_xarray.units, for one, defines
    UDUNITS spellings there). A user's own Quantity is converted by its own registry."""
    import pint

    return pint.UnitRegistry()


def is_quantity(value) -> bool:
    """True for a pint Quantity (duck-typed: no pint import needed to ask)."""
    return hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "to")


def _parse(field: str, text: str):
    """A unit string as a Quantity: a number followed by a unit (or a bare number)."""
    m = _NUMBER.match(text)
    if m is None:
        raise ValueError(f"{field} = {text!r} is not a number with a unit (e.g. \"5 um\", "
                         "\"850 degC\", \"1.5 bar\")")
    return quantity(field, float(m.group(1)), m.group(2), text)


def quantity(field: str, number, unit: str, text=None):
    """``number`` in ``unit`` (a pint unit, or one of :data:`ALIASES`) as a Quantity; a
    ``ValueError`` naming the field for a unit pint does not know."""
    ureg = registry()
    try:
        return ureg.Quantity(number, ALIASES.get(unit.strip(), unit))
    except Exception as exc:  # pint's UndefinedUnitError and parse errors
        shown = text if text is not None else f"{number!r} {unit}"
        raise ValueError(f"{field} = {shown!r}: {unit!r} is not a unit pint knows "
                         f"({type(exc).__name__})") from None


def _convert(field: str, q, unit: str, long_name: str, delta: bool = False, text=None):
    """Magnitude of Quantity ``q`` in ``unit``, exact for power-of-ten scalings; with
    ``delta``, ``q`` is a difference (a spread): an offset unit scales only (5 degC -> 5 K).
    ``text``: what the person typed, for the message."""
    import pint

    target = q._REGISTRY.parse_units(ALIASES.get(unit, unit))
    try:
        offset = q._REGISTRY.Quantity(0.0, q.units).to(target).magnitude
        factor = q._REGISTRY.Quantity(1.0, q.units).to(target).magnitude - offset
    except pint.DimensionalityError:
        raise ValueError(
            f"{field} = {q:~P} has units of {q.dimensionality}"
            + (f" (given as {text!r})" if text is not None else "") + f", but {field}"
            + (f" ({long_name})" if long_name != field else "") + f" is in {unit}"
            + _slip_hint(q, target)) from None
    mag = np.asarray(q.magnitude, dtype=float)
    if offset != 0.0 and not delta:  # temperatures: degC, degF
        return q.to(target).magnitude
    if factor == 1.0:
        return mag
    k = round(math.log10(factor))
    if abs(factor / 10.0**k - 1.0) <= 1e-12 and mag.size <= _EXACT_MAX:
        # A power of ten: shift the decimal exponent of the number as typed, so that
        # "0.1 um" is the double nearest 1e-7, exactly as the plain number 1e-7 is.
        out = np.array([_shift(x, k) for x in mag.ravel().tolist()])
        return out.reshape(mag.shape)
    return mag * factor


def _shift(x: float, k: int) -> float:
    """``x * 10**k`` by moving the decimal exponent of ``x`` as written (``1e+20``, ``k = 5``:
    ``1e25``)."""
    mantissa, _, exponent = repr(float(x)).partition("e")
    if mantissa in ("inf", "-inf", "nan"):
        return float(x)
    return float(f"{mantissa}e{int(exponent or 0) + k}")


def _slip_hint(q, target) -> str:
    """``"; 'C' is the coulomb in pint: did you mean "50 degC"?"`` where a temperature was
    asked for and the unit given is pint's symbol of something else."""
    if target.dimensionality != q._REGISTRY.parse_units("K").dimensionality:
        return ""
    for symbol, (what, meant) in _TEMPERATURE_SLIPS.items():
        if q.units == q._REGISTRY.parse_units(symbol):
            number = np.asarray(q.magnitude).reshape(-1)[0] if np.size(q.magnitude) else ""
            return (f"; {symbol!r} is the {what} in pint: did you mean "
                    f"\"{float(number):g} {meant}\"?")
    return ""


def to_si(field: str, value, unit: str, long_name: str = "", *, delta: bool = False):
    """``value`` in ``unit`` (the field's SI unit): a Quantity or unit string converted, a
    plain number or array returned as it is. A bare numeric string (``"5e-6"``) is a number.
    ``delta``: the value is a difference or a spread (an offset unit only scales).

    Raises
    ------
    ValueError
        Naming the field, the value and the unit expected, for a string pint cannot read or
        a Quantity of the wrong dimension.
    """
    if isinstance(value, str):
        m = _NUMBER.match(value)
        if m is not None and not m.group(2):
            return float(m.group(1))  # a bare number: SI, as typed
        q = _parse(field, value)
    elif is_quantity(value):
        q = value
    else:
        return value
    out = _convert(field, q, unit, long_name or field, delta,
                   value if isinstance(value, str) else None)
    out = np.asarray(out, dtype=float)
    return float(out) if out.ndim == 0 else out


def to_si_array(field: str, values, unit: str, long_name: str = ""):
    """A grid axis in SI: a Quantity array, or a list mixing numbers, strings, Quantities."""
    if is_quantity(values) or isinstance(values, str):
        return np.atleast_1d(to_si(field, values, unit, long_name))
    if isinstance(values, list | tuple) and any(isinstance(v, str) or is_quantity(v)
                                                for v in values):
        return np.array([to_si(field, v, unit, long_name) for v in values], dtype=float)
    return values
