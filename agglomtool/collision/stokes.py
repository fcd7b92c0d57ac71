"""The viscous Stokes criterion of Ennis, Tardos and Pfeffer (1991) (mode "stokes").

B.J. Ennis, G. Tardos, R. Pfeffer (1991), A microlevel-based characterization of granulation
phenomena, Powder Technol. 65:257-272, doi:10.1016/0032-5910(91)80189-9.

Two spheres approach through a liquid layer with only the lubrication force ``c w / D``
(``c = (3/2) pi mu_l r^2``, no volume correction, no capillary or body force). The relative
speed then falls linearly with ``ln D``: by ``(c / m_r) ln(H0 / Ha)`` over the approach
from the first liquid contact ``H0`` to the asperities ``Ha``, and by the same amount over
the separation back to ``H0``, where the bridge is taken to break. With the viscous Stokes
number ``St_v = m_r w / c`` (for identical spheres ``8 rho R u0 / (9 mu_l)`` with the head-on
``u0 = w / 2``, Ennis' definition) the pair sticks when

``St_v <= (1 + 1/e) ln(H0 / Ha)``

and otherwise rebounds with ``e_w = e - (1 + e) ln(H0 / Ha) / St_v``: the matching rebound
estimate, which is 0 exactly at the criterion.

The cheapest tier: no bridge geometry beyond ``H0`` and ``Ha``, no rupture criterion.
"""

from __future__ import annotations

import math

from numba import njit, prange

from .._jit import CACHE, parallel_launch
from . import _codes as codes
from . import stages
from .bridge import viscous_constant
from .physics import reduced_mass
from .records import Pair, TierInputs, tier_inputs

__all__ = ["run_stokes", "stokes_kernel"]


@njit(cache=CACHE)
def stokes_kernel(pair, w, det):
    """One collision (``pair`` a :class:`~.records.Pair`; its surface tension, contact
    angle and body forces are not used) at the relative normal impact speed ``w`` [m/s] by
    the Ennis criterion. Returns ``(e_w, stage, path)``."""
    m_i, m_j, r, H0, Ha, mu_l, e = pair.m_i, pair.m_j, pair.r, pair.H0, pair.Ha, pair.mu_l, pair.e
    want = stages.fresh_details(det)
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    if want:
        stages.split_details(det, codes.K_INI_I, codes.K_INI_J, frac_i, frac_j, 0.5 * m_r * w * w)
    if not H0 > Ha:
        # (no contact loss in the details: Ennis' criterion has no energy balance)
        if want:
            det[codes.W_CONTACT] = w
        return stages.no_bridge(e)
    st = m_r * w / viscous_constant(mu_l, r)
    ln_gap = math.log(H0 / Ha) if Ha > 0.0 else math.inf
    if want:
        det[codes.ST_APP] = st
    if not st > ln_gap:
        return 0.0, codes.APP_VIS, 0
    if want:
        det[codes.W_CONTACT] = w * (1.0 - ln_gap / st)
    if not e > 0.0:
        return 0.0, codes.CONTACT, 0
    if not st > (1.0 + 1.0 / e) * ln_gap:
        return 0.0, codes.SEP_VIS, 0
    return e - (1.0 + e) * ln_gap / st, codes.REBOUND, 0


@njit(parallel=True, cache=CACHE)
def _run_stokes_batch(ins, e_w, stage, path, det):
    nan = math.nan
    for q in prange(e_w.shape[0]):
        # Only the fields Ennis' criterion reads are loaded (the others NaN): loading all
        # twelve cost about 10 % on 1e6 collisions, the loads of five arrays it never uses.
        pair = Pair(ins.m_i[q], ins.m_j[q], ins.r[q], ins.H0[q], ins.Ha[q], ins.mu_l[q], nan,
                    nan, nan, nan, nan, ins.e[q])
        ew, st, pa = stokes_kernel(pair, ins.w[q], det[q])
        e_w[q] = ew
        stage[q] = st
        path[q] = pa


def run_stokes(ins: TierInputs, *, details=False):
    """Evaluate :func:`stokes_kernel` over the flat float64 arrays ``ins`` (a
    :class:`~.records.TierInputs`, or its arrays in order: the tier signature of
    :mod:`agglomtool.collision.tiers`; ``gamma, cos_t, theta, fn_i, fn_j`` are not used).

    Returns ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
    """
    ins = tier_inputs(ins)
    n = ins.w.shape[0]
    e_w, stage, path, det = stages.tier_outputs(n, details)
    parallel_launch(_run_stokes_batch, ins, e_w, stage, path, det)
    return e_w, stage, path, det
