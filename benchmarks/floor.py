"""The arithmetic floor of a collision batch: what no implementation of the model can beat.

A straight-line compiled loop over the same flat input arrays as the fused kernels
(:mod:`agglomtool.collision.fused`) that does only the arithmetic of the ordinary path:
the preparation (wet masses, radius, ``U_mf``, drag, projections), the approach with both
particles moving (one ``ln f`` difference, one capillary difference, the viscous loss),
contact, the rupture distance, and the separation likewise, each gap's square root and
``ln f`` taken once (as the kernels take them). No branch on the outcome, no
stopping-gap search, no details, no validation. Its time per collision is the yardstick the
benchmarks divide by.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from agglomtool.collision.bridge import _LN4, g_diff_s, gap_parts, rupture_distance
from agglomtool.collision.fused import BLOCK, NO_ANGLES, _one, slip_flag

__all__ = ["floor_batch"]


@njit(parallel=True)
def _floor(ins, st, body, particle_slip, e_w, w_out):
    n = e_w.shape[0]
    # Blocks carrying the angles' memo, as the fused loops do (fused._angles).
    for b in prange((n + BLOCK - 1) // BLOCK):
        last = NO_ANGLES
        for k in range(b * BLOCK, min(n, (b + 1) * BLOCK)):
            (m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, _, a_t, a_c, a_b,
             a_s) = _one(ins, st, k, body, particle_slip, last)
            last = (a_t, a_c, a_b, a_s)
            mu_l = ins[8][k * st[8]]
            gamma = ins[9][k * st[9]]
            e = ins[17][k * st[17]]
            m_r = m_i * (m_j / (m_i + m_j))
            a2 = (H0 - Ha) * (H0 + Ha)
            c = 1.5 * math.pi * mu_l * r * r
            kcap = 2.0 * math.pi * gamma * r * cos_t
            f_b = m_r * (fn_i / m_i - fn_j / m_j)
            k0 = 0.5 * m_r * w * w
            s_h0, kind_h0, val_h0 = gap_parts(H0, a2)
            s_ha, kind_ha, val_ha = gap_parts(Ha, a2)
            cd = -c * ((val_ha - val_h0) + (kind_h0 - kind_ha) * _LN4)
            k_app = (k0 - kcap * g_diff_s(H0, s_h0, Ha, s_ha, a2) - cd * (w - 0.5 * cd / m_r)
                     + f_b * (H0 - Ha))
            w_s = e * math.sqrt(2.0 * abs(k_app) / m_r)
            h_rupt = rupture_distance(theta, mu_l * w_s / gamma, 0.5 * math.pi * r * a2)
            s_hr, kind_hr, val_hr = gap_parts(h_rupt, a2)
            cd = c * ((val_hr - val_ha) + (kind_ha - kind_hr) * _LN4)
            k_end = (0.5 * m_r * w_s * w_s - kcap * g_diff_s(Ha, s_ha, h_rupt, s_hr, a2)
                     - cd * (w_s - 0.5 * cd / m_r) - f_b * (h_rupt - Ha))
            e_w[k] = math.sqrt(abs(k_end) / k0)
            w_out[k] = w


def floor_batch(ins, steps, n, body=True, particle_slip=False):
    """Run the floor loop on ``n`` collisions; returns ``(e_w-like, w)`` (meaningless
    numbers, computed so that nothing is optimised away)."""
    e_w = np.empty(n)
    w = np.empty(n)
    _floor(ins, steps, bool(body), slip_flag(particle_slip), e_w, w)
    return e_w, w
