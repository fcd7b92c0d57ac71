"""The critical impact speed: the smallest relative speed at which a pair rebounds.

Vectorised over collisions: every step evaluates a kernel on all still-unresolved elements
at once; no Python loop runs over collisions.
"""

from __future__ import annotations

import math

import numpy as np

from .bridge import ln_f_diff_array

__all__ = ["first_rebound_speed", "viscous_lower_bound"]

#: Geometric points scanned inside the first doubling that rebounds.
FINE_POINTS = 16
#: Smallest relative speed the search starts from [m/s] (the smallest normal double).
MIN_SPEED = float(np.finfo(float).tiny)
#: Doublings tried before a pair is declared never to rebound: 2^2100 spans every double.
MAX_DOUBLINGS = 2100


def viscous_lower_bound(m_i, m_j, r, H0, Ha, mu_l):
    """Relative speed [m/s] at or below which viscosity alone stops any approach.

    The approach needs ``m_r w > c (ln f(H0) - ln f(Ha))`` (Eqs. 73, 80 with the common CM
    momentum ``m_r w``); body and capillary forces do not enter that test, so every speed up
    to this bound sticks, whatever the model tier built on the paper's losses.
    """
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    delta = -ln_f_diff_array(H0, Ha, a2)
    plate_i, plate_j = np.isinf(m_i), np.isinf(m_j)
    # Finite stand-ins where a plate sits, so that no inf/inf is ever formed.
    mi_f, mj_f = np.where(plate_i, 1.0, m_i), np.where(plate_j, 1.0, m_j)
    m_r = np.where(plate_j, m_i, np.where(plate_i, m_j, mi_f * (mj_f / (mi_f + mj_f))))
    return c * delta / m_r


def first_rebound_speed(state, sticks, rtol):
    """Smallest relative speed ``w`` [m/s] at which ``sticks(w, idx)`` turns false.

    ``state`` carries flat arrays ``m_i, m_j, r, H0, Ha, mu_l, e``; ``sticks(w, idx)``
    evaluates the elements ``idx`` (an index array) at speeds ``w`` and returns a boolean
    array. Returns a flat array: ``inf`` where the pair never rebounds (``e = 0``, or a zero
    total asperity height), 0 where no bridge forms and ``e > 0``.
    """
    m_i, m_j, r = state.m_i.ravel(), state.m_j.ravel(), state.r.ravel()
    H0, Ha, mu_l, e = state.H0.ravel(), state.Ha.ravel(), state.mu_l.ravel(), state.e.ravel()
    n = m_i.size
    out = np.empty(n)
    bridge = H0 > Ha
    out[~bridge] = np.where(e[~bridge] > 0.0, 0.0, np.inf)
    never = bridge & ((e == 0.0) | (Ha == 0.0))
    out[never] = np.inf
    active = np.flatnonzero(bridge & ~never)
    if active.size == 0:
        return out

    # 1. Double from the viscous bound (which sticks) until a rebound.
    w_lo = viscous_lower_bound(m_i[active], m_j[active], r[active], H0[active], Ha[active],
                               mu_l[active])
    # Start from the bound itself, however small (a bridge barely thicker than the
    # asperities can rebound at any practical speed); where H0 and Ha differ only by rounding
    # the bound can be exactly 0, and the smallest normal double stands in.
    hi = np.maximum(w_lo, MIN_SPEED)
    pending = np.arange(active.size)
    for _ in range(MAX_DOUBLINGS):
        if pending.size == 0:
            break
        hi[pending] *= 2.0
        still = sticks(hi[pending], active[pending])
        pending = pending[still]
    if pending.size:
        out[active[pending]] = np.inf
        keep = np.ones(active.size, dtype=bool)
        keep[pending] = False
        active, hi = active[keep], hi[keep]
        if active.size == 0:
            return out

    # 2. Scan the last doubling (hi/2, hi] on FINE_POINTS geometric points.
    k = np.arange(1, FINE_POINTS + 1)
    grid = (0.5 * hi)[:, None] * 2.0 ** (k[None, :] / FINE_POINTS)
    st = sticks(grid.ravel(), np.repeat(active, FINE_POINTS)).reshape(grid.shape)
    st[:, -1] = False  # hi itself rebounded in step 1
    first = np.argmax(~st, axis=1)
    rows = np.arange(active.size)
    hi_first = grid[rows, first]
    # Below the first point lies the previous doubling, which stuck.
    lo = np.where(first > 0, grid[rows, np.maximum(first - 1, 0)], 0.5 * grid[rows, -1])
    hi = hi_first

    # 3. Bisect in ln w between a sticking lo and a rebounding hi.
    for _ in range(64):
        if np.all(hi - lo <= rtol * hi):
            break
        mid = np.sqrt(lo) * np.sqrt(hi)  # no underflow of lo * hi at tiny speeds
        s = sticks(mid, active)
        lo = np.where(s, mid, lo)
        hi = np.where(s, hi, mid)
    out[active] = hi
    return out
