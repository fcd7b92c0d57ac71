"""The sticking set above ``u0*`` of the tiers without a closed form, by bracketing.

:mod:`.sticking` finds the set of speeds above ``u0*`` at which a pair sticks again from the
structure of mode "relative" (and of "paper" without body forces, which equals it). The
other tiers have no such structure to hand: "ode" and "ode_selfconsistent" integrate the
motion numerically, "auto" chooses between closed forms and "ode" per collision, and in
modes "paper" with a body force on the axis and any mode with the drag's slip taken from
the particle's own speed the stages are no longer the quadratics of :mod:`.relative`. For
those, the set is found by the tier's own kernel, in batches:

1. **Candidates.** Each element (a collision under its speed law) gets a sorted row of
   candidate speeds above ``u0*``: ``u0*`` itself, the speeds :data:`NEAR` just above it,
   the law's equal-probability nodes (the quadrature's ``N``), a top speed above which the
   law holds at most :data:`TAIL` of probability, and seeds from mode "relative"'s
   compiled windows for the same collision (:func:`.sticking.sticking_windows`, with the
   body forces as given and the emulsion's slip), widened: speeds just inside and just
   outside each end and the window's middle. The kernel is evaluated at every candidate,
   those of the collision alone (``u0*``, :data:`NEAR`, the seeds) once per collision, the
   nodes and the top once per element (two batches).
2. **Brackets.** Between two adjacent candidates where the indicator changes (one sticks,
   the other rebounds) the change is bisected with the tier's kernel, every step one batch
   over the brackets still open, each bracket to its own convergence (a bracket that
   cannot run away: its ends keep their verdicts) to a relative width :data:`U_RTOL`.
3. **Integral.** Between candidates the indicator is taken as constant up to the crossing
   found, and the law's CDF is integrated over the sticking pieces
   (``agglomtool.bed.speeds``).

What is proven: each window end found lies within :data:`U_RTOL` of a change of the
tier's own verdict (in probability ``f(u) u U_RTOL`` per end, ``f`` the law's density),
and above the top candidate the law holds at most :data:`TAIL`. What is not: a window (or a
gap in one) that lies wholly between two adjacent candidates and is absent from the
seeds is missed. The candidates include the node quadrature's, so the method never misses
a window that the ``N``-node quadrature sees; narrower ones it misses where the quadrature
does too, unless mode "relative" has a window there. The tests measure that no window is
missed on the hard set and on a seeded random set against a dense scan of the tier's
kernel. Mode "ode_selfconsistent" is the exception: its own verdict flickers (tens of
changes) within about 3e-4 of its ``u0*`` on the Table 2 water case, a band no bracketing
from a few candidates resolves; its bound adds the law's probability there. Where the
kernel gives no verdict (NaN) at a candidate or a bracket, or a bisection
does not settle, the element is left to the node quadrature (counted).

Maps, beds and scenes run the same method element by element in one compiled pass per
block (:mod:`.sticking_bracketed`); the batches here are its reference (tested equal on
the hard set, mode "ode_selfconsistent" within its flicker band).

Mode "stokes" takes none of this: Ennis' criterion sticks iff ``St_v <= (1 + 1/e)
ln(H0 / Ha)`` with ``St_v = m_r w / c`` rising in proportion to the speed (no body force,
no other speed dependence: :mod:`.stokes`), so the set of sticking speeds is ``[0, w*]``
and nothing above a rebounding ``u0*`` sticks: ``P = F(u0*)``, with no kernel evaluation.
"""

from __future__ import annotations

import numpy as np

from .auto import DEFAULT_TOL, auto_fused
from .fused import TIER_RELATIVE, fused_batch, prepare_flat
from .sticking import EXACT, MAX_WINDOWS, sticking_windows
from .tiers import evaluate

__all__ = ["U_RTOL", "TAIL", "NEAR", "SEED_OFFSETS", "MAX_BISECTIONS", "stick_indicator",
           "relative_seeds", "bracket", "collision_candidates",
           "candidate_rows"]

#: Relative width in speed to which a change of the stick indicator is bisected.
U_RTOL = 1e-12
#: Probability above the top candidate (taken as the indicator there).
TAIL = 1e-13
#: Candidates just above ``u0*``: ``u0* (1 + x)``.
NEAR = (1e-6, 1e-4, 1e-2)
#: Relative offsets of the seeds around each end of a "relative" window.
SEED_OFFSETS = (1e-3, 3e-2)
#: Collisions per kernel call (the inputs of a call are gathered into new arrays).
CHUNK = 1 << 17
#: Bisection steps allowed to one bracket (a geometric bisection from 1e-300 to 1e300 to
#: ``U_RTOL`` takes about 50).
MAX_BISECTIONS = 200


def _sub_inputs(ins, steps, idx, u):
    """The fused inputs of collisions ``idx`` (repeats allowed) at head-on speeds ``u``."""
    arrays = [a[idx] if s else a for a, s in zip(ins, steps, strict=True)]
    arrays[18] = np.ascontiguousarray(u, dtype=np.float64)
    arrays[19] = np.full(1, np.nan)  # u0_j: head-on (0 for a plate), as collide(u0_j=None)
    st = np.array(steps, dtype=np.int64)
    st[18], st[19] = 1, 0
    return tuple(np.ascontiguousarray(a) for a in arrays), st


def stick_indicator(ins, steps, tier, body, particle_slip):
    """``sticks(idx, u) -> (stuck, known)``: the verdict of ``tier`` (a fused tier code, or
    a mode name) on collisions ``idx`` of the fused inputs ``ins, steps`` at head-on speeds
    ``u`` (the arithmetic of :func:`agglomtool.collide` at those speeds; mode "auto" at its
    default tolerance, as scenes run it), and where it is known (``e_w`` not NaN)."""

    def sticks(idx, u):
        m = int(np.size(idx))
        if m > CHUNK:
            parts = [sticks(idx[k:k + CHUNK], u[k:k + CHUNK]) for k in range(0, m, CHUNK)]
            return (np.concatenate([a for a, _ in parts]),
                    np.concatenate([b for _, b in parts]))
        if m == 0:
            return np.zeros(0, dtype=bool), np.zeros(0, dtype=bool)
        sub, st = _sub_inputs(ins, steps, idx, u)
        if tier == "auto":
            e_w = auto_fused(sub, st, m, body=body, particle_slip=particle_slip,
                             tol=DEFAULT_TOL)[0]
        elif isinstance(tier, str):
            k = prepare_flat(sub, st, m, body, particle_slip)
            e_w = evaluate(tier, *k[:13], details=False)[0]
        else:
            e_w = fused_batch(sub, st, m, tier, body=body, particle_slip=particle_slip)[0]
        return e_w == 0.0, ~np.isnan(e_w)

    return sticks


def relative_seeds(ins, steps, n, u_star, body):
    """Seed speeds per collision (``(n, 5 * MAX_WINDOWS + ...)`` float64, NaN where none)
    from mode "relative"'s compiled windows above ``u_star`` (per collision) with the body
    forces ``body`` and the emulsion's slip: each window's middle and the speeds
    :data:`SEED_OFFSETS` inside and outside each finite end."""
    lo, hi, count, status = sticking_windows(ins, steps, n, TIER_RELATIVE, u_star, body=body,
                                             particle_slip=False)
    cols = []
    for k in range(MAX_WINDOWS):
        has = (count > k) & (status == EXACT)
        a = np.where(has, lo[:, k], np.nan)
        b = np.where(has & np.isfinite(hi[:, k]), hi[:, k], np.nan)
        cols.append(np.sqrt(a) * np.sqrt(b))
        for x in SEED_OFFSETS:
            cols += [a * (1.0 - x), a * (1.0 + x), b * (1.0 - x), b * (1.0 + x)]
        # an unbounded window: two speeds above its start
        cols.append(np.where(np.isnan(b), a * 2.0, np.nan))
    return np.stack(cols, axis=1)


def bracket(sticks, coll, cand, pre=None, rtol=U_RTOL):
    """The stick indicator of the rows ``coll`` (collision per row) along their candidate
    speeds ``cand`` (``(m, K)``, each row sorted ascending, finite, ``>= 0``; a repeated
    speed is evaluated once). ``pre``: verdicts known beforehand, ``(m, K)`` float (1
    sticks, 0 rebounds, -1 no verdict, NaN not known: evaluated here).

    Returns ``(stuck, cross, ok)``: ``stuck`` ``(m, K)`` the verdicts at the candidates
    (a speed of 0 takes the next candidate's: it cannot collide), ``cross`` ``(m, K - 1)``
    the speed at which the indicator changes between candidates ``j`` and ``j + 1``
    (bisected to ``rtol``; ``cand[:, j + 1]`` where it does not change), ``ok`` ``(m,)``
    false where a verdict was unknown or a bisection did not settle."""
    m, k_n = cand.shape
    new = np.ones((m, k_n), dtype=bool)
    new[:, 1:] = cand[:, 1:] != cand[:, :-1]
    new &= cand > 0.0
    stuck = np.zeros((m, k_n), dtype=bool)
    ok = np.ones(m, dtype=bool)
    if pre is None:
        pre = np.full((m, k_n), np.nan)
    given = new & ~np.isnan(pre)
    stuck[given] = pre[given] == 1.0
    ok &= ~np.any(given & (pre == -1.0), axis=1)
    rows, cols = np.nonzero(new & ~given)
    s, known = sticks(coll[rows], cand[rows, cols])
    stuck[rows, cols] = s
    np.logical_and.at(ok, rows, known)
    for j in range(1, k_n):  # a repeated speed: the verdict of its first occurrence
        rep = ~new[:, j] & (cand[:, j] > 0.0)
        stuck[rep, j] = stuck[rep, j - 1]
    for j in range(k_n - 2, -1, -1):  # a speed of 0: the next candidate's verdict
        zero = ~(cand[:, j] > 0.0)
        stuck[zero, j] = stuck[zero, j + 1]
    cross = np.array(cand[:, 1:], dtype=float)
    rows, cols = np.nonzero(stuck[:, 1:] != stuck[:, :-1])
    if rows.size:
        lo = cand[rows, cols].copy()
        hi = cand[rows, cols + 1].copy()
        lo_sticks = stuck[rows, cols]
        live = np.ones(rows.size, dtype=bool)
        for _ in range(MAX_BISECTIONS):
            live &= hi - lo > rtol * hi
            at = np.flatnonzero(live)
            if at.size == 0:
                break
            mid = np.where(lo[at] > 0.0, np.sqrt(lo[at]) * np.sqrt(hi[at]),
                           0.5 * (lo[at] + hi[at]))
            s, known = sticks(coll[rows[at]], mid)
            bad = ~known
            if bad.any():
                ok[rows[at[bad]]] = False
                live[at[bad]] = False
            up = known & (s == lo_sticks[at])
            down = known & ~up
            lo[at[up]] = mid[up]
            hi[at[down]] = mid[down]
        ok[rows[live]] = False  # did not settle
        cross[rows, cols] = 0.5 * (lo + hi)
    return stuck, cross, ok


def collision_candidates(sticks, colls, u_star, seeds):
    """The candidates that depend on the collision alone, evaluated once per collision:
    ``u_star`` (``(n,)``, of the collisions ``colls``), the speeds :data:`NEAR` above it
    and the ``seeds`` (``(n, S)``, NaN where none). Returns ``(speeds, verdicts)``, both
    ``(n, 1 + len(NEAR) + S')`` (the seed columns that hold a seed), the verdicts as
    :func:`bracket`'s ``pre`` (NaN where the speed is NaN or 0)."""
    us = u_star[:, None]
    near = us * (1.0 + np.asarray(NEAR))[None, :]
    seeds = np.where(seeds > us, seeds, np.nan)
    seeds = seeds[:, ~np.all(np.isnan(seeds), axis=0)]
    speeds = np.concatenate([us, near, seeds], axis=1)
    pre = np.full(speeds.shape, np.nan)
    r, c = np.nonzero(speeds > 0.0)
    s, known = sticks(colls[r], speeds[r, c])
    pre[r, c] = np.where(known, s.astype(float), -1.0)
    return speeds, pre


def candidate_rows(col_speeds, col_pre, nodes, top):
    """The rows of :func:`bracket`: the collision's candidates (``col_speeds``,
    ``col_pre`` of :func:`collision_candidates`, one row per element) with the law's
    ``nodes`` (``(m, N)``) and ``top`` (``(m,)``), those above ``top`` dropped; sorted per
    row (a dropped speed repeats the row's last). Returns ``(cand, pre)``."""
    m = nodes.shape[0]
    speeds = np.concatenate([col_speeds, nodes, top[:, None]], axis=1)
    pre = np.concatenate([col_pre, np.full((m, nodes.shape[1] + 1), np.nan)], axis=1)
    speeds[:, 1:col_speeds.shape[1]] = np.where(
        col_speeds[:, 1:] < top[:, None], col_speeds[:, 1:], np.nan)
    order = np.argsort(speeds, axis=1)  # NaN last
    speeds = np.take_along_axis(speeds, order, axis=1)
    pre = np.take_along_axis(pre, order, axis=1)
    last = np.nanmax(speeds, axis=1, keepdims=True)
    return np.where(np.isnan(speeds), last, speeds), pre

