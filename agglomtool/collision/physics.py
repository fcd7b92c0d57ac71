"""The pair physics written once: compiled scalar functions that both the numpy reference
(:func:`agglomtool.pair.prepare_pair`, :mod:`agglomtool.properties`) and the fused kernels
(:mod:`.fused`) call.

Each function takes and returns float64 scalars and is compiled with Numba; the numpy side
broadcasts it over arrays as a ufunc (``numba.vectorize`` of a one-line call), the compiled
loops call it directly. One formula, one order of operations: the reference and the fused
preparation give bitwise the same masses, ``U_mf`` and drag (``tests/test_one_source.py``).

Cubes are products (``x * x * x``): a ``pow`` call costs several times a product, and the
cubes were a third of the fused preparation's time. A product of three factors is within
two units in the last place of the correctly rounded cube.

Division by zero follows IEEE (``error_model="numpy"``): these functions also serve the
public numpy functions, which answer ``inf`` or NaN there rather than raise. A plate
(``d = inf``) takes finite stand-ins before its answer is set: compiled over arrays, both
sides of a branch are evaluated on every element, and an ``inf / inf`` on the side not
taken would raise numpy's "invalid value" warning on good inputs.

:func:`reduced_mass` and :func:`relative_body_force` are the pair physics of the tier
kernels (every tier takes them, :mod:`.stages`): scalars in, a tuple or a scalar out, with
the kernels' error model.
"""

from __future__ import annotations

import math

from numba import njit

from .._jit import CACHE
from ..constants import GRAVITY

__all__ = ["WEN_YU_C1", "WEN_YU_C2", "EPS_SWITCH", "U_E_PER_UMF", "wet_mass", "wet_sphere",
           "umf_wen_yu", "wet_umf", "drag_gidaspow", "reduced_mass", "relative_body_force"]

#: Wen and Yu's constants of ``Re_mf = sqrt(C1^2 + C2 Ar) - C1`` (1966).
WEN_YU_C1, WEN_YU_C2 = 33.7, 0.0408

#: Voidage at which Gidaspow switches from the Ergun branch to the Wen-Yu branch [-].
EPS_SWITCH = 0.8

#: The emulsion gas velocity where the bed's is not given: ``U_e = 1.1 U_mf`` of the pair's
#: larger ``U_mf`` (the paper's Section 3.1 choice).
U_E_PER_UMF = 1.1

@njit(cache=CACHE, error_model="numpy")
def wet_mass(d, rho, h0, rho_l):
    """Mass of a coated sphere [kg] (Eqs. 32-33): diameter ``d`` [m], density ``rho``
    [kg/m3], coating ``h0`` [m] of density ``rho_l`` [kg/m3]; ``inf`` for a plate
    (``d = inf``).

    The coating volume ``(4/3) pi ((r + h0)^3 - r^3)`` is written as
    ``(4/3) pi h0 (3 r^2 + 3 r h0 + h0^2)``: no cancellation for thin coatings.
    """
    r = 0.5 * d
    plate = math.isinf(r)
    if plate:
        r = 1.0  # a finite stand-in (module docstring: no flags raised on a branch not taken)
    solid = rho * (r * r * r)
    shell = rho_l * h0 * (3.0 * r * r + 3.0 * r * h0 + h0 * h0)
    m = (4.0 / 3.0) * math.pi * (solid + shell)
    return math.inf if plate else m


@njit(cache=CACHE, error_model="numpy")
def wet_sphere(d, h0):
    """``(d_wet, volume)`` of a coated sphere: its wet diameter ``d + 2 h0`` [m] and volume
    ``(pi / 6) d_wet^3`` [m3] (solid diameter ``d``, coating ``h0`` [m])."""
    d_wet = d + 2.0 * h0
    return d_wet, (math.pi / 6.0) * (d_wet * d_wet * d_wet)


@njit(cache=CACHE, error_model="numpy")
def umf_wen_yu(d, rho_p, mu_g, rho_g, c1, c2):
    """Minimum fluidization velocity [m/s] of spheres of diameter ``d`` [m] and density
    ``rho_p`` [kg/m3] in a gas of viscosity ``mu_g`` [Pa s] and density ``rho_g`` [kg/m3],
    by the Wen-Yu family ``Re_mf = sqrt(c1^2 + c2 Ar) - c1`` (Wen and Yu's own constants:
    :data:`WEN_YU_C1`, :data:`WEN_YU_C2`)::

        Ar = d^3 rho_g (rho_p - rho_g) g / mu_g^2
        Re_mf = c2 Ar / (sqrt(c1^2 + c2 Ar) + c1)     (no cancellation at small Ar)
        U_mf = Re_mf mu_g / (rho_g d)
    """
    ar = (d * d * d) * rho_g * (rho_p - rho_g) * GRAVITY / (mu_g * mu_g)
    re_mf = c2 * ar / (math.sqrt(c1 * c1 + c2 * ar) + c1)
    return re_mf * mu_g / (rho_g * d)


@njit(cache=CACHE, error_model="numpy")
def wet_umf(d, h0, m, mu_g, rho_g, c1, c2):
    """:func:`umf_wen_yu` [m/s] of a coated sphere: its wet diameter ``d + 2 h0`` and its
    mean density, wet mass ``m`` [kg] over wet volume; 0 for a plate (``d = inf``), which
    has no ``U_mf``."""
    plate = math.isinf(d)
    if plate:  # finite stand-ins (module docstring), the answer replaced by 0 below
        d_wet = 1e-3
        rho_p = 1e3 * rho_g
    else:
        d_wet, vol = wet_sphere(d, h0)
        rho_p = m / vol
    u = umf_wen_yu(d_wet, rho_p, mu_g, rho_g, c1, c2)
    return 0.0 if plate else u


@njit(cache=CACHE, error_model="numpy")
def drag_gidaspow(slip, d, volume, eps, mu_g, rho_g):
    """Gidaspow's drag on one particle along the slip velocity [N] (signed like ``slip``
    [m/s]): diameter ``d`` [m] and volume ``volume`` [m3] of the wet particle, voidage
    ``eps`` [-], gas ``mu_g`` [Pa s] and ``rho_g`` [kg/m3]; :func:`agglomtool.properties.
    drag_force_gidaspow` gives the formulas and the source."""
    speed = abs(slip)
    if eps < EPS_SWITCH:
        return (150.0 * (1.0 - eps) * mu_g / (eps * d * d) + 1.75 * rho_g * speed / d) \
            * volume * slip
    re = rho_g * eps * d * speed / mu_g
    # C_d |slip| = (C_d Re) mu_g / (rho_g eps d): finite at zero slip.
    if re < 1000.0:
        cd_re = 24.0 * (1.0 + 0.15 * re**0.687)
    else:
        cd_re = 0.44 * re
    cd_speed = cd_re * mu_g / (rho_g * eps * d)
    return 0.75 * cd_speed * rho_g * slip * eps**-1.65 * volume / d


@njit(cache=CACHE)
def reduced_mass(m_i, m_j):
    """Reduced mass [kg] and the mass fractions ``(m_r, frac_i, frac_j)``; exact for a plate
    on either side (``frac = m / (m_i + m_j)``). Every tier takes its masses from here."""
    if math.isinf(m_j):
        return m_i, 0.0, 1.0
    if math.isinf(m_i):
        return m_j, 1.0, 0.0
    # Both fractions divided out directly: 1 - frac_i would cancel at extreme mass ratios.
    frac_i = m_i / (m_i + m_j)
    frac_j = m_j / (m_i + m_j)
    return m_i * frac_j, frac_i, frac_j


@njit(cache=CACHE)
def relative_body_force(m_i, m_j, fn_i, fn_j):
    """Body force on the relative motion [N], positive when it pushes the pair together:
    ``m_r (fn_i / m_i - fn_j / m_j)``; a plate (infinite mass, held) contributes 0."""
    m_r, _, _ = reduced_mass(m_i, m_j)
    acc_i = 0.0 if math.isinf(m_i) else fn_i / m_i
    acc_j = 0.0 if math.isinf(m_j) else fn_j / m_j
    return m_r * (acc_i - acc_j)
