"""Liquid-bridge geometry: volume, volume correction, distance function, rupture distance.

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397,
Eqs. 3, 28-30, 76 and 94 (the last after Pitois et al. 2001).

All functions are scalar and compiled with Numba; they are called per collision from the
kernels in this package. Gaps ``D`` are surface-to-surface distances [m]; ``a2`` is the
bridge constant ``a^2 = H0^2 - Ha^2`` [m2] (Eq. 29 with Eq. 30).
"""

from __future__ import annotations

import math

from numba import njit, vectorize

from .._jit import CACHE

_LN4 = math.log(4.0)

__all__ = [
    "ln_f",
    "ln_f_diff",
    "ln_f_diff_from",
    "ln_f_parts",
    "ln_f_parts_s",
    "ln_f_array",
    "ln_f_diff_array",
    "g_diff",
    "gap_parts",
    "g_diff_s",
    "rupture_distance",
    "rupture_gap",
    "bridge_volume",
    "ln_f_change",
    "g_change",
    "viscous_constant",
    "capillary_constant",
]


@njit(cache=CACHE)
def gap_parts(D, a2):
    """``(s, kind, value)`` of the gap ``D`` [m]: ``s = sqrt(D^2 + a^2)`` [m] and the parts
    of :func:`ln_f_parts` (which returns the last two), so that a kernel that needs both
    ``ln f`` and :func:`g_diff_s` at a gap takes its square root once."""
    s = math.sqrt(D * D + a2)
    kind, value = ln_f_parts_s(D, s, a2)
    return s, kind, value


@njit(cache=CACHE)
def ln_f_parts_s(D, s, a2):
    """:func:`ln_f_parts` from ``s = sqrt(D^2 + a^2)`` already taken (:func:`gap_parts`
    takes it and calls this)."""
    if D <= 0.0:
        return 0, -math.inf
    # With q = a^2 / (D + s)^2, exactly f = (1 - q^2) / 4. Where D >> a the three logs
    # below all approach constants and a difference of two ln f values would lose every
    # digit; log1p keeps them.
    q = a2 / ((D + s) * (D + s))
    if q < 0.5:
        return 1, math.log1p(-q * q)
    return 0, math.log(D) + math.log(s) - 2.0 * math.log(D + s)


@njit(cache=CACHE)
def ln_f(D, a2):
    """``ln f(D)`` of the distance function of Eq. 76 [-].

    ``f(D) = D s / (D + s)^2`` with ``s = sqrt(D^2 + a^2)``; evaluated as
    ``ln D + ln s - 2 ln(D + s)`` so that nothing underflows, or, where ``D >> a``, as
    ``log1p(-q^2) - ln 4`` with ``q = a^2 / (D + s)^2`` (the same number, exactly), so that
    differences of ``ln f`` keep their digits. ``d ln f / dD = X_v^2 / D``,
    which makes the viscous work a difference of ``ln f``. ``D <= 0`` gives ``-inf``
    (the lubrication singularity: an infinite viscous loss).
    """
    _, kind, value = gap_parts(D, a2)
    return value - _LN4 if kind else value


@njit(cache=CACHE)
def ln_f_parts(D, a2):
    """``(kind, value)``: kind 1 when ``ln f = value - ln 4`` (the log1p form), else 0 and
    ``ln f = value``."""
    _, kind, value = gap_parts(D, a2)
    return kind, value


@njit(cache=CACHE)
def g_diff_s(D1, s1, D2, s2, a2):
    """:func:`g_diff` from the square roots ``s_k = sqrt(D_k^2 + a^2)`` (of
    :func:`gap_parts`); :func:`g_diff` takes them and calls it."""
    return a2 * (D2 - D1) * (1.0 + (D1 + D2) / (s1 + s2)) / ((D1 + s1) * (D2 + s2))


@njit(cache=CACHE)
def ln_f_diff(D1, D2, a2):
    """``ln f(D2) - ln f(D1)`` [-], keeping its digits where both gaps are ``>> a``.

    There ``ln f`` is ``-ln 4`` plus a tiny ``log1p`` term, and subtracting two full values
    would lose every digit of that term; the constant is cancelled exactly instead. This is
    the ``Delta`` of every viscous loss (Eqs. 72-75, 88-97). ``D1`` or ``D2`` of 0 gives an
    infinite difference.
    """
    k1, v1 = ln_f_parts(D1, a2)
    return ln_f_diff_from(k1, v1, D2, a2)


@njit(cache=CACHE)
def ln_f_diff_from(k1, v1, D2, a2):
    """:func:`ln_f_diff` from ``(k1, v1) = ln_f_parts(D1, a2)``, for callers that measure
    many gaps from one start and compute its parts once."""
    k2, v2 = ln_f_parts(D2, a2)
    return (v2 - v1) + (k1 - k2) * _LN4


@njit(cache=CACHE)
def g_diff(D1, D2, a2):
    """``g(D2) - g(D1)`` for the capillary potential ``g(D) = D - sqrt(D^2 + a^2)`` [m].

    The capillary work between two gaps is ``2 pi gamma r cos(theta)`` times this
    (Eqs. 98-105). Written without cancellation: with ``s_k = sqrt(D_k^2 + a^2)``,
    ``g = -a^2 / (D + s)`` and the difference is
    ``a^2 (D2 - D1) (1 + (D1 + D2) / (s1 + s2)) / ((D1 + s1) (D2 + s2))``.
    Positive when ``D2 > D1`` (separating costs energy for a wetting liquid).
    """
    return g_diff_s(D1, math.sqrt(D1 * D1 + a2), D2, math.sqrt(D2 * D2 + a2), a2)


@njit(cache=CACHE)
def bridge_volume(r, a2):
    """Bridge volume ``V_b = (pi r / 2) (H0^2 - Ha^2)`` [m3] (Eq. 30), from ``a^2``."""
    return 0.5 * math.pi * r * a2


@njit(cache=CACHE)
def rupture_distance(theta, capillary_number, volume):
    """Gap at which the bridge ruptures [m] (Eq. 94, Pitois et al. 2001).

    ``h_rupt = (1 + theta/2) (1 + Ca^(1/2)) V_b^(1/3)``, ``theta`` in radians.
    """
    return rupture_gap(theta, capillary_number, volume ** (1.0 / 3.0))


@njit(cache=CACHE, inline="always")
def rupture_gap(theta, capillary_number, vol3):
    """:func:`rupture_distance` [m] from the cube root ``vol3`` [m] of the bridge volume,
    for the kernels that take it once per collision and the rupture gap at several speeds
    (the same operations, so the same number)."""
    return (1.0 + 0.5 * theta) * (1.0 + math.sqrt(capillary_number)) * vol3


@njit(cache=CACHE, inline="always")
def ln_f_change(start, end):
    """``ln f(end.d) - ln f(start.d)`` [-] of two gaps given with their parts (records with
    the fields ``d, s, kind, val`` of :class:`~.records.Gap`), formed as
    :func:`ln_f_diff_from` forms it (bitwise)."""
    return (end.val - start.val) + (start.kind - end.kind) * _LN4


@njit(cache=CACHE, inline="always")
def g_change(start, end, a2):
    """``g(end.d) - g(start.d)`` [m] (:func:`g_diff`) of two gaps given with their square
    roots (:class:`~.records.Gap` records), bitwise as :func:`g_diff`."""
    return g_diff_s(start.d, start.s, end.d, end.s, a2)


@njit(cache=CACHE, inline="always")
def viscous_constant(mu_l, r):
    """The viscous constant ``c = (3/2) pi mu_l r^2`` [kg m] (Eq. 26) of the lubrication
    force ``c X_v^2 v / D``: liquid viscosity ``mu_l`` [Pa s], radius ``r`` [m]."""
    return 1.5 * math.pi * mu_l * r * r


@njit(cache=CACHE, inline="always")
def capillary_constant(gamma, r, cos_t):
    """The capillary constant ``kcap = 2 pi gamma r cos(theta)`` [N] (Eq. 25) of the
    capillary force ``kcap X_v``: surface tension ``gamma`` [N/m], radius ``r`` [m],
    ``cos_t`` the cosine of the contact angle."""
    return 2.0 * math.pi * gamma * r * cos_t


#: :func:`ln_f` as a numpy ufunc, for array code outside the kernels.
ln_f_array = vectorize(["float64(float64, float64)"], cache=CACHE)(ln_f.py_func)

#: :func:`ln_f_diff` as a numpy ufunc.
ln_f_diff_array = vectorize(["float64(float64, float64, float64)"], cache=CACHE)(
    ln_f_diff.py_func
)
