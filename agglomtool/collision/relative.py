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
from . import stages
from .bridge import bridge_volume, gap_parts
from .physics import reduced_mass, relative_body_force
from .records import Gap, TierInputs, WorkScale, pair_at, tier_inputs
from .stages import term_work_fractions
from .stages import viscous_loss as _viscous_loss  # noqa: F401 (critical_relative's import)

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


@njit(cache=CACHE, inline="always")
def _stuck(stage, path, det, want, scale, h_rupt):
    """:func:`relative_kernel`'s answer where the pair sticks at ``stage``, the work
    fractions written first (with details; ``scale`` as in :func:`~.stages.work_details`)."""
    if want:
        stages.work_details(det, scale, h_rupt)
    return 0.0, stage, path, 0.0


@njit(cache=CACHE)
def relative_kernel(pair, w, det):
    """One collision (``pair`` a :class:`~.records.Pair`, relative normal impact speed
    ``w`` [m/s]) by the paper's closed forms on the relative motion.

    Returns ``(e_w, stage, path, k_fin)``: ``k_fin`` is the kinetic energy of the relative
    motion left at rupture over the initial one [-] (0 when the pair sticks; used by mode
    "auto"). ``det`` as in :func:`agglomtool.collision.paper.paper_kernel`; the per-particle
    columns hold the CM-frame split of the relative energies (``frac_j`` to i, ``frac_i``
    to j, which is exact for kinetic energies). The steps are those of :mod:`.stages`.
    """
    m_i, m_j, r, H0, Ha, _, _, _, _, fn_i, fn_j, e = pair
    want = stages.fresh_details(det)
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    if not H0 > Ha:
        e_w, stage, path = stages.dry_contact(det, m_r, e, w)
        return e_w, stage, path, e_w * e_w
    bridge = stages.bridge_constants(pair)
    c, kcap, a2 = bridge
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    scale = WorkScale(k0, w, c, kcap, f_b, H0, Ha, a2)
    if want:
        stages.split_details(det, codes.K_INI_I, codes.K_INI_J, frac_i, frac_j, k0)
        det[codes.ST_APP] = m_r * w / c

    # ---- approach, H0 -> Ha (each gap's square root and ln f parts taken once)
    gap_h0 = Gap(H0, *gap_parts(H0, a2))
    gap_ha = Gap(Ha, *gap_parts(Ha, a2))
    c_delta, l_cap, l_bdw = stages.stage_losses(gap_h0, gap_ha, bridge, f_b)
    code, k_app, l_vis = stages.stage_energy(k0, w, m_r, c_delta, l_cap, l_bdw)
    if want:
        stages.stage_details(det, False, l_cap, l_vis, l_bdw, frac_i, frac_j)
    if code:
        return _stuck(codes.APP_VIS if code == 1 else codes.APP_EN, 0, det, want, scale,
                      math.nan)

    # ---- contact
    w_s = stages.relative_contact(det, frac_i, frac_j, m_r, e, k_app)
    if not w_s > 0.0:
        return _stuck(codes.CONTACT, 0, det, want, scale, math.nan)

    # ---- separation, Ha -> h_rupt
    vol3 = bridge_volume(r, a2) ** (1.0 / 3.0)  # as rupture_distance takes it
    k_s, h_rupt = stages.separation_start(det, pair, frac_i, frac_j, m_r, w_s, vol3)
    path = 0
    if not h_rupt > Ha:
        path |= codes.P_BROKEN
        k_end = k_s
    else:
        c_delta, l_cap, l_bdw = stages.stage_losses(
            gap_ha, Gap(h_rupt, *gap_parts(h_rupt, a2)), bridge, f_b)
        code, k_end, l_vis = stages.stage_energy(k_s, w_s, m_r, c_delta, l_cap, l_bdw)
        if want:
            stages.stage_details(det, True, l_cap, l_vis, l_bdw, frac_i, frac_j)
        if code:
            return _stuck(codes.SEP_VIS if code == 1 else codes.SEP_EN, path, det, want, scale,
                          h_rupt)
    k_fin = k_end / k0
    if want:
        stages.split_details(det, codes.K_FIN_I, codes.K_FIN_J, frac_i, frac_j, k_end)
        stages.work_details(det, scale, h_rupt)
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
    e_w, stage, path, det = stages.tier_outputs(n, details)
    k_fin = np.empty(n)
    parallel_launch(_run_relative_batch, ins, e_w, stage, path, k_fin, det)
    return e_w, stage, path, det, k_fin


def run_relative(ins: TierInputs, *, details=False):
    """Evaluate :func:`relative_kernel` over the 1-D float64 arrays of equal length ``ins``
    (a :class:`~.records.TierInputs`, or the same arrays in its order).

    Returns ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
    """
    e_w, stage, path, det, _ = relative_batch(ins, details=details)
    return e_w, stage, path, det
