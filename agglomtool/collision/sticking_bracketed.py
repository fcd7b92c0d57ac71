"""The bracketing of :mod:`.sticking_numeric` in one compiled pass per block.

:mod:`.sticking_numeric` states the method (candidate speeds above ``u0*``, the changes of
the tier's stick indicator between them bisected with the tier's own kernel, the law's CDF
integrated over the sticking pieces) and writes it as batches of numpy over every element
at once: its reference. This module runs the same method element by element inside one
compiled loop, parallel over the elements, for every tier that brackets: modes "paper"
and "relative" with the flags that take them off their closed-form sets (body forces on
the axis in mode "paper", the drag's slip from the particle's own speed), mode "auto"
(its choice of form, and "ode" where it chooses it, at the default tolerance as scenes
run it), and modes "ode" and "ode_selfconsistent" (their integration with the tier's own
settings). The numpy batches are the reference the tests hold this pass to.

The work of one element (:func:`_element` and what it calls for each element:
:func:`_candidates`, :func:`_proof`, :func:`_top`, :func:`_node`, :func:`_f_star`) is
inlined by numba (``inline="always"``) into the loop over the elements: a call of a
compiled function that is not inlined counts a reference up and down (an atomic
operation) for every array it is passed, and copies its records, which cost as much as
the element's own arithmetic where no kernel is evaluated (inlining halved the pass with
``drag_slip = "particle"`` on the benchmarks' water map). Their stores go through local
names or parameters, not a record's attribute: numba 0.68's inlining lost stores made
through a record's attribute (``rows.own_v[j] = ...``) and warned at compile time of
variables "not in scope". The other functions are plain compiled functions (LLVM still
inlines where it pays).

What changes is where the numbers are made, and, in modes "paper" and "relative", which
candidates need a kernel evaluation:

- the candidates are the same speeds (``u0*``, :data:`.sticking_numeric.NEAR` above it,
  mode "relative"'s windows widened by :data:`.sticking_numeric.SEED_OFFSETS`, the law's
  ``N`` equal-probability nodes above ``u0*`` and its top speed), those of the collision
  alone evaluated once per run of consecutive elements of one collision;
- in modes "paper" and "relative" (body forces on the axis, or the drag's slip from the
  particle's own speed) a candidate at or above the lowest speed that
  :mod:`.rebound_proof` proves the collision rebounds from (up to the element's top) is
  taken as a rebound without an evaluation, and the element's row of candidates ends at
  the first such one: all beyond rebound, so they add no piece and no change of verdict.
  The proof may start from the first speed of :data:`.sticking_numeric.NEAR` up; the
  collision's own candidates are evaluated only where an element needs them. The
  candidates kept, the bisections between them and the integral are the method's, so the
  result does not depend on the speed proven. That proof belongs to the collision, not
  to the element: the elements of one run of a collision share it (:func:`_proof`),
  made once up to the run's highest top speed, taken as it is where an element's top
  lies inside it and extended by one more interval where that top lies above. In mode
  "paper" it is then extended downwards, towards the element's first node, through the
  band just above ``u0*`` where one particle stops first in the separation
  (:func:`.rebound_proof.extended_down`): on the benchmarks' water and slag maps with
  ``beta_deg = 90`` that band held most of the evaluations left;
- each change of verdict between adjacent candidates is bisected in the same steps (the
  geometric middle, to :data:`.sticking_numeric.U_RTOL`, at most
  :data:`.sticking_numeric.MAX_BISECTIONS` steps);
- ``P = F(c_0) + sum over the pieces`` as :func:`agglomtool.bed.speeds._bracketed`
  writes it, summed in candidate order.

An element whose verdict is unknown at a candidate, or whose bisection does not settle,
is flagged (not ``ok``) and left to the node quadrature, as in the reference.

The speed laws' quantiles are compiled for the fixed and Maxwellian laws (and the speed
models, which are Maxwellian). The lognormal quantile needs the inverse of the normal
CDF, which only scipy's compiled special functions provide here; a compiled function that
calls them cannot be cached by numba (it holds their address), so the lognormal nodes are
made by scipy beforehand, in chunks, and read by the loop, with ``F(u0*)``. Its CDF
elsewhere (at the candidates and crossings) is written with ``erfc`` in the loop (as
:mod:`.sticking`), which differs from scipy's ``ndtr`` by a few units in the last place;
where nothing sticks above ``u0*``, ``P = F(u0*)`` is scipy's, bitwise the quadrature's.
The Maxwellian nodes are the loop's own (``sqrt(-theta log1p(-q))``), which may lie a unit
in the last place from numpy's: immaterial to ``P`` (1e-16) except in mode
"ode_selfconsistent"'s flicker band above ``u0*``, where a bisection from a node that far
apart may settle on another of the band's many crossings (measured 1.2e-9 on one map of
``benchmarks/bench_bracketing.py``; within that tier's stated bound).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange, types
from numba.core.errors import TypingError
from numba.extending import overload

from .._jit import CACHE, parallel_launch
from .auto import DEFAULT_TOL, _check_tol, _decide, ode_options, ode_rtol
from .critical import _raw
from .fused import TIER_PAPER, TIER_RELATIVE, launch_blocks, prepare_one, slip_flag, tier_kernel
from .ode import DEFAULT_ATOL, DEFAULT_FIRST_STEP, DEFAULT_RTOL, ode_kernel
from .rebound_proof import extended_down, proven_from, rebounds_over
from .records import OdeOptions, Pair
from .sticking import EXACT, FIXED, LOGNORMAL, MAX_WINDOWS, REST_MIN, _cdf, _windows_one
from .sticking_numeric import MAX_BISECTIONS, NEAR, SEED_OFFSETS, TAIL, U_RTOL

__all__ = ["KIND_AUTO", "KIND_ODE", "KIND_ODE_SC", "bracketed_propensity", "kind_of"]

#: The verdict's kernel: the fused tiers' codes, modes "auto", "ode" and
#: "ode_selfconsistent".
KIND_AUTO, KIND_ODE, KIND_ODE_SC = 2, 3, 4
_KINDS = {"auto": KIND_AUTO, "ode": KIND_ODE, "ode_selfconsistent": KIND_ODE_SC}

#: Verdicts: rebounds, sticks, no verdict (NaN ``e_w`` or a failed integration), not yet
#: evaluated.
_REBOUNDS, _STICKS, _UNKNOWN, _TODO = 0, 1, -1, -2
#: :func:`_candidates`' count where every candidate rebounds (no row made)
_NOTHING_STICKS = -2

#: Candidates of a collision alone: ``u0*``, :data:`NEAR`, and per window of mode
#: "relative" its middle, four speeds per end and offset, and one above an open end.
_N_NEAR = len(NEAR)
_SEEDS_PER_WINDOW = 2 + 4 * len(SEED_OFFSETS)
_MAX_OWN = 1 + _N_NEAR + MAX_WINDOWS * _SEEDS_PER_WINDOW


def kind_of(tier):
    """The verdict kind of a tier (a fused tier code, or a mode's name), or None where
    this module does not bracket it (mode "stokes", which needs no bracket)."""
    if isinstance(tier, str):
        return _KINDS.get(tier)
    return int(tier)


def _auto_options():
    o = ode_options(ode_rtol(_check_tol(DEFAULT_TOL)))
    return OdeOptions(o["rtol"], o["atol"], False, True, o["first_step"], o["max_step"],
                      o["first_change"], o["stick_margin"])


def _ode_options(self_consistent):
    """Mode "ode"'s (or "ode_selfconsistent"'s) integration as the tier runs it
    (:func:`.ode.run_ode`'s defaults)."""
    return OdeOptions(DEFAULT_RTOL, DEFAULT_ATOL, self_consistent, True, DEFAULT_FIRST_STEP,
                      math.inf, math.inf, -1.0)


#: Mode "auto"'s integration where it chooses "ode" (its default tolerance, as scenes run
#: it), and modes "ode" and "ode_selfconsistent"'s: constants of the compiled loop.
_AUTO_OPTS = _auto_options()
_ODE_OPTS = _ode_options(False)
_ODE_SC_OPTS = _ode_options(True)


def verdict(kind, pair, w, empty):
    """The stick verdict (:data:`_STICKS`, :data:`_REBOUNDS`, :data:`_UNKNOWN`) of the
    kernel ``kind`` on ``pair`` at relative speed ``w``, in compiled code only."""
    raise NotImplementedError("verdict is called from compiled code only")


@njit(cache=CACHE)
def _code(ew):
    if math.isnan(ew):
        return _UNKNOWN
    return _STICKS if ew == 0.0 else _REBOUNDS


@overload(verdict, prefer_literal=True)
def _verdict(kind, pair, w, empty):
    def auto(kind, pair, w, empty):
        ew, _, _, nq, _ = _decide(pair, w, DEFAULT_TOL, empty)
        if nq == 0:
            ew, _, _, _, status = ode_kernel(pair, w, empty, _AUTO_OPTS)
            if status != 0:
                return _UNKNOWN
        return _code(ew)

    def ode(kind, pair, w, empty):
        ew, _, _, _, status = ode_kernel(pair, w, empty, _ODE_OPTS)
        return _UNKNOWN if status != 0 else _code(ew)

    def ode_sc(kind, pair, w, empty):
        ew, _, _, _, status = ode_kernel(pair, w, empty, _ODE_SC_OPTS)
        return _UNKNOWN if status != 0 else _code(ew)

    def fused(kind, pair, w, empty):
        ew, _, _ = tier_kernel(kind, pair, w, empty)
        return _code(ew)

    if not isinstance(kind, types.IntegerLiteral):
        raise TypingError("verdict: the kind must be a compile-time constant (the entry "
                          "points pass one)")
    return {KIND_AUTO: auto, KIND_ODE: ode, KIND_ODE_SC: ode_sc}.get(kind.literal_value,
                                                                      fused)


class Judge(NamedTuple):
    """How a verdict is reached (made inside the loop from its parts)."""

    #: weight, buoyancy and drag on
    body: bool
    #: the drag's slip is the particle's own speed: ``True``, or ``None`` for false
    particle_slip: object
    #: any array of length 0 (the kernels' details row)
    empty: np.ndarray


class Collision(NamedTuple):
    """One collision of the loop."""

    #: its raw inputs (:class:`.records.RawPair`)
    raw: tuple
    #: :func:`.fused.prepare_one` at speed 0 (used where the forces do not depend on it)
    vals: tuple
    #: its head-on ``u0*`` [m/s]
    u_star: float


class ElementLaw(NamedTuple):
    """The speed law of one element, and its lognormal nodes."""

    #: :data:`.sticking.FIXED`, ``LOGNORMAL`` or ``MAXWELLIAN``
    family: int
    #: the fixed speed, the lognormal median [m/s] or the granular temperature [m2/s2]
    a: float
    #: the lognormal ``sigma_ln`` [-]
    b: float
    #: the lognormal nodes and top speeds, one row per element of the launch
    given: np.ndarray
    #: the element's row of ``given``
    k: int
    #: ``N``, the law's nodes among the candidates
    n_nodes: int


class Scratch(NamedTuple):
    """A thread's rows: the collision's own candidates and an element's."""

    #: the collision's candidate speeds [m/s], sorted, ``u0*`` first
    own: np.ndarray
    #: their verdicts
    own_v: np.ndarray
    #: an element's candidate speeds [m/s]
    cand: np.ndarray
    #: their verdicts
    ver: np.ndarray
    #: mode "relative"'s windows, lower ends [m/s]
    lo: np.ndarray
    #: and upper ends [m/s]
    hi: np.ndarray
    #: the head-on speeds ``[lo, hi]`` over which the collision is proven to rebound
    #: (:func:`_proof`; ``lo = inf``: none yet), the highest top speed of its run of
    #: elements, and the lower end from which mode "paper"'s extension downwards last gave
    #: up (NaN: none) [m/s]
    held: np.ndarray


@njit(cache=CACHE)
def _at(kind, coll, u, judge):
    """The verdict at head-on lab speed ``u`` of ``coll`` (a :class:`Collision`)."""
    raw, vals, _ = coll
    w = u * vals[10]  # u_i + u_j, exactly: 2 u head-on, u against a plate
    if judge.particle_slip:
        if judge.body:  # the drag depends on the speed: prepared at this one
            vals = prepare_one(raw, u, math.nan, judge.body, judge.particle_slip)
            w = vals[9]
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, _ = vals
    pair = Pair(m_i, m_j, r, H0, Ha, raw[8], raw[9], cos_t, theta, fn_i, fn_j, raw[17])
    return verdict(kind, pair, w, judge.empty)


@njit(cache=CACHE)
def _own(kind, coll, judge, rows):
    """The candidates of the collision alone into ``rows.own`` (speeds, sorted; ``rows``:
    a :class:`Scratch`), their verdicts in ``rows.own_v`` left to evaluate
    (:data:`_TODO`: :func:`_candidates` evaluates those an element keeps, once for the
    collision); returns their count. ``u0*`` comes first and is kept whatever its
    verdict."""
    us = coll.u_star
    # the rows as local names: with numba's own inlining of these functions
    # (``inline="always"``, since removed) the stores ``rows.own_v[j] = ...`` were lost
    sp, sv, lo, hi = rows.own, rows.own_v, rows.lo, rows.hi
    k = 0
    sp[k] = us
    k += 1
    for x in NEAR:
        sp[k] = us * (1.0 + x)
        k += 1
    count, status = _windows_one(coll.raw, us, (TIER_RELATIVE, judge.body, None), lo, hi,
                                 judge.empty)
    if status == EXACT:
        for j in range(count):
            a = lo[j]
            b = hi[j] if math.isfinite(hi[j]) else math.nan
            sp[k] = math.sqrt(a) * math.sqrt(b)
            k += 1
            for x in SEED_OFFSETS:
                sp[k] = a * (1.0 - x)
                sp[k + 1] = a * (1.0 + x)
                sp[k + 2] = b * (1.0 - x)
                sp[k + 3] = b * (1.0 + x)
                k += 4
            sp[k] = a * 2.0 if math.isnan(b) else math.nan
            k += 1
    # keep u0*, the speeds NEAR it and the seeds above it (not NaN), sorted (insertion)
    n = 1
    for j in range(1, k):
        s = sp[j]
        if j > _N_NEAR and not s > us:
            continue
        i = n
        while i > 1 and sp[i - 1] > s:
            sp[i] = sp[i - 1]
            i -= 1
        sp[i] = s
        n += 1
    for j in range(n):
        sv[j] = _TODO  # evaluated where an element first needs it (:func:`_candidates`)
    return n


@njit(cache=CACHE)
def _quantile(q, theta):
    """The Maxwellian quantile (as :meth:`agglomtool.bed.speeds.SpeedModel.quantile`)."""
    return math.sqrt(-theta * math.log1p(-q))


@njit(cache=CACHE, inline="always")
def _node(law, j, f_star, rest, top):
    """Node ``j`` of the law above ``u0*`` (``j = n_nodes``: the top speed)."""
    if j == law.n_nodes:
        return top
    if law.family == LOGNORMAL:
        return law.given[law.k, j]
    return _quantile(f_star + rest * ((j + 0.5) / law.n_nodes), law.a)


@njit(cache=CACHE, inline="always")
def _proof(kind, coll, judge, top, held, need):
    """The lowest head-on speed [m/s] below ``top`` from which :mod:`.rebound_proof` proves
    that ``coll`` rebounds at every speed up to ``top``; ``inf`` where none is. ``held``
    (``rows.held``): the interval proven for the collision by its earlier elements, and
    the highest top of the run of elements of the collision. A proof over an interval of
    speeds is the collision's, whatever the element's law, so the elements of one run
    share it: an element whose top lies inside it takes it as it is, one above it extends
    it by the interval up to its top (one check), and only where that fails is the proof
    made anew (:func:`.rebound_proof.proven_from`, up to three rounds), up to the run's
    highest top where that proves below the element's top, else up to the element's top,
    and joined to the held one where the two meet. In mode "paper" the interval held is
    then extended down towards ``need`` (the element's first node) where one particle
    stops first (:func:`.rebound_proof.extended_down`), once for each lower end held
    (``held[3]``: the lower end from which that extension last gave up)."""
    lo, hi, far = held[0], held[1], held[2]
    if not (lo < top and top <= hi):
        if lo < top and rebounds_over(kind, coll.raw, coll.vals, judge.body,
                                      judge.particle_slip, hi, top):
            held[1] = top
        else:
            floor = coll.u_star * (1.0 + NEAR[0])
            new = math.inf
            reach = far
            if far > top:  # up to the highest top of the run, once for all its elements
                new = proven_from(kind, coll.raw, coll.vals, judge.body,
                                  judge.particle_slip, floor, far)
            if not new < top:
                reach = top
                new = proven_from(kind, coll.raw, coll.vals, judge.body,
                                  judge.particle_slip, floor, top)
                if not new < top:
                    return math.inf
            if lo <= reach and new <= hi:  # the two intervals meet: their union is proven
                held[0], held[1] = min(lo, new), max(hi, reach)
            else:
                held[0], held[1] = new, reach
    if kind == TIER_PAPER and need < held[0] and held[3] != held[0]:
        down = extended_down(kind, coll.raw, coll.vals, judge.body, judge.particle_slip,
                             coll.u_star * (1.0 + NEAR[0]), held[0], need)
        if down > need:
            held[3] = down  # gave up there: not tried again from that end
        held[0] = down
    return held[0]


@njit(cache=CACHE, inline="always")
def _top(law, f_star, rest):
    """The top speed of the element's candidates [m/s]: above it the law holds
    :data:`.sticking_numeric.TAIL`, or less than its last node's share."""
    n_nodes = law.n_nodes
    if law.family == LOGNORMAL:
        return law.given[law.k, n_nodes]
    return _quantile(max(1.0 - TAIL, f_star + rest * ((n_nodes - 1 + 0.5) / n_nodes)), law.a)


@njit(cache=CACHE, inline="always")
def _candidates(kind, coll, law, n_own, judge, rows, f_star, rest):
    """The element's candidates into ``rows.cand`` and their verdicts into ``rows.ver``:
    the collision's own (``u0*`` always, the others below the top) merged with the law's
    nodes and top speed; a tie puts the collision's first (its verdict known). In modes
    "paper" and "relative" a candidate at or above the lowest speed that
    :mod:`.rebound_proof` proves for the collision (:func:`_proof`) is a rebound, taken
    without an evaluation: the candidates, and so the bisections and the integral, are
    those of the method, whatever speed is proven. Returns their count, -1 where a
    verdict is unknown, or :data:`_NOTHING_STICKS` where every candidate below the proven
    speed rebounds (the collision's own, then the law's nodes in order; u0* first): then
    no piece sticks, ``P = F(u0*)``, and the rows are left unmade
    (tests/test_sticking_numeric.py::test_a_window_only_the_nodes_reach holds the nodes'
    part of that check)."""
    sp, sv, cand, ver = rows.own, rows.own_v, rows.cand, rows.ver
    n_nodes = law.n_nodes
    top = _top(law, f_star, rest)
    # modes "paper" and "relative": from a proven speed up to the top every speed rebounds
    # (.rebound_proof); the candidates there are not evaluated
    cut = math.inf
    if kind == TIER_PAPER or kind == TIER_RELATIVE:
        cut = _proof(kind, coll, judge, top, rows.held, _node(law, 0, f_star, rest, top))
    n_keep = 1
    while n_keep < n_own and sp[n_keep] < top:
        n_keep += 1
    clear = sp[0] > 0.0  # every candidate below the cut rebounds (so far)
    for i in range(n_keep):  # the collision's own, once for all its elements
        if sv[i] == _TODO and sp[i] > 0.0 and sp[i] < cut:
            sv[i] = _at(kind, coll, sp[i], judge)
        if sp[i] < cut and sv[i] != _REBOUNDS:
            clear = False
    if clear:
        # the law's nodes below the cut, in order, while they rebound: where all do, no
        # piece sticks and P = F(u0*), the row below left unmade (its end, the same)
        j = 0
        while j <= n_nodes:
            node = _node(law, j, f_star, rest, top)
            if node >= cut or (j == 0 and not node > sp[0]):
                clear = node >= cut  # (a first node not above u0* leads the row below)
                break
            if _at(kind, coll, node, judge) != _REBOUNDS:
                clear = False  # the row below evaluates it again (rare: a pair that
                break  # sticks again above u0*, or no verdict)
            j += 1
        if clear:
            return _NOTHING_STICKS
    m = 0
    i = 0
    j = 0
    node = _node(law, 0, f_star, rest, top)
    # the law's nodes 0 .. n_nodes - 1 and its top; the row ends at the first candidate at
    # or above the proven speed: all beyond rebound, adding no piece and no crossing
    while i < n_keep or j <= n_nodes:
        if j <= n_nodes and (i >= n_keep or node < sp[i]):
            cand[m] = node
            ver[m] = _TODO
            j += 1
            if j <= n_nodes:
                node = _node(law, j, f_star, rest, top)
        else:
            cand[m] = sp[i]
            ver[m] = sv[i]
            i += 1
        m += 1
        if cand[m - 1] >= cut:
            break
    # the verdicts: each distinct positive speed once, a repeat takes its first's
    for j in range(m):
        s = cand[j]
        if not s > 0.0:
            continue
        if j > 0 and s == cand[j - 1]:
            ver[j] = ver[j - 1]
            continue
        if ver[j] == _TODO:
            ver[j] = _REBOUNDS if s >= cut else _at(kind, coll, s, judge)
        if ver[j] == _UNKNOWN:
            return -1
    # a speed of 0 cannot collide: the next candidate's verdict
    if not cand[m - 1] > 0.0:
        ver[m - 1] = _REBOUNDS
    for j in range(m - 2, -1, -1):
        if not cand[j] > 0.0:
            ver[j] = ver[j + 1]
    return m


@njit(cache=CACHE)
def _crossing(kind, coll, lo, hi, lo_sticks, judge):
    """The speed where the verdict changes between ``lo`` and ``hi`` (``lo_sticks``: the
    verdict at ``lo``), bisected as :func:`.sticking_numeric.bracket` does; NaN where a
    verdict is unknown or the bisection does not settle."""
    for _ in range(MAX_BISECTIONS):
        if not hi - lo > U_RTOL * hi:
            return 0.5 * (lo + hi)
        mid = math.sqrt(lo) * math.sqrt(hi) if lo > 0.0 else 0.5 * (lo + hi)
        v = _at(kind, coll, mid, judge)
        if v == _UNKNOWN:
            return math.nan
        if (v == _STICKS) == lo_sticks:
            lo = mid
        else:
            hi = mid
    return math.nan


@njit(cache=CACHE, inline="always")
def _f_star(coll, law):
    """``F(u0*)`` of the element: scipy's (given) for the lognormal law, so that an element
    with nothing sticking above ``u0*`` has the quadrature's ``P`` bitwise."""
    if law.family == LOGNORMAL:
        return law.given[law.k, law.n_nodes + 1]
    return _cdf(law.family, coll.u_star, law.a, law.b)


@njit(cache=CACHE, inline="always")
def _element(kind, coll, law, n_own, judge, rows):
    """``(P, ok)`` of one element of collision ``coll`` (:class:`Collision`, its own
    candidates in ``rows`` (:class:`Scratch`), ``n_own`` of them) under ``law``
    (:class:`ElementLaw`)."""
    family, a, b = law.family, law.a, law.b
    if not coll.u_star >= 0.0:
        return math.nan, False  # no u0* (NaN): nothing proven, left to the caller
    f_star = _f_star(coll, law)
    rest = 1.0 - f_star
    if not rest > REST_MIN:
        return 1.0, True
    if family == FIXED:
        if not a > 0.0:
            return f_star + rest, True  # a speed of 0 cannot collide: sticks
        v = _at(kind, coll, a, judge)
        if v == _UNKNOWN:
            return math.nan, False
        return f_star + rest * (1.0 if v == _STICKS else 0.0), True
    m = _candidates(kind, coll, law, n_own, judge, rows, f_star, rest)
    if m == _NOTHING_STICKS:
        return f_star, True  # the pieces below sum to it where all rebound (f_star < 1)
    if m < 0:
        return math.nan, False
    cand, ver = rows.cand, rows.ver
    # the pieces: between candidates, constant up to the crossing bisected
    p = f_star if cand[0] == coll.u_star else _cdf(family, cand[0], a, b)
    f_lo = p
    have_lo = True  # f_lo is F(cand[j]); left unmade across pieces that rebound
    for j in range(m - 1):
        s0 = ver[j] == _STICKS
        s1 = ver[j + 1] == _STICKS
        if not (s0 or s1):
            have_lo = False
            continue
        if not have_lo:
            f_lo = _cdf(family, cand[j], a, b)
            have_lo = True
        f_hi = _cdf(family, cand[j + 1], a, b)
        if s0 == s1:
            if s0:
                p += f_hi - f_lo
        else:
            x = _crossing(kind, coll, cand[j], cand[j + 1], s0, judge)
            if math.isnan(x):
                return math.nan, False
            f_x = _cdf(family, x, a, b)
            p += (f_x - f_lo) if s0 else (f_hi - f_x)
        f_lo = f_hi
    if ver[m - 1] == _STICKS:
        p += 1.0 - f_lo
    return min(p, 1.0), True


@njit(cache=CACHE)
def _run_top(c, law_of, given, n_nodes, coll, k0, k1):
    """The highest top speed [m/s] of the elements from ``k0`` (below ``k1``) of collision
    ``c`` while they follow one another (its run in the block); 0 where none brackets.
    ``law_of``: the :class:`.sticking.SpeedLaw` tuple with steps."""
    family, p1, s1, p2, s2 = law_of
    far = 0.0
    if family == FIXED:
        return far
    # a Maxwellian top rises with the granular temperature (its square is the smaller of
    # theta ln(1/TAIL) and u0*^2 + theta ln(2 N)): the hottest element's is the run's (a
    # bound is all the proof needs; the elements' results do not depend on it)
    hot = 0.0
    k = k0
    while k < k1 and coll[k] == coll[k0]:
        if family == LOGNORMAL:  # its top given per element
            law = ElementLaw(family, p1[k * s1], p2[k * s2], given, k, n_nodes)
            f_star = _f_star(c, law)
            if 1.0 - f_star > REST_MIN:
                far = max(far, _top(law, f_star, 1.0 - f_star))
        else:
            hot = max(hot, p1[k * s1])
        k += 1
    if family != LOGNORMAL:
        law = ElementLaw(family, hot, 0.0, given, k0, n_nodes)
        f_star = _f_star(c, law)
        if 1.0 - f_star > REST_MIN:
            far = _top(law, f_star, 1.0 - f_star)
    return far


@njit(cache=CACHE)
def _range(kind, task, judge, res, k0, k1):
    """Elements ``k0 <= k < k1`` of ``task`` (``(inp, coll, law, given, n_nodes)``: a
    :class:`.sticking.SetInputs` tuple, each element's collision, a
    :class:`.sticking.SpeedLaw` tuple with steps for ``how``, the lognormal nodes and
    ``N``) into ``res`` (``(P, ok)``); ``judge``: ``(body, particle_slip)``. A
    collision's own candidates are kept while consecutive elements share it."""
    (ins, st, u_star, su), coll, (family, p1, s1, p2, s2), given, n_nodes = task
    out, ok = res
    how = Judge(judge[0], judge[1], np.empty(0))
    rows = Scratch(np.empty(_MAX_OWN), np.empty(_MAX_OWN, dtype=np.int64),
                   np.empty(_MAX_OWN + n_nodes + 1),
                   np.empty(_MAX_OWN + n_nodes + 1, dtype=np.int64),
                   np.zeros(MAX_WINDOWS), np.zeros(MAX_WINDOWS), np.empty(4))
    last = -1
    n_own = 0
    raw = _raw(ins, st, 0)
    c = Collision(raw, prepare_one(raw, 0.0, math.nan, how.body, how.particle_slip), 0.0)
    for k in range(k0, k1):
        q = coll[k]
        if q != last:
            raw = _raw(ins, st, q)
            c = Collision(raw, prepare_one(raw, 0.0, math.nan, how.body, how.particle_slip),
                          u_star[q * su])
            last = q
            rows.held[0], rows.held[1] = math.inf, 0.0  # nothing proven for it yet
            rows.held[3] = math.nan  # nor given up
            if kind == TIER_PAPER or kind == TIER_RELATIVE:  # the kinds with a proof
                rows.held[2] = _run_top(c, (family, p1, s1, p2, s2), given, n_nodes, coll,
                                        k, k1)
            n_own = -1  # made on first need (not for a fixed law, nor where P = 1)
        law = ElementLaw(family, p1[k * s1], p2[k * s2], given, k, n_nodes)
        if n_own < 0 and family != FIXED and 1.0 - _f_star(c, law) > REST_MIN:
            n_own = _own(kind, c, how, rows)
        out[k], ok[k] = _element(kind, c, law, n_own, how, rows)


@njit(cache=CACHE)
def _serial(kind, task, judge, res):
    _range(kind, task, judge, res, 0, res[0].shape[0])


@njit(parallel=True, cache=CACHE)
def _parallel(kind, task, judge, res, block, lanes):
    # the task's and the judge's tuples made in the loop's body from their parts: a
    # parallel loop cannot take a tuple that holds a tuple of arrays (as in .sticking)
    inp, coll, law, given, n_nodes = task
    ins, st, u_star, su = inp
    body, particle_slip = judge
    n = res[0].shape[0]
    nb = (n + block - 1) // block
    for t in prange(lanes):
        for b in range(t, nb, lanes):
            _range(kind, ((ins, st, u_star, su), coll, law, given, n_nodes),
                   (body, particle_slip), res, b * block, min(n, (b + 1) * block))


# One serial and one parallel entry per kind, the kind a compile-time constant: only its
# kernel is compiled into the loop (as the fused loops do).


@njit(cache=CACHE)
def _serial_paper(task, judge, res):
    _serial(TIER_PAPER, task, judge, res)


@njit(cache=CACHE)
def _serial_relative(task, judge, res):
    _serial(TIER_RELATIVE, task, judge, res)


@njit(cache=CACHE)
def _serial_auto(task, judge, res):
    _serial(KIND_AUTO, task, judge, res)


@njit(cache=CACHE)
def _parallel_paper(task, judge, res, block, lanes):
    _parallel(TIER_PAPER, task, judge, res, block, lanes)


@njit(cache=CACHE)
def _parallel_relative(task, judge, res, block, lanes):
    _parallel(TIER_RELATIVE, task, judge, res, block, lanes)


@njit(cache=CACHE)
def _parallel_auto(task, judge, res, block, lanes):
    _parallel(KIND_AUTO, task, judge, res, block, lanes)


@njit(cache=CACHE)
def _serial_ode(task, judge, res):
    _serial(KIND_ODE, task, judge, res)


@njit(cache=CACHE)
def _serial_ode_sc(task, judge, res):
    _serial(KIND_ODE_SC, task, judge, res)


@njit(cache=CACHE)
def _parallel_ode(task, judge, res, block, lanes):
    _parallel(KIND_ODE, task, judge, res, block, lanes)


@njit(cache=CACHE)
def _parallel_ode_sc(task, judge, res, block, lanes):
    _parallel(KIND_ODE_SC, task, judge, res, block, lanes)


_ENTRIES = {
    TIER_PAPER: (_serial_paper, _parallel_paper),
    TIER_RELATIVE: (_serial_relative, _parallel_relative),
    KIND_AUTO: (_serial_auto, _parallel_auto),
    KIND_ODE: (_serial_ode, _parallel_ode),
    KIND_ODE_SC: (_serial_ode_sc, _parallel_ode_sc),
}

#: Elements below which the loop runs on the calling thread (an element costs about 20
#: kernel evaluations).
SERIAL_BELOW = 64
#: Elements per block of the parallel loop, and the fewest.
BLOCK, MIN_BLOCK = 1024, 16
#: Lognormal elements whose nodes scipy makes at a time (17 speeds each).
LOGNORMAL_CHUNK = 1 << 16


def _grouping(coll):
    """The order (stable) that puts the elements of each collision next to one another,
    or None where they mostly are: where the runs of consecutive elements of one collision
    outnumber the collisions by more than a 32nd of the elements. A run makes its
    collision's proof and own candidates anew (:func:`_range`), several microseconds,
    against a fraction of one for its element's share of the sort. A map whose speed law
    varies along an axis that is not its last (the README's granulator map has ``U_Umf``
    in the middle) has a run per element otherwise."""
    m = coll.shape[0]
    if m < 2:
        return None
    runs = 1 + int(np.count_nonzero(coll[1:] != coll[:-1]))
    distinct = int(np.count_nonzero(np.bincount(coll)))
    if runs - distinct <= m // 32:
        return None
    # (numpy's stable sort of 32-bit keys took half the time of 64-bit ones: 7 against 15
    # ms for 1e6 elements of 1e4 collisions)
    key = coll.astype(np.uint32) if int(coll.max()) < 2**32 else coll
    return np.argsort(key, kind="stable")


def bracketed_propensity(ins, steps, kind, u_star, coll, family, p1, p2, *, body,
                         particle_slip, nodes=16, lognormal=None):
    """``(P, ok)`` at ``coll.size`` elements, element ``k`` of collision ``coll[k]`` of the
    fused inputs ``ins, steps`` (their lab speeds not read) with head-on ``u_star`` (float64,
    length 1 or one per collision), by the bracketing of :mod:`.sticking_numeric` with the
    kernel ``kind`` (:func:`kind_of`) and the law ``family`` (:data:`.sticking.FIXED`,
    ``LOGNORMAL``, ``MAXWELLIAN``) of parameters ``p1``, ``p2`` (float64, length 1 or one
    per element; as :func:`.sticking.propensity_from_windows`). ``nodes``: the law's
    quantile nodes among the candidates. ``lognormal``: for that family, a function
    ``(idx) -> (idx.size, nodes + 2)`` array, the nodes, the top speed and ``F(u0*)`` of
    the elements ``idx`` (an index array, in the caller's numbering;
    :func:`agglomtool.bed.speeds.bracket_elements`' rule, by scipy). ``ok`` false where
    the element is left to the quadrature (``P`` NaN). The elements are taken grouped by
    collision (:func:`_grouping`), and the results returned in the caller's order."""
    coll = np.ascontiguousarray(coll, dtype=np.int64)
    u_star = np.ascontiguousarray(u_star, dtype=np.float64).reshape(-1)
    su = 1 if u_star.shape[0] > 1 else 0
    m = coll.shape[0]
    p1 = np.ascontiguousarray(p1, dtype=np.float64).reshape(-1)
    p2 = np.ascontiguousarray(p2, dtype=np.float64).reshape(-1)
    order = _grouping(coll)
    if order is not None:
        coll = coll[order]
        p1 = p1[order] if p1.shape[0] > 1 else p1
        p2 = p2[order] if p2.shape[0] > 1 else p2
    out = np.empty(m)
    ok = np.empty(m, dtype=np.bool_)
    serial, parallel = _ENTRIES[int(kind)]
    n_nodes = int(nodes)
    step = LOGNORMAL_CHUNK if family == LOGNORMAL else max(m, 1)
    for k0 in range(0, m, step):
        k1 = min(m, k0 + step)
        if family == LOGNORMAL:
            idx = order[k0:k1] if order is not None else np.arange(k0, k1)
            given = np.ascontiguousarray(lognormal(idx), dtype=np.float64)
        else:
            given = np.zeros((1, 1))
        law = (int(family), p1[k0:k1] if p1.shape[0] > 1 else p1, int(p1.shape[0] > 1),
               p2[k0:k1] if p2.shape[0] > 1 else p2, int(p2.shape[0] > 1))
        args = (((ins, steps, u_star, su), coll[k0:k1], law, given, n_nodes),
                (bool(body), slip_flag(particle_slip)), (out[k0:k1], ok[k0:k1]))
        if k1 - k0 < SERIAL_BELOW:
            serial(*args)
        else:
            block, lanes = launch_blocks(k1 - k0, BLOCK, MIN_BLOCK)
            parallel_launch(parallel, *args, block, lanes)
    if order is not None:  # back to the caller's order
        back_out, back_ok = np.empty(m), np.empty(m, dtype=np.bool_)
        back_out[order], back_ok[order] = out, ok
        return back_out, back_ok
    return out, ok
