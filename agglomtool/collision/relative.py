"""The frame-consistent variant of the paper's model (mode "relative"; docs/model.md).

The paper's closed-form losses (Shabanian et al. 2024, Heliyon 10:e29397,
doi:10.1016/j.heliyon.2024.e29397, Eqs. 72-105, 126-129) applied to the *relative* motion
along the collision axis instead of to each particle in the centre-of-mass frame:

- one body of reduced mass ``m_r = m_i m_j / (m_i + m_j)`` (``m_i`` for a plate j) moving at
  the relative normal speed ``w``;
- bridge forces as in the paper: capillary ``kcap X_v``, viscous ``c X_v^2 w / D``;
- body forces enter only through the relative acceleration they cause,
  ``F_b = m_r (fn_i / m_i - fn_j / m_j)`` (positive: pushes the pair together). Two particles
  with equal body force per unit mass (identical particles in a uniform field) feel none, so
  for them the collision direction has no effect, as mechanics requires.

Per stage (approach ``H0 -> Ha``, separation ``Ha -> h_rupt``), with
``Delta = |ln f(D_end) - ln f(D_start)|`` and the entering speed ``v``:

1. viscosity alone stops the pair when ``c Delta >= m_r v`` (the paper's Eqs. 73, 75 written
   for the relative motion);
2. otherwise ``K_end = K_start - L_cap - L_vis - L_bdw`` with the exact viscous-only loss
   ``L_vis = c Delta (v - c Delta / (2 m_r))``, the capillary loss
   ``kcap (g(D_end) - g(D_start))`` and the body-force loss ``-F_b (D_start - D_end)``
   (approach) or ``F_b (D_end - D_start)`` (separation); ``K_end <= 0`` sticks.

With no body forces (``fn_i = fn_j = 0``, e.g. ``beta = 0``) each particle of the paper's
model carries the mass fraction of the relative energy, both stop together, and this tier
equals mode "paper" to rounding.

A plate (``m_j = inf``) is the ``m_j -> inf`` limit of the same formulas (``m_r -> m_i``):
the losses are taken in the same order as for two moving particles (viscous loss from the
impact speed), so the tier is continuous in ``m_j``, as mode "paper" is too (there the
plate's running energy per unit speed decides whether it stops first). For the body
forces a plate is a *held* wall: nothing accelerates it, its term ``fn_j / m_j`` is 0. (A
free partner of huge mass would keep its own gravitational acceleration; a plate does not.)
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from . import _codes as codes
from .bridge import (
    _LN4,
    bridge_volume,
    g_diff,
    g_diff_s,
    gap_parts,
    ln_f,
    rupture_distance,
)
from .paper import _viscous_loss
from .records import TierInputs, WorkScale, pair_at, tier_inputs

__all__ = [
    "relative_kernel",
    "run_relative",
    "reduced_mass",
    "relative_body_force",
    "term_work_fractions",
    "NEGLIGIBLE_FRACTION",
]

#: A term (body forces, the bridge-volume correction) is reported negligible when its work
#: bound is below this fraction of the initial relative kinetic energy.
NEGLIGIBLE_FRACTION = 1e-3




@njit(cache=CACHE)
def reduced_mass(m_i, m_j):
    """Reduced mass [kg] and the mass fractions ``(m_r, frac_i, frac_j)``; exact for a plate
    on either side (``frac = m / (m_i + m_j)``)."""
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


@njit(cache=CACHE)
def term_work_fractions(scale, h_rupt):
    """Bounds of the work of two optional terms, as fractions of the initial relative kinetic
    energy ``scale.k0`` [J]: ``(body, volume correction)``; ``scale`` a
    :class:`~.records.WorkScale`, ``h_rupt`` the rupture gap [m].

    - body forces: ``|F_b| (H0 - Ha + h_rupt - Ha)``, the most they can do over the bridge;
    - the bridge-volume correction ``X_v``: the change it makes to the capillary work and to
      the viscous work at the impact speed ``w`` (with ``X_v = 1`` the capillary work over a
      stage is ``kcap |dD|`` and the viscous ``c w |d ln D|``).

    ``h_rupt`` NaN (the pair stuck before contact) counts the approach only.
    """
    k0, w, c, kcap, f_b, H0, Ha, a2 = scale
    sep = h_rupt > Ha
    d_body = (H0 - Ha) + ((h_rupt - Ha) if sep else 0.0)
    body = abs(f_b) * d_body / k0
    if not Ha > 0.0:
        return body, math.inf
    ln_h0, ln_ha = math.log(H0), math.log(Ha)
    cap = kcap * abs((H0 - Ha) - abs(g_diff(H0, Ha, a2)))
    vis = c * w * abs((ln_h0 - ln_ha) - abs(ln_f(H0, a2) - ln_f(Ha, a2)))
    if sep:
        cap += kcap * abs((h_rupt - Ha) - abs(g_diff(Ha, h_rupt, a2)))
        ln_hr = math.log(h_rupt)
        vis += c * w * abs((ln_hr - ln_ha) - abs(ln_f(h_rupt, a2) - ln_f(Ha, a2)))
    return body, (cap + vis) / k0


@njit(cache=CACHE, inline="always")
def _stage_energy(k, v, m_r, c_delta, l_cap, l_bdw):
    """One liquid stage of the relative motion, entered with kinetic energy ``k`` [J] at
    speed ``v`` [m/s], with its viscous ``c Delta`` and its capillary and body-force losses
    [J]: ``(code, k_end, l_vis)``, ``code`` 0 where the pair goes through with ``k_end``
    left, 1 where viscosity alone stops it (``c Delta >= m_r v``; ``k_end`` 0, ``l_vis``
    NaN), 2 where the energy is spent (``k_end <= 0``)."""
    if not c_delta < m_r * v:
        return 1, 0.0, math.nan
    l_vis = _viscous_loss(v, m_r, c_delta)
    k_end = k - l_cap - l_vis - l_bdw
    return (0 if k_end > 0.0 else 2), k_end, l_vis


@njit(cache=CACHE, inline="always")
def _work_details(det, scale, h_rupt):
    """The detail columns of the body and volume-correction work fractions; ``scale`` a
    :class:`~.records.WorkScale`."""
    body, vol = term_work_fractions(scale, h_rupt)
    det[codes.W_BODY] = body
    det[codes.W_VOLCORR] = vol


@njit(cache=CACHE, inline="always")
def _stuck(stage, path, det, want, scale, h_rupt):
    """:func:`relative_kernel`'s answer where the pair sticks at ``stage``, the work
    fractions written first (with details; ``scale`` as in :func:`_work_details`)."""
    if want:
        _work_details(det, scale, h_rupt)
    return 0.0, stage, path, 0.0


@njit(cache=CACHE)
def relative_kernel(pair, w, det):
    """One collision (``pair`` a :class:`~.records.Pair`, relative normal impact speed
    ``w`` [m/s]) by the paper's closed forms on the relative motion.

    Returns ``(e_w, stage, path, k_fin)``: ``k_fin`` is the kinetic energy of the relative
    motion left at rupture over the initial one [-] (0 when the pair sticks; used by mode
    "auto"). ``det`` as in :func:`agglomtool.collision.paper.paper_kernel`; the per-particle
    columns hold the CM-frame split of the relative energies (``frac_j`` to i, ``frac_i``
    to j, which is exact for kinetic energies).
    """
    m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e = pair
    nan = math.nan
    want = det.shape[0] > 0
    if want:
        for k in range(det.shape[0]):
            det[k] = nan
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    if not H0 > Ha:
        if want:
            det[codes.W_CONTACT] = w
            det[codes.L_C] = 0.5 * m_r * (1.0 - e * e) * w * w
        if e > 0.0:
            return e, codes.REBOUND, codes.P_NO_BRIDGE, e * e
        return 0.0, codes.CONTACT, codes.P_NO_BRIDGE, 0.0
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    kcap = 2.0 * math.pi * gamma * r * cos_t
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    scale = WorkScale(k0, w, c, kcap, f_b, H0, Ha, a2)
    if want:
        det[codes.K_INI_I] = frac_j * k0
        det[codes.K_INI_J] = frac_i * k0
        det[codes.ST_APP] = m_r * w / c

    # ---- approach, H0 -> Ha (each gap's square root and ln f parts taken once; the
    # differences formed as ln_f_diff and g_diff form them, bitwise)
    s_h0, kind_h0, val_h0 = gap_parts(H0, a2)
    s_ha, kind_ha, val_ha = gap_parts(Ha, a2)
    c_delta = c * -((val_ha - val_h0) + (kind_h0 - kind_ha) * _LN4)
    l_cap = kcap * g_diff_s(H0, s_h0, Ha, s_ha, a2)
    l_bdw = -f_b * (H0 - Ha)
    code, k_app, l_vis = _stage_energy(k0, w, m_r, c_delta, l_cap, l_bdw)
    if want:
        det[codes.L_CAP_APP] = l_cap
        det[codes.L_BDW_APP_I] = frac_j * l_bdw
        det[codes.L_BDW_APP_J] = frac_i * l_bdw
        det[codes.L_VIS_APP] = l_vis
    if code:
        return _stuck(codes.APP_VIS if code == 1 else codes.APP_EN, 0, det, want, scale,
                      math.nan)

    # ---- contact
    w_c = math.sqrt(2.0 * k_app / m_r)
    w_s = e * w_c
    if want:
        det[codes.K_APP_I] = frac_j * k_app
        det[codes.K_APP_J] = frac_i * k_app
        det[codes.W_CONTACT] = w_c
        det[codes.L_C] = 0.5 * m_r * (1.0 - e * e) * w_c * w_c
    if not w_s > 0.0:
        return _stuck(codes.CONTACT, 0, det, want, scale, math.nan)

    # ---- separation, Ha -> h_rupt
    k_s = 0.5 * m_r * w_s * w_s
    ca = mu_l * w_s / gamma
    h_rupt = rupture_distance(theta, ca, bridge_volume(r, a2))
    path = 0
    if want:
        det[codes.K_SEP_I] = frac_j * k_s
        det[codes.K_SEP_J] = frac_i * k_s
        det[codes.CA] = ca
        det[codes.H_RUPT] = h_rupt
    if not h_rupt > Ha:
        path |= codes.P_BROKEN
        k_end = k_s
    else:
        s_hr, kind_hr, val_hr = gap_parts(h_rupt, a2)
        c_delta = c * ((val_hr - val_ha) + (kind_ha - kind_hr) * _LN4)
        l_cap = kcap * g_diff_s(Ha, s_ha, h_rupt, s_hr, a2)
        l_bdw = f_b * (h_rupt - Ha)
        code, k_end, l_vis = _stage_energy(k_s, w_s, m_r, c_delta, l_cap, l_bdw)
        if want:
            det[codes.L_CAP_SEP] = l_cap
            det[codes.L_BDW_SEP_I] = frac_j * l_bdw
            det[codes.L_BDW_SEP_J] = frac_i * l_bdw
            det[codes.L_VIS_SEP] = l_vis
        if code:
            return _stuck(codes.SEP_VIS if code == 1 else codes.SEP_EN, path, det, want, scale,
                          h_rupt)
    k_fin = k_end / k0
    if want:
        det[codes.K_FIN_I] = frac_j * k_end
        det[codes.K_FIN_J] = frac_i * k_end
        _work_details(det, scale, h_rupt)
    e_w = math.sqrt(k_fin)
    if not e_w > 0.0:  # the energy left underflowed: a stick, as in the paper kernel
        return 0.0, codes.SEP_EN, path, 0.0
    return e_w, codes.REBOUND, path, k_fin


@njit(parallel=True, cache=CACHE)
def _run_relative_batch(ins, e_w, stage, path, k_fin, det):
    for k in prange(e_w.shape[0]):
        ew, st, pa, kf = relative_kernel(pair_at(ins, k), ins.w[k], det[k])
        e_w[k] = ew
        stage[k] = st
        path[k] = pa
        k_fin[k] = kf


def relative_batch(ins: TierInputs, *, details=False):
    """:func:`run_relative` that also returns ``k_fin`` (final over initial relative kinetic
    energy [-]) as a fifth array."""
    ins = tier_inputs(ins)
    n = ins.w.shape[0]
    e_w = np.empty(n)
    stage = np.empty(n, dtype=np.int8)
    path = np.empty(n, dtype=np.int8)
    k_fin = np.empty(n)
    det = np.empty((n, codes.N_DETAILS if details else 0))
    parallel_launch(_run_relative_batch, ins, e_w, stage, path, k_fin, det)
    return e_w, stage, path, det, k_fin


def run_relative(ins: TierInputs, *, details=False):
    """Evaluate :func:`relative_kernel` over the 1-D float64 arrays of equal length ``ins``
    (a :class:`~.records.TierInputs`, or the same arrays in its order).

    Returns ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
    """
    e_w, stage, path, det, _ = relative_batch(ins, details=details)
    return e_w, stage, path, det
