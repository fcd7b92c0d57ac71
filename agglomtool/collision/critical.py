"""The critical impact speed: the smallest relative speed at which a pair rebounds.

One bracketed search (doubling from the viscous bound, a geometric scan of the last
doubling, bisection in ``ln w``), written once as a compiled state machine per collision
(:class:`Search`, :func:`search_from_bound`, :func:`search_update`), driven by two solvers:

- :func:`first_rebound_speed`, for any tier: the machine stepped over a batch, every step
  evaluating a kernel on all elements still searching at once, each to its own
  convergence;
- :func:`critical_speeds`, compiled, per collision, for the fused tiers: mode "relative"
  from its near-closed form (:mod:`.critical_relative`) checked with the kernel (at two
  speeds that share the kernel's speed-independent work with each other and with the
  threshold: :func:`.critical_relative.kernel_e_w`, bitwise the kernel), mode "paper"
  from the same value where it has no body forces (checked with its own kernel, and
  bracketed where the check fails: :func:`search_from_candidate`); each falls back to the
  search where the check fails.
"""

from __future__ import annotations

import math
from typing import NamedTuple, get_type_hints

import numpy as np
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from .bridge import ln_f_diff
from .critical_relative import (
    EARLY_RTOL,
    MAX_ITER,
    OK,
    NewtonOptions,
    kernel_constants,
    kernel_e_w,
    threshold_from,
)
from .fused import SERIAL_BELOW, TIER_PAPER, TIER_RELATIVE, prepare_one, tier_kernel
from .records import Pair, RawPair
from .relative import reduced_mass

__all__ = ["first_rebound_speed", "critical_speeds", "Search", "SearchLimits",
           "search_from_bound", "search_from_candidate", "search_update"]

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


# ---- the search, written once: a state machine per collision ----------------------------
#
# A search's next trial speed depends only on what the collision did at the speeds it
# tried before, so the search is a small state machine: a start (:func:`search_from_bound`,
# or :func:`search_from_candidate` in mode "paper"), the speed to try next (``Search.w``)
# and :func:`search_update` with whether the pair stuck there, until ``phase`` is
# ``DONE``. The compiled solver drives it per collision (:func:`_run`);
# :func:`first_rebound_speed` drives the same machine over a batch (:func:`_batch_step`
# between batched evaluations of a tier's numpy kernel). Either way each collision
# converges on its own: its answer does not depend on what else is in the batch.

#: How each u0* was found (:func:`critical_speeds` ``how``): no search needed (no bridge,
#: ``e = 0``, ``Ha = 0``); the closed-form candidate verified by the kernel; a bracket
#: around it (mode "paper"); the full search (the candidate failed or was not asked for).
HOW_TRIVIAL, HOW_CLOSED, HOW_BRACKET, HOW_SEARCH = 0, 1, 2, 3

#: A search's phases: doubling from the viscous bound, scanning the last doubling on
#: :data:`FINE_POINTS` geometric points, bisecting in ``ln w``; mode "paper": trying the
#: candidate, widening a bracket around it upwards or downwards; done.
DOUBLE, SCAN, BISECT, CANDIDATE, WIDEN_UP, WIDEN_DOWN, DONE = 0, 1, 2, 3, 4, 5, 6
#: Halvings allowed to the bisection after the scan, and after the bracket of mode "paper".
SEARCH_BISECTIONS, BRACKET_BISECTIONS = 64, 200

class Search(NamedTuple):
    """The state of one collision's search (relative speeds)."""

    #: one of :data:`DOUBLE` ... :data:`DONE`
    phase: int
    #: the speed known to stick [m/s]
    lo: float
    #: the speed known to rebound [m/s] (while doubling and scanning: the doubling's last)
    hi: float
    #: the speed to try next [m/s]; once ``DONE``, the answer (``inf``: every speed up to
    #: ``w_max`` sticks, or none rebounds at all)
    w: float
    #: steps taken in the phase (doublings, scan points, halvings, widenings)
    k: int
    #: the bracket's widening factor [-] (mode "paper")
    g: float
    #: how it started: :data:`HOW_SEARCH` or :data:`HOW_BRACKET`
    origin: int


class SearchLimits(NamedTuple):
    """What bounds one collision's search, fixed while it runs."""

    #: the viscous bound [m/s] (:func:`_viscous_bound`: every speed up to it sticks in
    #: every tier)
    w_vis: float
    #: the ceiling [m/s]: the search ends with ``inf`` as soon as every speed up to it is
    #: known to stick
    w_max: float
    #: the bisection's relative tolerance [-]
    rtol: float


#: A batch of searches as a record array (:func:`first_rebound_speed`): one field per
#: field of :class:`Search`.
_STATE_DTYPE = np.dtype([(name, {int: np.int64, float: np.float64}[kind])
                         for name, kind in get_type_hints(Search).items()])


@njit(cache=CACHE, inline="always")
def _viscous_bound(m_i, m_j, r, H0, Ha, mu_l):
    """Relative speed [m/s] at or below which viscosity alone stops any approach.

    The approach needs ``m_r w > c (ln f(H0) - ln f(Ha))`` (Eqs. 73, 80 with the common CM
    momentum ``m_r w``); body and capillary forces do not enter that test, so every speed up
    to this bound sticks, whatever the model tier built on the paper's losses.
    """
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    m_r, _, _ = reduced_mass(m_i, m_j)
    return c * -ln_f_diff(H0, Ha, a2) / m_r


@njit(cache=CACHE)
def _finished(s, w):
    """``s`` done with the answer ``w`` [m/s]."""
    return Search(phase=DONE, lo=s.lo, hi=s.hi, w=w, k=s.k, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def _doubling(s, lim):
    """The next doubling of ``s.hi``; done with ``inf`` once every speed up to ``w_max`` is
    known to stick, or after :data:`MAX_DOUBLINGS`."""
    if s.k >= MAX_DOUBLINGS:
        return _finished(s, math.inf)
    hi = s.hi * 2.0
    if 0.5 * hi >= lim.w_max:
        return _finished(s, math.inf)
    return Search(phase=DOUBLE, lo=s.lo, hi=hi, w=hi, k=s.k + 1, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def _scanning(s, lim):
    """Point ``s.k`` of the scan of the last doubling ``(hi/2, hi]``; past the last point
    below ``hi`` (which rebounded), the bisection from ``s.lo``."""
    if s.k >= FINE_POINTS:
        return _bisecting(s, s.lo, s.hi, 0, lim)
    w = 0.5 * s.hi * 2.0 ** (s.k / FINE_POINTS)
    return Search(phase=SCAN, lo=s.lo, hi=s.hi, w=w, k=s.k, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def _bisecting(s, lo, hi, k, lim):
    """Halving ``k`` of the bisection in ``ln w`` between a sticking ``lo`` and a rebounding
    ``hi``; done with ``hi`` once ``hi - lo <= rtol hi`` or the halvings allowed are used."""
    steps = BRACKET_BISECTIONS if s.origin == HOW_BRACKET else SEARCH_BISECTIONS
    if k >= steps or hi - lo <= lim.rtol * hi:
        return Search(phase=DONE, lo=lo, hi=hi, w=hi, k=k, g=s.g, origin=s.origin)
    mid = math.sqrt(lo) * math.sqrt(hi)  # no underflow of lo * hi at tiny speeds
    return Search(phase=BISECT, lo=lo, hi=hi, w=mid, k=k, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def _widening_up(s, lo, hi, k, lim):
    """Mode "paper", the candidate stuck: try ``hi`` above the sticking ``lo``; done with
    ``inf`` once ``lo`` reaches ``w_max`` or after :data:`MAX_DOUBLINGS` widenings."""
    if k >= MAX_DOUBLINGS or lo >= lim.w_max:
        return Search(phase=DONE, lo=lo, hi=hi, w=math.inf, k=k, g=s.g, origin=s.origin)
    return Search(phase=WIDEN_UP, lo=lo, hi=hi, w=hi, k=k, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def _widening_down(s, lo, hi, k, lim):
    """Mode "paper", the candidate rebounded: try ``lo`` below the rebounding ``hi``; at or
    below the viscous bound the bound itself (it sticks in every tier) and the bisection;
    after :data:`MAX_DOUBLINGS` widenings the search from the bound instead."""
    if k >= MAX_DOUBLINGS:
        return search_from_bound(lim)
    if lo <= lim.w_vis:
        return _bisecting(s, lim.w_vis, hi, 0, lim)
    return Search(phase=WIDEN_DOWN, lo=lo, hi=hi, w=lo, k=k, g=s.g, origin=s.origin)


@njit(cache=CACHE)
def search_from_bound(lim):
    """A search that doubles from the viscous bound (which sticks) until a rebound, scans
    the last doubling on :data:`FINE_POINTS` geometric points and bisects in ``ln w``
    between the last sticking and the first rebounding point. It starts from the bound
    itself, however small (a bridge barely thicker than the asperities can rebound at any
    practical speed); where ``H0`` and ``Ha`` differ only by rounding the bound can be
    exactly 0, and :data:`MIN_SPEED` stands in."""
    s = Search(phase=DOUBLE, lo=0.0, hi=max(lim.w_vis, MIN_SPEED), w=math.nan, k=0,
               g=BRACKET, origin=HOW_SEARCH)
    return _doubling(s, lim)


@njit(cache=CACHE)
def search_from_candidate(w):
    """Mode "paper" from the relative tier's threshold ``w`` [m/s]: a bracket around it,
    widened geometrically (factor :data:`BRACKET`, squared at each widening, at most 2)
    until its bottom sticks and its top rebounds, never below the viscous bound; then the
    bisection in ``ln w``."""
    return Search(phase=CANDIDATE, lo=math.nan, hi=math.nan, w=w, k=0, g=BRACKET,
                  origin=HOW_BRACKET)


@njit(cache=CACHE)
def search_update(s, sticks, lim):
    """The state after trying ``s.w``: ``sticks`` tells whether the pair stuck there."""
    phase = s.phase
    if phase == DOUBLE:
        if sticks:
            return _doubling(s, lim)
        # below hi/2 lies the previous doubling, which stuck
        return _scanning(Search(phase=SCAN, lo=0.5 * s.hi, hi=s.hi, w=math.nan, k=1, g=s.g,
                                origin=s.origin), lim)
    if phase == SCAN:
        if sticks:
            return _scanning(Search(phase=SCAN, lo=s.w, hi=s.hi, w=math.nan, k=s.k + 1,
                                    g=s.g, origin=s.origin), lim)
        return _bisecting(s, s.lo, s.w, 0, lim)
    if phase == BISECT:
        if sticks:
            return _bisecting(s, s.w, s.hi, s.k + 1, lim)
        return _bisecting(s, s.lo, s.w, s.k + 1, lim)
    if phase == CANDIDATE:
        if sticks:
            return _widening_up(s, s.w, s.w * s.g, 0, lim)
        return _widening_down(s, s.w / s.g, s.w, 0, lim)
    if phase == WIDEN_UP:
        if not sticks:
            return _bisecting(s, s.lo, s.hi, 0, lim)
        g = min(s.g * s.g, 2.0)
        t = Search(phase=WIDEN_UP, lo=s.lo, hi=s.hi, w=s.w, k=s.k, g=g, origin=s.origin)
        return _widening_up(t, s.hi, s.hi * g, s.k + 1, lim)
    if phase == WIDEN_DOWN:
        if sticks:
            return _bisecting(s, s.lo, s.hi, 0, lim)
        g = min(s.g * s.g, 2.0)
        t = Search(phase=WIDEN_DOWN, lo=s.lo, hi=s.hi, w=s.w, k=s.k, g=g, origin=s.origin)
        return _widening_down(t, s.lo / g, s.lo, s.k + 1, lim)
    return s


@njit(cache=CACHE, inline="always")
def _load(rec):
    """The :class:`Search` held in a record of :data:`_STATE_DTYPE`."""
    return Search(phase=rec.phase, lo=rec.lo, hi=rec.hi, w=rec.w, k=rec.k, g=rec.g,
                  origin=rec.origin)


@njit(cache=CACHE, inline="always")
def _store(rec, s):
    rec.phase, rec.lo, rec.hi, rec.w = s.phase, s.lo, s.hi, s.w
    rec.k, rec.g, rec.origin = s.k, s.g, s.origin


@njit(cache=CACHE)
def _trials(s, lim, out, at):
    """The speeds [m/s] that search ``s`` tries next, written to ``out[at:]``; returns how
    many. One speed; in the scan, the rest of the scan as far as the pair keeps sticking
    (the machine itself, fed "sticks", gives them): a batch then tries a whole scan in one
    kernel call."""
    n = 0
    t = s
    while True:
        out[at + n] = t.w
        n += 1
        if t.phase != SCAN:
            return n
        t = search_update(t, True, lim)
        if t.phase != SCAN:
            return n


@njit(cache=CACHE)
def _batch_trials(states, idx, w_vis, w_max, rtol):
    """The elements among ``idx`` still searching (``keep``), where the speeds of each
    begin in the flat arrays (``starts``, one more than ``keep``), the element of each speed
    (``which``) and the speeds [m/s] (``w``): :func:`_trials`."""
    keep = np.empty(idx.size, dtype=np.int64)
    starts = np.empty(idx.size + 1, dtype=np.int64)
    w = np.empty(idx.size * FINE_POINTS)
    n = 0
    m = 0
    for q in idx:
        s = _load(states[q])
        if s.phase == DONE:
            continue
        keep[n] = q
        starts[n] = m
        m += _trials(s, SearchLimits(w_vis=w_vis[q], w_max=w_max[q], rtol=rtol), w, m)
        n += 1
    starts[n] = m
    which = np.empty(m, dtype=np.int64)
    for a in range(n):
        which[starts[a]:starts[a + 1]] = keep[a]
    return keep[:n], starts[:n + 1], which, w[:m]


@njit(cache=CACHE)
def _batch_start(states, w_vis, w_max, rtol):
    """Start every search of a batch from its viscous bound ``w_vis`` [m/s] (ceilings
    ``w_max`` [m/s]); returns :func:`_batch_trials` of all."""
    for q in range(states.size):
        _store(states[q], search_from_bound(SearchLimits(w_vis=w_vis[q], w_max=w_max[q],
                                                         rtol=rtol)))
    return _batch_trials(states, np.arange(states.size), w_vis, w_max, rtol)


@njit(cache=CACHE)
def _batch_step(states, trials, sticks, w_vis, w_max, rtol):
    """:func:`search_update` of the elements of ``trials`` (:func:`_batch_trials`), which
    stuck where ``sticks``: each element's results fed in order for as long as the speed is
    the one its search asks for (the rest of a scan after a rebound is dropped); returns
    :func:`_batch_trials` of them."""
    keep, starts, _, w = trials
    for a in range(keep.size):
        q = keep[a]
        lim = SearchLimits(w_vis=w_vis[q], w_max=w_max[q], rtol=rtol)
        s = _load(states[q])
        for j in range(starts[a], starts[a + 1]):
            if s.phase == DONE or s.w != w[j]:
                break
            s = search_update(s, sticks[j], lim)
        _store(states[q], s)
    return _batch_trials(states, keep, w_vis, w_max, rtol)


@njit(cache=CACHE)
def _viscous_bounds(m_i, m_j, r, H0, Ha, mu_l):
    """:func:`_viscous_bound` of each element of flat arrays."""
    out = np.empty(m_i.size)
    for q in range(m_i.size):
        out[q] = _viscous_bound(m_i[q], m_j[q], r[q], H0[q], Ha[q], mu_l[q])
    return out


def first_rebound_speed(state, sticks, rtol, w_max=math.inf):
    """Smallest relative speed ``w`` [m/s] at which ``sticks(w, idx)`` turns false, by the
    search of :func:`search_from_bound` run over the batch: every step tries the next speed
    of each element still searching (the rest of its scan, where it scans) in one call of
    ``sticks``, each element to its own convergence (its answer does not depend on the rest
    of the batch, and equals the compiled solver's for the same verdicts).

    ``state`` carries flat arrays ``m_i, m_j, r, H0, Ha, mu_l, e``; ``sticks(w, idx)``
    evaluates the elements ``idx`` (an index array) at speeds ``w`` and returns a boolean
    array. ``w_max`` [m/s] (a number or one per element): an element's search ends with
    ``inf`` as soon as every speed up to it is known to stick. Returns a flat array: ``inf``
    where the pair never rebounds (``e = 0``, or a zero total asperity height) or not up to
    ``w_max``, 0 where no bridge forms and ``e > 0``.
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
    f = np.ascontiguousarray
    w_vis = _viscous_bounds(f(m_i[active]), f(m_j[active]), f(r[active]), f(H0[active]),
                            f(Ha[active]), f(mu_l[active]))
    w_top = f(np.broadcast_to(np.asarray(w_max, dtype=float), (n,))[active])
    states = np.empty(active.size, dtype=_STATE_DTYPE)
    rtol = float(rtol)
    trials = _batch_start(states, w_vis, w_top, rtol)
    while trials[0].size:
        _, _, which, w = trials
        stuck = f(sticks(w, active[which]), dtype=np.bool_)
        trials = _batch_step(states, trials, stuck, w_vis, w_top, rtol)
    out[active] = states["w"]
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
    ew, _, _ = tier_kernel(tier, Pair(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i,
                                      fn_j, e), w_rel, empty)
    return ew == 0.0


@njit(cache=CACHE, inline="always")
def _raw(ins, st, q):
    """The raw inputs of collision ``q`` as a :class:`.records.RawPair` of floats (its
    fields also read by position): the solver's helpers take it instead of the arrays
    themselves (passing the tuple of 20 arrays to a function that is not inlined costs a
    reference-count update per array and call)."""
    return RawPair(
        ins[0][q * st[0]], ins[1][q * st[1]], ins[2][q * st[2]], ins[3][q * st[3]],
        ins[4][q * st[4]], ins[5][q * st[5]], ins[6][q * st[6]], ins[7][q * st[7]],
        ins[8][q * st[8]], ins[9][q * st[9]], ins[10][q * st[10]], ins[11][q * st[11]],
        ins[12][q * st[12]], ins[13][q * st[13]], ins[14][q * st[14]], ins[15][q * st[15]],
        ins[16][q * st[16]], ins[17][q * st[17]],
    )


@njit(cache=CACHE)
def _prep(raw, u, body, particle_slip):
    """:func:`.fused.prepare_one` of a head-on collision at lab speed ``u`` [m/s]."""
    return prepare_one(raw, u, math.nan, body, particle_slip)


class SolveOptions(NamedTuple):
    """The compiled solver's options (:func:`critical_speeds`), one record for a batch."""

    #: weight, buoyancy and drag on
    body: bool
    #: the drag's slip is the particle's own speed (re-evaluated at every trial speed)
    particle_slip: bool
    #: the answer's relative tolerance [-]
    rtol: float
    #: the ceiling [m/s]
    u_max: float
    #: start from the near-closed form of mode "relative"
    closed: bool
    #: its Newton evaluations at most
    max_iter: int


@njit(cache=CACHE)
def _run(s, lim, vals, raw, tier, opts, empty):
    """The search ``s`` of one collision driven to its end, each speed tried with the
    ``tier``'s kernel (:func:`_sticks`)."""
    body, particle_slip = opts.body, opts.particle_slip
    while s.phase != DONE:
        s = search_update(s, _sticks(vals, raw, s.w, tier, body, particle_slip, empty), lim)
    return s


@njit(cache=CACHE)
def _solve_one(raw, tier, opts, empty):
    """``(u0*, how)`` of one collision [m/s] (``raw``: its inputs, :func:`_raw`; ``opts``:
    :class:`SolveOptions`); ``inf`` where it exceeds ``opts.u_max`` [m/s].

    ``opts.closed``: start from the near-closed form of mode "relative"
    (:func:`.critical_relative.relative_threshold`) and verify it with the kernel
    (:func:`_from_candidate`); where that fails, mode "paper" brackets the candidate
    (:func:`search_from_candidate`) and mode "relative" searches from the viscous bound
    (:func:`search_from_bound`), as does every collision without ``closed``. ``empty``: a
    length-0 array (the kernels' "no details").
    """
    vals = _prep(raw, 0.0, opts.body, opts.particle_slip)
    H0, Ha = vals[3], vals[4]
    w_per_u0 = vals[10]
    u_max = opts.u_max
    e = raw[17]
    if not H0 > Ha:
        return (0.0 if e > 0.0 else math.inf), HOW_TRIVIAL
    if e == 0.0 or Ha == 0.0:
        return math.inf, HOW_TRIVIAL
    start = _SEARCH
    w = math.nan
    if opts.closed:
        w, start = _from_candidate(vals, raw, tier, opts, empty)
        if start == _FOUND:
            u_star = w / w_per_u0
            return (u_star if u_star <= u_max else math.inf), HOW_CLOSED
    lim = SearchLimits(w_vis=_viscous_bound(vals[0], vals[1], vals[2], H0, Ha, raw[8]),
                       w_max=u_max * w_per_u0, rtol=opts.rtol)
    s = search_from_candidate(w) if start == _BRACKET else search_from_bound(lim)
    s = _run(s, lim, vals, raw, tier, opts, empty)
    u_star = s.w / w_per_u0
    return (u_star if u_star <= u_max else math.inf), s.origin


#: Outcomes of :func:`_from_candidate`: the answer; bracket the candidate (mode "paper");
#: search from the viscous bound.
_FOUND, _BRACKET, _SEARCH = 0, 1, 2


@njit(cache=CACHE, inline="always")
def _relative_candidate(kc, vals, raw, opts):
    """``(w*, ok)``: the near-closed-form threshold of mode "relative" [m/s] from the
    collision's kernel constants ``kc`` at zero speed. Where the drag depends on the
    particles' own speed (``drag_slip="particle"``) the body forces are re-evaluated at the
    candidate until it moves by less than :data:`SLIP_RTOL` (at most :data:`SLIP_ITER`
    rounds)."""
    m_i, m_j, r, H0, Ha, cos_t, theta, _, _, _, w_per_u0 = vals
    mu_l = raw[8]
    gamma = raw[9]
    e = raw[17]
    body, particle_slip, max_iter = opts.body, opts.particle_slip, opts.max_iter
    slip = body and particle_slip
    early = SLIP_EARLY_RTOL if slip else EARLY_RTOL
    newton = NewtonOptions(max_iter=max_iter, early_rtol=early)
    w, status = threshold_from(kc, H0, Ha, mu_l, gamma, theta, e, newton)
    if not slip or status != OK:
        return w, status == OK
    for _ in range(SLIP_ITER):
        pre = _prep(raw, w / w_per_u0, body, particle_slip)
        kc_w = kernel_constants(Pair(m_i=m_i, m_j=m_j, r=r, H0=H0, Ha=Ha, mu_l=mu_l,
                                     gamma=gamma, cos_t=cos_t, theta=theta, fn_i=pre[7],
                                     fn_j=pre[8], e=e))
        w_new, status = threshold_from(kc_w, H0, Ha, mu_l, gamma, theta, e, newton)
        if status != OK:
            return math.nan, False
        if abs(w_new - w) <= SLIP_RTOL * w_new:
            return w_new, True
        w = w_new
    return math.nan, False


@njit(cache=CACHE, inline="always")
def _check_sticks(own, kc, vals, raw, w_rel, tier, opts, empty):
    """:func:`_sticks` at ``w_rel`` [m/s]; with ``own`` (mode "relative", body forces that
    do not depend on the speed) from the kernel's speed-independent numbers ``kc``
    (:func:`.critical_relative.kernel_e_w`, bitwise the kernel's ``e_w``)."""
    if own:
        return kernel_e_w(kc, vals[3], vals[4], raw[8], raw[9], vals[6], raw[17],
                          w_rel) == 0.0
    return _sticks(vals, raw, w_rel, tier, opts.body, opts.particle_slip, empty)


@njit(cache=CACHE)
def _from_candidate(vals, raw, tier, opts, empty):
    """``(w*, status)`` from the relative tier's near-closed form, checked with the
    ``tier``'s own kernel; status ``_FOUND``, ``_BRACKET`` (mode "paper": no verified
    answer, bracket the candidate ``w*``) or ``_SEARCH`` (no verified answer: search from
    the viscous bound).

    The answer ``hi`` always satisfies the search's own contract: the kernel rebounds at
    ``hi`` and sticks at ``hi (1 - rtol)``.

    - ``relative``: ``hi = w* (1 + delta)``, ``delta`` = :data:`NUDGE` ``rtol`` (then
      ``rtol / 4``, should rounding in the kernel put its switch a little above ``w*``);
      anything else goes to the search. Where the body forces do not depend on the speed
      the two kernel evaluations share its speed-independent work with each other and
      with the threshold (:func:`.critical_relative.kernel_e_w`, the kernel's arithmetic
      bitwise);
    - ``paper``: with body forces, ``_SEARCH`` at once (see the code); without, the same
      check first (the tiers then agree to rounding); else ``_BRACKET``
      (:func:`search_from_candidate`).
    """
    if tier == TIER_PAPER and (vals[7] != 0.0 or vals[8] != 0.0):
        # With body forces the tiers' thresholds differ (by 1 % typically, up to a factor
        # 20 on the benchmark's mixed set); a bracket around the relative one was measured
        # 10-15 % slower than the plain search there, so the search runs directly.
        return math.nan, _SEARCH
    kc = kernel_constants(Pair(m_i=vals[0], m_j=vals[1], r=vals[2], H0=vals[3], Ha=vals[4],
                               mu_l=raw[8], gamma=raw[9], cos_t=vals[5], theta=vals[6],
                               fn_i=vals[7], fn_j=vals[8], e=raw[17]))
    w, ok = _relative_candidate(kc, vals, raw, opts)
    if not ok or not w > 0.0 or math.isinf(w):
        return math.nan, _SEARCH
    own = tier != TIER_PAPER and not (opts.body and opts.particle_slip)
    rtol = opts.rtol
    delta = NUDGE * rtol
    for _ in range(2):
        hi = w * (1.0 + delta)
        if not _check_sticks(own, kc, vals, raw, hi, tier, opts, empty):
            lo = hi * (1.0 - rtol)
            if _check_sticks(own, kc, vals, raw, lo, tier, opts, empty):
                return hi, _FOUND
            break
        if tier == TIER_PAPER:
            break  # the tiers differ: no second try, the bracket follows
        delta = 0.25 * rtol
    return w, (_BRACKET if tier == TIER_PAPER else _SEARCH)


@njit(parallel=True, cache=CACHE)
def _solve_parallel(ins, st, tier, opts, out, how):
    empty = np.empty(0)
    for q in prange(out.shape[0]):
        out[q], how[q] = _solve_one(_raw(ins, st, q), tier, opts, empty)


@njit(cache=CACHE)
def _solve_serial(ins, st, tier, opts, out, how):
    empty = np.empty(0)
    for q in range(out.shape[0]):
        out[q], how[q] = _solve_one(_raw(ins, st, q), tier, opts, empty)


# One pair of entry points per tier, the tier a compile-time constant: only that tier's
# kernel is compiled (fused.tier_kernel).


@njit(cache=CACHE)
def _solve_serial_paper(ins, st, opts, out, how):
    _solve_serial(ins, st, TIER_PAPER, opts, out, how)


@njit(cache=CACHE)
def _solve_serial_relative(ins, st, opts, out, how):
    _solve_serial(ins, st, TIER_RELATIVE, opts, out, how)


@njit(cache=CACHE)
def _solve_parallel_paper(ins, st, opts, out, how):
    _solve_parallel(ins, st, TIER_PAPER, opts, out, how)


@njit(cache=CACHE)
def _solve_parallel_relative(ins, st, opts, out, how):
    _solve_parallel(ins, st, TIER_RELATIVE, opts, out, how)


#: (tier, parallel) -> the solver's entry point.
_SOLVE_ENTRY = {(TIER_PAPER, False): _solve_serial_paper,
                (TIER_RELATIVE, False): _solve_serial_relative,
                (TIER_PAPER, True): _solve_parallel_paper,
                (TIER_RELATIVE, True): _solve_parallel_relative}


def critical_speeds(ins, steps, n, tier, *, body, particle_slip, rtol, u_max=math.inf,
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
    - otherwise, and wherever the candidate fails, the search
      (:func:`search_from_bound`: doubling from the viscous bound, a 16-point geometric
      scan of the last doubling, bisection in ``ln w`` to ``rtol``).

    Either way the answer ``hi`` rebounds and ``hi (1 - rtol)`` sticks. ``inf`` where u0*
    exceeds ``u_max`` [m/s]. ``body``: weight, buoyancy and drag on; ``particle_slip``: the
    drag's slip is the particle's own speed (``drag_slip="particle"``). ``return_how``: also
    return an int8 array of :data:`HOW_TRIVIAL`, :data:`HOW_CLOSED`, :data:`HOW_BRACKET` or
    :data:`HOW_SEARCH` per collision.
    """
    out = np.empty(n)
    how = np.empty(n, dtype=np.int8)
    opts = SolveOptions(body=bool(body), particle_slip=bool(particle_slip), rtol=float(rtol),
                        u_max=float(u_max), closed=bool(closed_form), max_iter=int(max_iter))
    args = (ins, steps, opts, out, how)
    if n < SERIAL_BELOW // 4:
        _SOLVE_ENTRY[int(tier), False](*args)
    else:
        parallel_launch(_SOLVE_ENTRY[int(tier), True], *args)
    return (out, how) if return_how else out
