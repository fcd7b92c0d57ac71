"""The critical impact speed: the smallest relative speed at which a pair rebounds.

Vectorised over collisions: every step evaluates a kernel on all still-unresolved elements
at once; no Python loop runs over collisions.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._jit import CACHE, parallel_launch
from .bridge import ln_f_diff, ln_f_diff_array
from .fused import SERIAL_BELOW, TIER_PAPER, prepare_one
from .paper import paper_kernel
from .relative import relative_kernel

__all__ = ["first_rebound_speed", "viscous_lower_bound", "critical_speeds"]

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


# ---- compiled solver for the tiers with fused kernels ("paper", "relative") -------------


@njit(cache=CACHE)
def _sticks(vals, ins, st, q, w_rel, tier, body, particle_slip, empty):
    """True where collision ``q`` sticks at relative speed ``w_rel`` [m/s]; ``vals`` holds
    its prepared numbers (``fused.prepare_one`` at zero speed)."""
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, w_per_u0 = vals
    if body and particle_slip:  # the drag depends on the particles' own speed
        u = w_rel / w_per_u0
        pre = _one_at_speed(ins, st, q, u, body, particle_slip)
        fn_i, fn_j = pre[7], pre[8]
    mu_l = ins[8][q * st[8]]
    gamma = ins[9][q * st[9]]
    e = ins[17][q * st[17]]
    if tier == TIER_PAPER:
        ew, _, _ = paper_kernel(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w_rel, fn_i,
                                fn_j, e, empty)
    else:
        ew, _, _, _ = relative_kernel(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w_rel,
                                      fn_i, fn_j, e, empty)
    return ew == 0.0


@njit(cache=CACHE)
def _one_at_speed(ins, st, q, u, body, particle_slip):
    return prepare_one(
        ins[0][q * st[0]], ins[1][q * st[1]], ins[2][q * st[2]], ins[3][q * st[3]],
        ins[4][q * st[4]], ins[5][q * st[5]], ins[6][q * st[6]], ins[7][q * st[7]],
        ins[8][q * st[8]], ins[9][q * st[9]], ins[10][q * st[10]], ins[11][q * st[11]],
        ins[12][q * st[12]], ins[13][q * st[13]], ins[14][q * st[14]], ins[15][q * st[15]],
        ins[16][q * st[16]], ins[17][q * st[17]], u, math.nan, body, particle_slip,
    )


@njit(cache=CACHE)
def _solve_one(ins, st, q, tier, body, particle_slip, rtol, u_max):
    """u0* [m/s] of collision ``q`` by the search of :func:`first_rebound_speed`, run to
    this collision's own convergence; ``inf`` where it exceeds ``u_max`` [m/s] (the search
    stops as soon as every speed up to ``u_max`` is known to stick)."""
    empty = np.empty(0)
    vals = _one_at_speed(ins, st, q, 0.0, body, particle_slip)
    m_i, m_j, r, H0, Ha = vals[0], vals[1], vals[2], vals[3], vals[4]
    w_per_u0 = vals[10]
    e = ins[17][q * st[17]]
    if not H0 > Ha:
        return 0.0 if e > 0.0 else math.inf
    if e == 0.0 or Ha == 0.0:
        return math.inf
    mu_l = ins[8][q * st[8]]
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    delta = -ln_f_diff(H0, Ha, a2)
    if math.isinf(m_j):
        m_r = m_i
    elif math.isinf(m_i):
        m_r = m_j
    else:
        m_r = m_i * (m_j / (m_i + m_j))
    # 1. Double from the viscous bound (which sticks) until a rebound.
    hi = max(c * delta / m_r, MIN_SPEED)
    w_max = u_max * w_per_u0
    found = False
    for _ in range(MAX_DOUBLINGS):
        hi *= 2.0
        if 0.5 * hi >= w_max:  # every speed up to w_max sticks: u0* > u_max
            return math.inf
        if not _sticks(vals, ins, st, q, hi, tier, body, particle_slip, empty):
            found = True
            break
    if not found:
        return math.inf
    # 2. Scan the last doubling (hi/2, hi] on FINE_POINTS geometric points.
    base = 0.5 * hi
    lo = base  # below the first point lies the previous doubling, which stuck
    top = hi
    for k in range(1, FINE_POINTS):
        g = base * 2.0 ** (k / FINE_POINTS)
        if not _sticks(vals, ins, st, q, g, tier, body, particle_slip, empty):
            top = g
            break
        lo = g
    hi = top
    # 3. Bisect in ln w between a sticking lo and a rebounding hi.
    for _ in range(64):
        if hi - lo <= rtol * hi:
            break
        mid = math.sqrt(lo) * math.sqrt(hi)
        if _sticks(vals, ins, st, q, mid, tier, body, particle_slip, empty):
            lo = mid
        else:
            hi = mid
    u_star = hi / w_per_u0
    return u_star if u_star <= u_max else math.inf


@njit(parallel=True, cache=CACHE)
def _solve_parallel(ins, st, tier, body, particle_slip, rtol, u_max, out):
    for q in prange(out.shape[0]):
        out[q] = _solve_one(ins, st, q, tier, body, particle_slip, rtol, u_max)


@njit(cache=CACHE)
def _solve_serial(ins, st, tier, body, particle_slip, rtol, u_max, out):
    for q in range(out.shape[0]):
        out[q] = _solve_one(ins, st, q, tier, body, particle_slip, rtol, u_max)


def critical_speeds(ins, steps, n, tier, body, particle_slip, rtol, u_max=math.inf):
    """Head-on u0* [m/s] of ``n`` collisions given as the fused kernels' inputs
    (:mod:`.fused`), for ``tier`` ``fused.TIER_PAPER`` or ``fused.TIER_RELATIVE``.

    The search of :func:`first_rebound_speed` (doubling from the viscous bound, a 16-point
    geometric scan of the last doubling, bisection in ``ln w`` to ``rtol``), compiled and
    run per collision: each stops at its own convergence, so a collision's u0* does not
    depend on the rest of the batch. ``inf`` where u0* exceeds ``u_max`` [m/s]: the search
    stops once every speed up to ``u_max`` is known to stick.
    """
    out = np.empty(n)
    args = (ins, steps, int(tier), bool(body), bool(particle_slip), float(rtol), float(u_max),
            out)
    if n < SERIAL_BELOW // 100:
        _solve_serial(*args)
    else:
        parallel_launch(_solve_parallel, *args)
    return out
