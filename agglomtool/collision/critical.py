"""The critical impact speed: the smallest relative speed at which a pair rebounds.

Two solvers:

- :func:`first_rebound_speed`, the bracketed search for any tier (doubling from the viscous
  bound, a geometric scan of the last doubling, bisection), vectorised over collisions:
  every step evaluates a kernel on all still-unresolved elements at once;
- :func:`critical_speeds`, compiled, per collision, for the fused tiers: mode "relative"
  from its near-closed form (:mod:`.critical_relative`) checked with the kernel (at two
  speeds that share the kernel's speed-independent work with each other and with the
  threshold: :func:`.critical_relative.kernel_e_w`, bitwise the kernel), mode "paper"
  from the same value where it has no body forces (checked with its own kernel); each
  falls back to the same search compiled where the check fails.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange, types
from numba.extending import overload

from .._jit import CACHE, parallel_launch
from .bridge import ln_f_diff, ln_f_diff_array
from .critical_relative import (
    EARLY_RTOL,
    MAX_ITER,
    OK,
    kernel_constants,
    kernel_e_w,
    threshold_from,
)
from .fused import SERIAL_BELOW, TIER_PAPER, TIER_RELATIVE, prepare_one, tier_kernel
from .relative import reduced_mass

__all__ = ["first_rebound_speed", "viscous_lower_bound", "critical_speeds"]

#: Geometric points scanned inside the first doubling that rebounds.
FINE_POINTS = 16
#: Smallest relative speed the search starts from [m/s] (the smallest normal double).
MIN_SPEED = float(np.finfo(float).tiny)
#: Doublings tried before a pair is declared never to rebound: 2^2100 spans every double.
MAX_DOUBLINGS = 2100
#: The closed-form candidate ``w*`` is checked at ``w* (1 + NUDGE rtol)``: close enough to
#: the switch that the answer sits within a thousandth of ``rtol`` above it.
NUDGE = 1e-3
#: First half-width factor of the bracket ``paper`` searches around the relative ``w*``.
BRACKET = 1.02
#: Rounds and tolerance of the candidate's drag update with ``drag_slip="particle"``.
SLIP_ITER = 12
SLIP_RTOL = 1e-12
#: The Newton iteration's early-stop bound there (:data:`.critical_relative.EARLY_RTOL`
#: elsewhere): far below :data:`SLIP_RTOL`, so that the rounds' candidates can settle.
SLIP_EARLY_RTOL = 1e-14


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
def _sticks(vals, raw, w_rel, tier, body, particle_slip, empty):
    """True where collision ``q`` sticks at relative speed ``w_rel`` [m/s]; ``vals`` holds
    its prepared numbers (``fused.prepare_one`` at zero speed)."""
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, w_per_u0 = vals
    if body and particle_slip:  # the drag depends on the particles' own speed
        u = w_rel / w_per_u0
        pre = _prep(raw, u, body, particle_slip)
        fn_i, fn_j = pre[7], pre[8]
    mu_l = raw[8]
    gamma = raw[9]
    e = raw[17]
    ew, _, _ = tier_kernel(tier, m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w_rel, fn_i,
                           fn_j, e, empty)
    return ew == 0.0


@njit(cache=CACHE, inline="always")
def _raw(ins, st, q):
    """The raw inputs of collision ``q`` as a tuple of floats: the solver's helpers take it
    instead of the arrays themselves (passing the tuple of 20 arrays to a function that is
    not inlined costs a reference-count update per array and call)."""
    return (
        ins[0][q * st[0]], ins[1][q * st[1]], ins[2][q * st[2]], ins[3][q * st[3]],
        ins[4][q * st[4]], ins[5][q * st[5]], ins[6][q * st[6]], ins[7][q * st[7]],
        ins[8][q * st[8]], ins[9][q * st[9]], ins[10][q * st[10]], ins[11][q * st[11]],
        ins[12][q * st[12]], ins[13][q * st[13]], ins[14][q * st[14]], ins[15][q * st[15]],
        ins[16][q * st[16]], ins[17][q * st[17]],
    )


@njit(cache=CACHE)
def _prep(raw, u, body, particle_slip):
    """:func:`.fused.prepare_one` of a head-on collision at lab speed ``u`` [m/s]."""
    return prepare_one(
        raw[0], raw[1], raw[2], raw[3], raw[4], raw[5], raw[6], raw[7], raw[8], raw[9],
        raw[10], raw[11], raw[12], raw[13], raw[14], raw[15], raw[16], raw[17], u, math.nan,
        body, particle_slip,
    )


#: How each u0* was found (:func:`critical_speeds` ``how``): no search needed (no bridge,
#: ``e = 0``, ``Ha = 0``); the closed-form candidate verified by the kernel; a bracket
#: around it (mode "paper"); the full search (the candidate failed or was not asked for).
HOW_TRIVIAL, HOW_CLOSED, HOW_BRACKET, HOW_SEARCH = 0, 1, 2, 3


@njit(cache=CACHE)
def _solve_one(raw, tier, body, particle_slip, rtol, u_max, closed, max_iter, empty):
    """``(u0*, how)`` of one collision [m/s] (``raw``: its inputs, :func:`_raw`); ``inf``
    where it exceeds ``u_max`` [m/s].

    ``closed``: start from the near-closed form of mode "relative"
    (:func:`.critical_relative.relative_threshold`) and verify it with the kernel
    (:func:`_from_candidate`); else, or where that fails, the search of
    :func:`first_rebound_speed` (:func:`_search_one`). ``empty``: a length-0 array (the
    kernels' "no details").
    """
    vals = _prep(raw, 0.0, body, particle_slip)
    H0, Ha = vals[3], vals[4]
    w_per_u0 = vals[10]
    e = raw[17]
    if not H0 > Ha:
        return (0.0 if e > 0.0 else math.inf), HOW_TRIVIAL
    if e == 0.0 or Ha == 0.0:
        return math.inf, HOW_TRIVIAL
    w_max = u_max * w_per_u0
    if closed:
        w_star, status = _from_candidate(vals, raw, tier, body, particle_slip, rtol,
                                         w_max, max_iter, empty)
        how = HOW_BRACKET if status == _BRACKETED else HOW_CLOSED
        if status == _FOUND or status == _BRACKETED:
            u_star = w_star / w_per_u0
            return (u_star if u_star <= u_max else math.inf), how
        if status == _ABOVE:
            return math.inf, HOW_BRACKET
    return (_search_one(vals, raw, tier, body, particle_slip, rtol, u_max, empty),
            HOW_SEARCH)


#: Outcomes of :func:`_from_candidate`.
_FOUND, _ABOVE, _SEARCH, _BRACKETED = 0, 1, 2, 3


@njit(cache=CACHE, inline="always")
def _relative_candidate(kc, vals, raw, body, particle_slip, max_iter):
    """``(w*, ok)``: the near-closed-form threshold of mode "relative" [m/s] from the
    collision's kernel constants ``kc`` at zero speed. Where the drag depends on the
    particles' own speed (``drag_slip="particle"``) the body forces are re-evaluated at the
    candidate until it moves by less than :data:`SLIP_RTOL` (at most :data:`SLIP_ITER`
    rounds)."""
    m_i, m_j, r, H0, Ha, cos_t, theta, _, _, _, w_per_u0 = vals
    mu_l = raw[8]
    gamma = raw[9]
    e = raw[17]
    slip = body and particle_slip
    early = SLIP_EARLY_RTOL if slip else EARLY_RTOL
    w, status = threshold_from(kc, H0, Ha, mu_l, gamma, theta, e, max_iter, early)
    if not slip or status != OK:
        return w, status == OK
    for _ in range(SLIP_ITER):
        pre = _prep(raw, w / w_per_u0, body, particle_slip)
        kc_w = kernel_constants(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, pre[7],
                                pre[8])
        w_new, status = threshold_from(kc_w, H0, Ha, mu_l, gamma, theta, e, max_iter,
                                       early)
        if status != OK:
            return math.nan, False
        if abs(w_new - w) <= SLIP_RTOL * w_new:
            return w_new, True
        w = w_new
    return math.nan, False


@njit(cache=CACHE, inline="always")
def _check_sticks(own, kc, vals, raw, w_rel, tier, body, particle_slip, empty):
    """:func:`_sticks` at ``w_rel`` [m/s]; with ``own`` (mode "relative", body forces that
    do not depend on the speed) from the kernel's speed-independent numbers ``kc``
    (:func:`.critical_relative.kernel_e_w`, bitwise the kernel's ``e_w``)."""
    if own:
        return kernel_e_w(kc, vals[3], vals[4], raw[8], raw[9], vals[6], raw[17],
                          w_rel) == 0.0
    return _sticks(vals, raw, w_rel, tier, body, particle_slip, empty)


@njit(cache=CACHE)
def _from_candidate(vals, raw, tier, body, particle_slip, rtol, w_max, max_iter,
                    empty):
    """``(w*, status)`` from the relative tier's near-closed form, checked with the
    ``tier``'s own kernel; status ``_FOUND``, ``_ABOVE`` (every speed up to ``w_max``
    sticks) or ``_SEARCH`` (no verified answer: run the search).

    The answer ``hi`` always satisfies the search's own contract: the kernel rebounds at
    ``hi`` and sticks at ``hi (1 - rtol)``.

    - ``relative``: ``hi = w* (1 + delta)``, ``delta`` = :data:`NUDGE` ``rtol`` (then
      ``rtol / 4``, should rounding in the kernel put its switch a little above ``w*``);
      anything else goes to the search. Where the body forces do not depend on the speed
      the two kernel evaluations share its speed-independent work with each other and
      with the threshold (:func:`.critical_relative.kernel_e_w`, the kernel's arithmetic
      bitwise);
    - ``paper``: with body forces, ``_SEARCH`` at once (see the code); without, the same
      check first (the tiers then agree to rounding); else a bracket around ``w*`` widened
      geometrically (factor :data:`BRACKET`, squared at
      each widening) until the kernel sticks at its bottom and rebounds at its top, never
      below the viscous bound (where every tier sticks), then bisection in ``ln w`` to
      ``rtol``.
    """
    if tier == TIER_PAPER and (vals[7] != 0.0 or vals[8] != 0.0):
        # With body forces the tiers' thresholds differ (by 1 % typically, up to a factor
        # 20 on the benchmark's mixed set); a bracket around the relative one was measured
        # 10-15 % slower than the plain search there, so the search runs directly.
        return math.nan, _SEARCH
    kc = kernel_constants(vals[0], vals[1], vals[2], vals[3], vals[4], raw[8], raw[9],
                          vals[5], vals[6], vals[7], vals[8])
    w, ok = _relative_candidate(kc, vals, raw, body, particle_slip, max_iter)
    if not ok or not w > 0.0 or math.isinf(w):
        return math.nan, _SEARCH
    own = tier != TIER_PAPER and not (body and particle_slip)
    delta = NUDGE * rtol
    for _ in range(2):
        hi = w * (1.0 + delta)
        if not _check_sticks(own, kc, vals, raw, hi, tier, body, particle_slip, empty):
            lo = hi * (1.0 - rtol)
            if _check_sticks(own, kc, vals, raw, lo, tier, body, particle_slip, empty):
                return hi, _FOUND
            break
        if tier == TIER_PAPER:
            break  # the tiers differ: no second try, the bracket follows
        delta = 0.25 * rtol
    return _bracket_if_paper(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty)


def _bracket_if_paper(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
    """Mode "paper": :func:`_paper_bracket`; mode "relative": ``(nan, _SEARCH)``. In compiled
    code only; where ``tier`` is a compile-time constant the bracket is compiled for
    "paper" alone."""
    raise NotImplementedError("_bracket_if_paper is called from compiled code only")


@overload(_bracket_if_paper, prefer_literal=True, inline="always")
def _bracket_if_paper_impl(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
    def paper(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
        return _paper_bracket(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty)

    def relative(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
        return math.nan, _SEARCH

    def either(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
        if tier != TIER_PAPER:
            return math.nan, _SEARCH
        return _paper_bracket(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty)

    if isinstance(tier, types.IntegerLiteral):
        return paper if tier.literal_value == TIER_PAPER else relative
    return either


@njit(cache=CACHE, inline="always")
def _viscous_bound(m_i, m_j, r, H0, Ha, mu_l):
    """:func:`viscous_lower_bound` of one collision [m/s]: at or below it every tier sticks."""
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    m_r, _, _ = reduced_mass(m_i, m_j)
    return c * -ln_f_diff(H0, Ha, a2) / m_r


@njit(cache=CACHE, inline="always")
def _bisect(lo, hi, steps, vals, raw, tier, body, particle_slip, rtol, empty):
    """Bisect in ``ln w`` between a sticking ``lo`` and a rebounding ``hi`` [m/s] until
    ``hi - lo <= rtol hi`` (at most ``steps`` halvings); returns the rebounding end."""
    for _ in range(steps):
        if hi - lo <= rtol * hi:
            break
        mid = math.sqrt(lo) * math.sqrt(hi)
        if _sticks(vals, raw, mid, tier, body, particle_slip, empty):
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=CACHE)
def _paper_bracket(w, vals, raw, tier, body, particle_slip, rtol, w_max, empty):
    """Mode "paper" from the relative threshold ``w`` [m/s]: a bracket around it widened
    geometrically until it holds, then bisection in ``ln w`` (:func:`_from_candidate`)."""
    w_vis = _viscous_bound(vals[0], vals[1], vals[2], vals[3], vals[4], raw[8])
    g = BRACKET
    if _sticks(vals, raw, w, tier, body, particle_slip, empty):
        lo, hi = w, w * g
        for _ in range(MAX_DOUBLINGS):
            if lo >= w_max:
                return math.inf, _ABOVE
            if not _sticks(vals, raw, hi, tier, body, particle_slip, empty):
                break
            lo = hi
            g = min(g * g, 2.0)
            hi = lo * g
        else:
            return math.inf, _ABOVE
    else:
        hi, lo = w, w / g
        for _ in range(MAX_DOUBLINGS):
            if lo <= w_vis:
                lo = w_vis  # sticks in every tier
                break
            if _sticks(vals, raw, lo, tier, body, particle_slip, empty):
                break
            hi = lo
            g = min(g * g, 2.0)
            lo = hi / g
        else:
            return math.nan, _SEARCH
    return _bisect(lo, hi, 200, vals, raw, tier, body, particle_slip, rtol, empty), _BRACKETED


@njit(cache=CACHE)
def _search_one(vals, raw, tier, body, particle_slip, rtol, u_max, empty):
    """u0* [m/s] of collision ``q`` (a bridge, ``e > 0``, ``Ha > 0``) by the search of
    :func:`first_rebound_speed`, run to this collision's own convergence; ``inf`` where it
    exceeds ``u_max`` [m/s] (the search stops as soon as every speed up to ``u_max`` is
    known to stick)."""
    w_per_u0 = vals[10]
    # 1. Double from the viscous bound (which sticks) until a rebound.
    hi = max(_viscous_bound(vals[0], vals[1], vals[2], vals[3], vals[4], raw[8]), MIN_SPEED)
    w_max = u_max * w_per_u0
    found = False
    for _ in range(MAX_DOUBLINGS):
        hi *= 2.0
        if 0.5 * hi >= w_max:  # every speed up to w_max sticks: u0* > u_max
            return math.inf
        if not _sticks(vals, raw, hi, tier, body, particle_slip, empty):
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
        if not _sticks(vals, raw, g, tier, body, particle_slip, empty):
            top = g
            break
        lo = g
    # 3. Bisect in ln w between a sticking lo and a rebounding hi.
    hi = _bisect(lo, top, 64, vals, raw, tier, body, particle_slip, rtol, empty)
    u_star = hi / w_per_u0
    return u_star if u_star <= u_max else math.inf


@njit(parallel=True, cache=CACHE)
def _solve_parallel(ins, st, tier, body, particle_slip, rtol, u_max, closed, max_iter, out,
                    how):
    empty = np.empty(0)
    for q in prange(out.shape[0]):
        out[q], how[q] = _solve_one(_raw(ins, st, q), tier, body, particle_slip, rtol,
                                    u_max, closed, max_iter, empty)


@njit(cache=CACHE)
def _solve_serial(ins, st, tier, body, particle_slip, rtol, u_max, closed, max_iter, out,
                  how):
    empty = np.empty(0)
    for q in range(out.shape[0]):
        out[q], how[q] = _solve_one(_raw(ins, st, q), tier, body, particle_slip, rtol,
                                    u_max, closed, max_iter, empty)


# One pair of entry points per tier, the tier a compile-time constant: only that tier's
# kernel and search are compiled (fused.tier_kernel, _bracket_if_paper).


@njit(cache=CACHE)
def _solve_serial_paper(ins, st, body, particle_slip, rtol, u_max, closed, max_iter, out, how):
    _solve_serial(ins, st, TIER_PAPER, body, particle_slip, rtol, u_max, closed, max_iter, out,
                  how)


@njit(cache=CACHE)
def _solve_serial_relative(ins, st, body, particle_slip, rtol, u_max, closed, max_iter, out,
                           how):
    _solve_serial(ins, st, TIER_RELATIVE, body, particle_slip, rtol, u_max, closed, max_iter,
                  out, how)


@njit(cache=CACHE)
def _solve_parallel_paper(ins, st, body, particle_slip, rtol, u_max, closed, max_iter, out,
                          how):
    _solve_parallel(ins, st, TIER_PAPER, body, particle_slip, rtol, u_max, closed, max_iter,
                    out, how)


@njit(cache=CACHE)
def _solve_parallel_relative(ins, st, body, particle_slip, rtol, u_max, closed, max_iter, out,
                             how):
    _solve_parallel(ins, st, TIER_RELATIVE, body, particle_slip, rtol, u_max, closed, max_iter,
                    out, how)


#: (tier, parallel) -> the solver's entry point.
_SOLVE_ENTRY = {(TIER_PAPER, False): _solve_serial_paper,
                (TIER_RELATIVE, False): _solve_serial_relative,
                (TIER_PAPER, True): _solve_parallel_paper,
                (TIER_RELATIVE, True): _solve_parallel_relative}


def critical_speeds(ins, steps, n, tier, body, particle_slip, rtol, u_max=math.inf,
                    closed_form=True, max_iter=MAX_ITER, return_how=False):
    """Head-on u0* [m/s] of ``n`` collisions given as the fused kernels' inputs
    (:mod:`.fused`), for ``tier`` ``fused.TIER_PAPER`` or ``fused.TIER_RELATIVE``.

    Per collision, compiled, each to its own convergence (a collision's u0* does not depend
    on the rest of the batch):

    - ``closed_form`` (default): the near-closed-form threshold of mode "relative"
      (:mod:`.critical_relative`, Newton limited to ``max_iter`` steps), checked with the
      tier's kernel: it must rebound at the answer ``hi`` and stick at ``hi (1 - rtol)``.
      Mode "paper" takes it only without body forces (the tiers then agree), with a bracket
      around it should the check fail (:func:`_from_candidate`);
    - otherwise, and wherever the candidate fails, the search of
      :func:`first_rebound_speed` (doubling from the viscous bound, a 16-point geometric
      scan of the last doubling, bisection in ``ln w`` to ``rtol``).

    Either way the answer ``hi`` rebounds and ``hi (1 - rtol)`` sticks. ``inf`` where u0*
    exceeds ``u_max`` [m/s]. ``return_how``: also return an int8 array of
    :data:`HOW_TRIVIAL`, :data:`HOW_CLOSED`, :data:`HOW_BRACKET` or :data:`HOW_SEARCH` per
    collision.
    """
    out = np.empty(n)
    how = np.empty(n, dtype=np.int8)
    args = (ins, steps, bool(body), bool(particle_slip), float(rtol), float(u_max),
            bool(closed_form), int(max_iter), out, how)
    if n < SERIAL_BELOW // 4:
        _SOLVE_ENTRY[int(tier), False](*args)
    else:
        parallel_launch(_SOLVE_ENTRY[int(tier), True], *args)
    return (out, how) if return_how else out
