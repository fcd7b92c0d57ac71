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

import numpy as np

#: Arrays up to this size get the exact decimal power-of-ten conversion (a grid axis, a
#: few parameters); larger ones are multiplied (within one rounding of it).
_EXACT_MAX = 100_000

__all__ = ["is_quantity", "to_si", "to_si_array", "registry"]

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def registry():
    """pint's application registry (the one a user's ``pint.Quantity`` belongs to)."""
    import pint

    return pint.get_application_registry()


def is_quantity(value) -> bool:
    """True for a pint Quantity (duck-typed: no pint import needed to ask)."""
    return hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "to")


def _parse(field: str, text: str):
    """A unit string as a Quantity: a number followed by a unit (or a bare number)."""
    m = _NUMBER.match(text)
    if m is None:
        raise ValueError(f"{field} = {text!r} is not a number with a unit (e.g. \"5 um\", "
                         "\"850 degC\", \"1.5 bar\")")
    number, unit = float(m.group(1)), m.group(2)
    ureg = registry()
    try:
        return ureg.Quantity(number, unit)
    except Exception as exc:  # pint's UndefinedUnitError and parse errors
        raise ValueError(f"{field} = {text!r}: {unit!r} is not a unit pint knows "
                         f"({type(exc).__name__})") from None


def _convert(field: str, q, unit: str, long_name: str):
    """Magnitude of Quantity ``q`` in ``unit``, exact for power-of-ten scalings."""
    import pint

    target = q._REGISTRY.parse_units(unit)
    try:
        offset = q._REGISTRY.Quantity(0.0, q.units).to(target).magnitude
        factor = q._REGISTRY.Quantity(1.0, q.units).to(target).magnitude - offset
    except pint.DimensionalityError:
        raise ValueError(
            f"{field} = {q:~P} has units of {q.dimensionality}, but {field}"
            + (f" ({long_name})" if long_name != field else "") + f" is in {unit}") from None
    mag = np.asarray(q.magnitude, dtype=float)
    if offset != 0.0:  # temperatures: degC, degF
        return q.to(target).magnitude
    if factor == 1.0:
        return mag
    k = round(math.log10(factor))
    if abs(factor / 10.0**k - 1.0) <= 1e-12 and mag.size <= _EXACT_MAX:
        # A power of ten: shift the decimal exponent of the number as typed, so that
        # "0.1 um" is the double nearest 1e-7, exactly as the plain number 1e-7 is.
        out = np.array([float(f"{x!r}e{k}") for x in mag.ravel().tolist()])
        return out.reshape(mag.shape)
    return mag * factor


def to_si(field: str, value, unit: str, long_name: str = ""):
    """``value`` in ``unit`` (the field's SI unit): a Quantity or unit string converted, a
    plain number or array returned as it is. A bare numeric string (``"5e-6"``) is a number.

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
    out = _convert(field, q, unit, long_name or field)
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
