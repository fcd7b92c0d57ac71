"""The sticking set above ``u0*`` and the propensity over it, compiled.

The propensity of a speed law ``F`` is ``P = F(u0*) + integral over u > u0* of stick(u) dF``
(:func:`agglomtool.bed.speeds.sticking_probability`). Above ``u0*`` a pair sticks again only
on a set of speeds that the tier's structure bounds; this module finds that set as a union
of intervals ``[a_k, b_k]`` and integrates the law's CDF over them,
``P = F(u0*) + sum_k F(b_k) - F(max(a_k, u0*))``, with no quadrature.

Mode "relative" (:mod:`.relative`, :mod:`.critical_relative`)
-------------------------------------------------------------
Both stages are quadratic energy balances in the speed entering them. The approach sticks
every relative speed up to ``w_app``; above it the pair reaches contact and leaves it with
``w_s`` rising strictly with ``w``, and with ``t = sqrt(Ca) = sqrt(mu_l w_s / gamma)`` the
separation rebounds iff the bridge is broken at contact (``h(t) = h_b (1 + t) <= Ha``) or
``F(t) > 0``, ``F`` the separation's balance of :mod:`.critical_relative`. There ``F`` is
shown convex on ``[t_0, t_E]`` and on ``[t_E, inf)`` (``t_E``: where the capillary and body
work of the separation changes sign, only with a body force pulling the pair apart), with
``t_0`` the larger of the smallest ``t`` that reaches contact and the ``t`` at which the
bridge starts to hold at contact. On a convex piece the set ``F <= 0`` is one interval
(possibly empty), so the sticking set above ``w_app`` is at most two intervals, found per
piece:

- from a point where ``F > 0`` and ``F' >= 0`` the rest of the piece rebounds (convexity):
  at ``u0*`` itself, the kernel's first rebound, this ends the work on most pairs after one
  evaluation of ``F``;
- otherwise the piece's minimum is bracketed by the sign of ``F'`` (bisection, at most
  :data:`MAX_STEPS` steps) while the two tangents at the bracket's ends bound ``F`` from
  below: a positive bound proves the piece rebounds throughout; a point with ``F <= 0``
  proves a window, whose ends are then found by bisection between a rebounding and a
  sticking ``t`` (a bracket that cannot run away) to :data:`T_RTOL`.

Each window found is checked with the tier's kernel (it sticks inside, and rebounds just
outside where that lies above ``u0*``). Mode "paper" without body forces equals mode
"relative" to rounding (:mod:`.relative`) and takes the same set, checked with the paper's
kernel. Where no bracket is proven (mode "paper" with body forces, a drag that depends on
the particles' speed, a failed check, an iteration that did not settle) the collision is
flagged :data:`FALLBACK` and the caller brackets its set with the tier's own kernel
(:mod:`.sticking_numeric`), or, where no bracket settles there either, integrates it by
the node quadrature (the checked reference).

Accuracy: the window ends are bisected to ``T_RTOL`` (1e-13) of ``t``, i.e. ``2e-13`` of
the speed at contact; in probability each end is then within ``f(u) u 1e-12`` of the true
one (``f`` the speed law's density), far below 1e-9 for any law of this package.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from .critical import _raw
from .critical_relative import (
    Separation,
    _e_zero,
    _sep,
    approach,
    kernel_constants,
    speed_of_separation,
)
from .fused import SERIAL_BELOW, TIER_PAPER, launch_blocks, prepare_one, tier_kernel
from .records import Pair

__all__ = ["sticking_windows", "propensity_from_windows", "propensity_exact", "FIXED", "LOGNORMAL",
           "MAXWELLIAN", "EXACT", "FALLBACK", "MAX_WINDOWS", "T_RTOL", "MAX_STEPS",
           "SetInputs", "SetFlags", "Windows", "SpeedLaw"]

#: Speed-law family codes of :func:`propensity_from_windows`.
FIXED, LOGNORMAL, MAXWELLIAN = 0, 1, 2
#: Status of a collision's sticking set: found and checked, or left to the quadrature.
EXACT, FALLBACK = 0, 1
#: Intervals of sticking speeds above ``u0*`` a collision may hold: the approach's (when
#: ``u0*`` lies below it by rounding) and one per convex piece of the separation.
MAX_WINDOWS = 3
#: Relative width in ``t = sqrt(Ca)`` to which a window's ends are bisected.
T_RTOL = 1e-13
#: Steps allowed to any one bracketing or bisection.
MAX_STEPS = 2100
#: Relative offset of the checks just outside a window's ends.
CHECK_OFFSET = 1e-9
#: ``1 - F(u0*)`` below which ``P = 1`` (as the quadrature takes it).
REST_MIN = 1e-12


# The records of a launch. The launches take them from Python as plain tuples and make them
# records inside (numba's dispatcher types a plain tuple as fast as separate arguments, a
# named tuple more slowly, the slower the more fields it holds).


class SetInputs(NamedTuple):
    """The collisions of a launch: the fused kernels' inputs and each one's ``u0*``."""

    #: the input arrays of :data:`.fused.INPUT_NAMES` (the lab speeds are not read)
    ins: tuple
    #: their steps, 0 or 1 (int64 array)
    st: np.ndarray
    #: the head-on ``u0*`` [m/s], of length 1 or one per collision
    u_star: np.ndarray
    #: its step, 0 or 1
    su: int


class SetFlags(NamedTuple):
    """Which kernel decides a collision."""

    #: ``fused.TIER_PAPER`` or ``fused.TIER_RELATIVE``
    tier: int
    #: weight, buoyancy and drag on
    body: bool
    #: the drag's slip is the particle's own speed: ``True``, or ``None`` for false
    particle_slip: object


class Windows(NamedTuple):
    """The sticking sets of :func:`sticking_windows`, one row per collision."""

    #: the windows' lower ends, head-on speed [m/s], ``(n, MAX_WINDOWS)``
    lo: np.ndarray
    #: their upper ends [m/s]
    hi: np.ndarray
    #: windows per collision (int8; ``count`` would hide the tuple's method)
    counts: np.ndarray
    #: :data:`EXACT` or :data:`FALLBACK` (int8)
    status: np.ndarray


class SpeedLaw(NamedTuple):
    """The speed law of a propensity: its family and its two parameters, each a float64
    array read as its ``how`` says (:data:`ONE`, :data:`PER_ELEMENT`, :data:`PER_COLLISION`,
    :data:`PER_TRAILING`; :func:`propensity_from_windows` takes ``ONE`` or
    ``PER_ELEMENT``, which are the arrays' steps 0 and 1)."""

    #: :data:`FIXED`, :data:`LOGNORMAL` or :data:`MAXWELLIAN`
    family: int
    #: the fixed speed, the lognormal median [m/s] or the granular temperature [m2/s2]
    p1: np.ndarray
    #: how ``p1`` is read
    how1: int
    #: the lognormal ``sigma_ln`` [-] (else not read)
    p2: np.ndarray
    #: how ``p2`` is read
    how2: int


@njit(cache=CACHE)
def _t_of_w(w, kappa, e, e_a, m_r, w_v, wc_min, w_app):
    """``t = sqrt(Ca)`` at the start of the separation of an impact at relative speed
    ``w > w_app`` [m/s]: ``w_c = sqrt((w - w_v)^2 - 2 E_a / m_r)``, the difference of
    squares factored where ``E_a >= 0``."""
    if e_a < 0.0:
        w_c = math.hypot(w - w_v, wc_min)
    else:
        s = w_app - w_v
        w_c = math.sqrt((w - w_app) * (w - w_v + s))
    return math.sqrt(kappa * e * w_c)


@njit(cache=CACHE)
def _bisect_t(lo, hi, lo_sticks, args):
    """A crossing of ``F`` between ``lo`` and ``hi`` (``F(lo) <= 0`` where ``lo_sticks``,
    else ``F(hi) <= 0``; the other end ``> 0``), bisected to :data:`T_RTOL`. Returns
    ``(t, ok)``."""
    for _ in range(MAX_STEPS):
        if hi - lo <= T_RTOL * hi:
            return 0.5 * (lo + hi), True
        mid = 0.5 * (lo + hi)
        f, _ = _sep(mid, args)
        if (f <= 0.0) == lo_sticks:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi), False


@njit(cache=CACHE)
def _upper(a, step, args):
    """A ``t > a`` with ``F(t) > 0`` (``F`` grows like ``t^2``): ``a + step`` doubled."""
    for _ in range(MAX_STEPS):
        t = a + step
        f, _ = _sep(t, args)
        if f > 0.0:
            return t, True
        step *= 2.0
    return math.inf, False


@njit(cache=CACHE)
def _piece(a, a_inner, b, scale, args):
    """The interval where ``F <= 0`` in the convex piece ``[a, b]`` (``b`` may be inf).

    ``a_inner``: ``a`` lies inside the piece, so ``F'(a)`` is a one-sided slope of the
    convex ``F`` there (else ``a`` is the piece's end, where ``F'`` may be unbounded, and
    only ``F(a)`` is used). ``scale``: a step in ``t`` to search upwards from ``a``.
    Returns ``(found, t_a, t_b, ok)``."""
    inf = math.inf
    fa, dfa = _sep(a, args)
    if not a_inner:
        dfa = -inf
    if fa <= 0.0:  # sticks from a on: the window ends at the crossing
        if b < inf:
            fb, _ = _sep(b, args)
            if fb <= 0.0:
                return True, a, b, True
            hi, ok = b, True
        else:
            hi, ok = _upper(a, max(scale, a), args)
        if not ok:
            return False, a, a, False
        t_b, ok = _bisect_t(a, hi, True, args)
        return True, a, t_b, ok
    if dfa >= 0.0:  # F > 0 and rising on a convex piece: rebounds throughout
        return False, a, a, True
    lo, flo, dlo = a, fa, dfa
    if b < inf:
        hi = b
        fhi, _ = _sep(b, args)
        dhi = inf
        if fhi <= 0.0:
            t_a, ok = _bisect_t(a, b, False, args)
            return True, t_a, b, ok
    else:  # step up until F rises (or a point sticks)
        step = max(scale, a)
        hi = lo + step
        found = False
        for _ in range(MAX_STEPS):
            hi = lo + step
            fhi, dhi = _sep(hi, args)
            if fhi <= 0.0 or dhi > 0.0:
                found = True
                break
            lo, flo, dlo = hi, fhi, dhi
            step *= 2.0
        if not found:
            return False, a, a, False
        if fhi <= 0.0:
            t_a, ok_a = _bisect_t(lo, hi, False, args)
            top, ok_u = _upper(hi, max(scale, hi), args)
            t_b, ok_b = _bisect_t(hi, top, True, args)
            return True, t_a, t_b, ok_a and ok_u and ok_b
    # F(lo) > 0 falling, F(hi) > 0 rising: the minimum lies between. The tangents at the
    # ends bound F from below; bisect on the sign of F'.
    for _ in range(MAX_STEPS):
        if dlo == -inf and dhi == inf:
            bound = -inf
        elif dlo == -inf:
            bound = fhi + dhi * (lo - hi)
        elif dhi == inf:
            bound = flo + dlo * (hi - lo)
        else:
            tx = (fhi - flo + dlo * lo - dhi * hi) / (dlo - dhi)
            bound = flo + dlo * (tx - lo)
        if bound > 0.0:
            return False, a, a, True
        if hi - lo <= T_RTOL * hi:
            # The minimum is pinned to rounding and no point there sticks: a window, if
            # any, narrower than the bracket (no probability to this accuracy).
            return False, a, a, True
        mid = 0.5 * (lo + hi)
        fm, dm = _sep(mid, args)
        if fm <= 0.0:
            t_a, ok_a = _bisect_t(lo, mid, False, args)
            t_b, ok_b = _bisect_t(mid, hi, True, args)
            return True, t_a, t_b, ok_a and ok_b
        if dm < 0.0:
            lo, flo, dlo = mid, fm, dm
        else:
            hi, fhi, dhi = mid, fm, dm
    return False, a, a, False


@njit(cache=CACHE)
def _sticks(tier, vals, mu_l, gamma, e, w, empty):
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, _ = vals
    ew, _, _ = tier_kernel(tier, Pair(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i,
                                      fn_j, e), w, empty)
    return ew == 0.0


@njit(cache=CACHE)
def _windows_one(raw, u_star, flags, lo, hi, empty):
    """The sticking set of one collision (``raw``: :class:`.records.RawPair`) above
    ``u_star`` [m/s] (head-on lab speed), decided by the kernel of ``flags``
    (:class:`SetFlags`), as intervals of head-on speed written to ``lo``, ``hi``; returns
    ``(count, status)``."""
    tier, body, particle_slip = flags
    if not u_star >= 0.0:
        return 0, FALLBACK  # NaN: nothing to integrate from
    if math.isinf(u_star):
        return 0, EXACT  # sticks at every speed: P = 1 from F(u0*) alone
    vals = prepare_one(raw, 0.0, math.nan, body, particle_slip)
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, wpu = vals
    mu_l, gamma, e = raw[8], raw[9], raw[17]
    if not H0 > Ha:
        if e > 0.0:
            return 0, EXACT  # no bridge: every approach rebounds
        lo[0], hi[0] = u_star, math.inf
        return 1, EXACT
    if e == 0.0 or Ha == 0.0:
        lo[0], hi[0] = u_star, math.inf  # sticks at every speed
        return 1, EXACT
    if body and particle_slip:
        return 0, FALLBACK  # the body forces change with the speed: no fixed balance
    if tier == TIER_PAPER and (fn_i != 0.0 or fn_j != 0.0):
        return 0, FALLBACK  # the paper's own bookkeeping with body forces: no bracket
    kc = kernel_constants(Pair(m_i=m_i, m_j=m_j, r=r, H0=H0, Ha=Ha, mu_l=mu_l, gamma=gamma,
                               cos_t=cos_t, theta=theta, fn_i=fn_i, fn_j=fn_j, e=e))
    m_r, a2, c, kcap, f_b, d_app, g_app, v13, k_ha, v_ha, s_ha = kc
    c_m, w_v, e_a, wc_min, w_app, kappa, hb, t_min = approach(kc, H0, Ha, mu_l, gamma,
                                                              theta, e)
    if not math.isfinite(w_app):
        return 0, FALLBACK
    args = Separation(kappa, hb, Ha, a2, c_m, kcap, f_b, m_r, k_ha, v_ha, s_ha)
    w_lo = u_star * wpu
    count = 0
    # ---- the approach sticks up to w_app
    if w_lo < w_app:
        lo[count], hi[count] = w_lo, w_app
        count += 1
        t_lo = t_min
    else:
        t_lo = _t_of_w(w_lo, kappa, e, e_a, m_r, w_v, wc_min, w_app)
    # ---- the separation's convex pieces
    t_0 = max(t_min, Ha / hb - 1.0)  # below Ha / hb - 1 the bridge is broken at contact
    t_e = math.inf
    if f_b < 0.0 and kcap * (a2 / (H0 + Ha)) / H0 + f_b > 0.0:
        h_e, ok = _e_zero(Ha, a2, kcap, f_b, 60)
        if not ok:
            return 0, FALLBACK
        t_e = h_e / hb - 1.0
    scale = math.sqrt(kappa * e * max(w_v, w_app))  # t at a speed of the approach's scale
    if not scale > 0.0:
        scale = max(t_0, 1e-150)
    starts = (t_0, t_e)
    ends = (t_e, math.inf)
    for p in range(2):
        a, b = starts[p], ends[p]
        if not a < b:
            continue
        inner = False
        if t_lo >= b:
            continue
        if t_lo > a:
            a, inner = t_lo, True
        found, t_a, t_b, ok = _piece(a, inner, b, scale, args)
        if not ok:
            return 0, FALLBACK
        if found:
            wa = speed_of_separation(t_a, kappa, e, e_a, m_r, w_v, wc_min, w_app)
            wb = speed_of_separation(t_b, kappa, e, e_a, m_r, w_v, wc_min, w_app)
            if count > 0 and wa <= hi[count - 1]:
                hi[count - 1] = max(hi[count - 1], wb)  # adjoins the previous window
            else:
                lo[count], hi[count] = wa, wb
                count += 1
    # ---- each window checked with the tier's kernel
    for k in range(count):
        wa, wb = lo[k], hi[k]
        if math.isfinite(wb):
            if not _sticks(tier, vals, mu_l, gamma, e, math.sqrt(wa) * math.sqrt(wb), empty):
                return 0, FALLBACK
            if _sticks(tier, vals, mu_l, gamma, e, wb * (1.0 + CHECK_OFFSET), empty):
                return 0, FALLBACK
        below = wa * (1.0 - CHECK_OFFSET)
        if below > w_lo and _sticks(tier, vals, mu_l, gamma, e, below, empty):
            return 0, FALLBACK
        lo[k], hi[k] = wa / wpu, wb / wpu
    return count, EXACT


@njit(cache=CACHE)
def _windows_range(inp, flags, win, q0, q1):
    """The sticking sets of collisions ``q0 <= q < q1`` of ``inp`` (:class:`SetInputs`)
    into ``win`` (:class:`Windows`)."""
    ins, st, u_star, su = inp
    lo, hi, count, status = win
    empty = np.empty(0)
    for q in range(q0, q1):
        c, s = _windows_one(_raw(ins, st, q), u_star[q * su], flags, lo[q], hi[q], empty)
        count[q] = c
        status[q] = s


@njit(cache=CACHE)
def _windows_serial(inp, flags, win):
    _windows_range(SetInputs(*inp), SetFlags(*flags), Windows(*win), 0, win[2].shape[0])


@njit(parallel=True, cache=CACHE)
def _windows_parallel(inp, flags, win):
    # the inputs' record is made in the loop's body: a parallel loop cannot take a record
    # that holds the tuple of input arrays
    ins, st, u_star, su = inp
    kernel = SetFlags(*flags)
    sets = Windows(*win)
    n = sets.counts.shape[0]
    nb = (n + 255) // 256
    for b in prange(nb):
        _windows_range(SetInputs(ins, st, u_star, su), kernel, sets, b * 256,
                       min(n, (b + 1) * 256))


def sticking_windows(ins, steps, n, tier, u_star, *, body, particle_slip):
    """The sticking sets above ``u_star`` of ``n`` collisions given as the fused kernels'
    inputs (:mod:`.fused`; the lab speeds are not read) for ``tier`` ``fused.TIER_PAPER``
    or ``fused.TIER_RELATIVE``.

    ``u_star``: a float64 array of length 1 or ``n``, the head-on ``u0*`` [m/s]. Returns
    a :class:`Windows` ``(lo, hi, counts, status)``: collision ``q`` sticks (above
    ``u_star``) on the head-on speeds ``[lo[q, k], hi[q, k]]``, ``k < count[q]``;
    ``status[q]`` is :data:`EXACT` or :data:`FALLBACK` (no proven bracket: integrate it by
    the quadrature). ``body``: weight, buoyancy and drag on; ``particle_slip``: the drag's
    slip is the particle's own speed."""
    u_star = np.ascontiguousarray(u_star, dtype=np.float64).reshape(-1)
    su = 1 if u_star.shape[0] > 1 else 0
    win = Windows(lo=np.zeros((n, MAX_WINDOWS)), hi=np.zeros((n, MAX_WINDOWS)),
                  counts=np.zeros(n, dtype=np.int8), status=np.zeros(n, dtype=np.int8))
    # SetInputs, SetFlags and Windows as plain tuples (the launches make them records)
    args = ((ins, steps, u_star, su), (int(tier), bool(body), True if particle_slip else None),
            tuple(win))
    if n < SERIAL_BELOW // 4:
        _windows_serial(*args)
    else:
        parallel_launch(_windows_parallel, *args)
    return win


@njit(cache=CACHE, inline="always")
def _cdf(family, u, p1, p2):
    """``F(u) = P(u0 < u)`` of the speed law (``p1``: the fixed speed, the lognormal median
    or the granular temperature; ``p2``: the lognormal ``sigma_ln``), as
    :meth:`agglomtool.bed.speeds.SpeedModel.cdf`."""
    if family == FIXED:
        return 1.0 if u > p1 else 0.0
    if family == LOGNORMAL:
        if not u > 0.0:
            return 0.0
        z = math.log(u / p1) / p2
        return 0.5 * math.erfc(-z / math.sqrt(2.0))
    return -math.expm1(-(u * u) / p1)


@njit(cache=CACHE, inline="always")
def _p_one(family, us, a, b, lo, hi, count, status):
    """``P`` of one element: its collision's ``u0*`` ``us``, sticking set (``lo``, ``hi``:
    its rows, ``count``, ``status``) and the law's parameters ``a``, ``b``."""
    f_star = _cdf(family, us, a, b)
    if not (1.0 - f_star) > REST_MIN:
        return 1.0
    if status != EXACT:
        return math.nan
    if family == FIXED:
        # Every collision at p1 >= u0*: it sticks iff p1 lies in a window.
        stuck = 0.0
        if not a > 0.0:
            stuck = 1.0  # a speed of 0 cannot collide: sticks, as the quadrature says
        for j in range(count):
            if lo[j] <= a <= hi[j]:
                stuck = 1.0
        return f_star + (1.0 - f_star) * stuck
    p = f_star
    for j in range(count):
        top = hi[j]
        if top > us:
            p += _cdf(family, top, a, b) - _cdf(family, max(lo[j], us), a, b)
    return min(p, 1.0)


@njit(cache=CACHE)
def _integrate_range(idx, law, u_star, win, out, k0, k1):
    """``P`` of elements ``k0 <= k < k1`` (collision ``idx[k]``) under ``law``
    (:class:`SpeedLaw`, ``how`` the arrays' steps) from the sticking sets ``win``."""
    family, p1, s1, p2, s2 = law
    lo, hi, count, status = win
    for k in range(k0, k1):
        q = idx[k]
        out[k] = _p_one(family, u_star[q], p1[k * s1], p2[k * s2], lo[q], hi[q], count[q],
                        status[q])


@njit(cache=CACHE)
def _integrate_serial(idx, law, u_star, win, out):
    _integrate_range(idx, SpeedLaw(*law), u_star, Windows(*win), out, 0, out.shape[0])


@njit(parallel=True, cache=CACHE)
def _integrate_parallel(idx, law, u_star, win, out):
    speeds = SpeedLaw(*law)
    sets = Windows(*win)
    n = out.shape[0]
    nb = (n + 4095) // 4096
    for b in prange(nb):
        _integrate_range(idx, speeds, u_star, sets, out, b * 4096, min(n, (b + 1) * 4096))


def propensity_from_windows(idx, family, p1, p2, u_star, windows):
    """``P`` at ``idx.size`` elements, element ``k`` of collision ``idx[k]`` of
    :func:`sticking_windows` (its ``u_star`` and its :class:`Windows` ``windows``):
    ``F(u0*) + sum_k F(hi_k) - F(max(lo_k, u0*))`` with the law ``family``
    (:data:`FIXED`, :data:`LOGNORMAL`, :data:`MAXWELLIAN`) of parameters ``p1``, ``p2``
    (float64 arrays of length 1 or ``idx.size``). NaN where the collision's status is
    :data:`FALLBACK` and probability lies above ``u0*`` (the caller fills those in)."""
    n = idx.shape[0]
    out = np.empty(n)
    s1 = 1 if p1.shape[0] > 1 else 0
    s2 = 1 if p2.shape[0] > 1 else 0
    # SpeedLaw (its steps for ``how``) and Windows as plain tuples (the launches make them
    # records)
    args = (idx, (int(family), p1, s1, p2, s2), u_star, tuple(windows), out)
    if n < SERIAL_BELOW:
        _integrate_serial(*args)
    else:
        parallel_launch(_integrate_parallel, *args)
    return out


@njit(cache=CACHE, inline="always")
def _param(p, how, k, q, inner):
    """A law parameter at element ``k`` of collision ``q`` (:func:`propensity_exact`'s
    ``how``: 0 one value, 1 per element, 2 per collision, 3 per trailing position)."""
    if how == 0:
        return p[0]
    if how == 1:
        return p[k]
    if how == 2:
        return p[q]
    return p[k - q * inner]


@njit(cache=CACHE)
def _propensity_range(inp, flags, inner, law, out, q0, q1):
    """The sticking sets and ``P`` of collisions ``q0 <= q < q1`` of ``inp``
    (:class:`SetInputs`; their ``inner`` elements each, consecutive) under ``law``
    (:class:`SpeedLaw`), into ``out``."""
    ins, st, u_star, su = inp
    family, p1, h1, p2, h2 = law
    empty = np.empty(0)
    lo = np.zeros(MAX_WINDOWS)
    hi = np.zeros(MAX_WINDOWS)
    for q in range(q0, q1):
        lo[:] = 0.0
        hi[:] = 0.0
        us = u_star[q * su]
        c, s = _windows_one(_raw(ins, st, q), us, flags, lo, hi, empty)
        for k in range(q * inner, (q + 1) * inner):
            out[k] = _p_one(family, us, _param(p1, h1, k, q, inner),
                            _param(p2, h2, k, q, inner), lo, hi, c, s)


@njit(cache=CACHE)
def _propensity_serial(inp, flags, inner, law, out):
    _propensity_range(SetInputs(*inp), SetFlags(*flags), inner, SpeedLaw(*law), out, 0,
                      out.shape[0] // inner)


@njit(parallel=True, cache=CACHE)
def _propensity_parallel(inp, flags, inner, law, out, per, lanes):
    # blocks of ``per`` collisions, lane t running blocks t, t + lanes, ... (launch_blocks)
    # (the inputs' record made in the loop's body, as in _windows_parallel)
    ins, st, u_star, su = inp
    kernel = SetFlags(*flags)
    speeds = SpeedLaw(*law)
    n = out.shape[0] // inner
    nb = (n + per - 1) // per
    for t in prange(lanes):
        for b in range(t, nb, lanes):
            _propensity_range(SetInputs(ins, st, u_star, su), kernel, inner, speeds, out,
                              b * per, min(n, (b + 1) * per))


#: How :func:`propensity_exact` reads a law parameter: one value, one per element, one per
#: collision, one per position along the trailing axes.
ONE, PER_ELEMENT, PER_COLLISION, PER_TRAILING = 0, 1, 2, 3


def propensity_exact(ins, steps, n, tier, u_star, inner, *, body, particle_slip, family, p1,
                     p2, how=None, out=None):
    """The sticking sets of :func:`sticking_windows` and the propensity of
    :func:`propensity_from_windows` in one pass (one launch): ``P`` at ``n * inner``
    elements, element ``k`` of collision ``k // inner`` (the collisions constant along the
    trailing axes of the elements, a map's speed axes), with the same arithmetic as the
    two steps. ``p1``, ``p2``: float64 arrays read as ``how`` says (a pair of
    :data:`ONE`, :data:`PER_ELEMENT`, :data:`PER_COLLISION`, :data:`PER_TRAILING`; by
    default ``ONE`` for an array of length 1, else ``PER_ELEMENT``). NaN where the
    collision's set was not proven and probability lies above ``u0*``. ``out``: a
    C-contiguous float64 1-D array of ``n * inner`` elements to write ``P`` into (then
    returned). ``body``, ``particle_slip``: as :func:`sticking_windows`; ``family``: the
    speed law's (:data:`FIXED`, :data:`LOGNORMAL`, :data:`MAXWELLIAN`)."""
    u_star = np.ascontiguousarray(u_star, dtype=np.float64).reshape(-1)
    su = 1 if u_star.shape[0] > 1 else 0
    if out is None:
        out = np.empty(n * int(inner))
    if how is None:
        how = tuple(ONE if p.shape[0] == 1 else PER_ELEMENT for p in (p1, p2))
    # SetInputs, SetFlags and SpeedLaw as plain tuples (the launches make them records)
    args = ((ins, steps, u_star, su), (int(tier), bool(body), True if particle_slip else None),
            int(inner), (int(family), p1, int(how[0]), p2, int(how[1])), out)
    if n < SERIAL_BELOW // 4 and out.shape[0] < SERIAL_BELOW:
        _propensity_serial(*args)
    else:
        # blocks of about 4096 elements (at least one collision), smaller where a launch
        # would have few blocks per thread; each block's windows are searched afresh
        per, lanes = launch_blocks(n, max(1, 4096 // int(inner)), 1)
        parallel_launch(_propensity_parallel, *args, per, lanes)
    return out
