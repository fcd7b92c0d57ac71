"""The paper's generalized energy-balance model of one binary wet collision (mode "paper").

Shabanian, Duchesne, Syamlal, Runstedtler (2024), Generalized analytical energy balance
model for binary collisions of wet particles, Heliyon 10:e29397,
doi:10.1016/j.heliyon.2024.e29397, Sections 2.2-2.3.5, Fig. 3 and Table 1, as specified and
corrected as listed in docs/model.md ("Corrections to the printed equations").

The kernel is scalar code compiled with Numba and run over flat arrays in parallel. Inputs
per collision, all SI:

- ``m_i, m_j``: wet masses [kg] (Eqs. 32-33); ``inf`` for a plate (not both);
- ``r``: harmonic-mean solid radius [m] (Eq. 3; ``2 r_i`` for a plate);
- ``H0, Ha``: gap at first liquid contact and at solid contact [m];
- ``mu_l, gamma, cos_t, theta``: liquid viscosity [Pa s], surface tension [N/m], cosine of
  the contact angle and the angle itself [rad];
- ``w``: relative normal impact speed ``u_i - u_j`` > 0 [m/s];
- ``fn_i, fn_j``: net body forces on i and on j projected on ``n`` (from i towards j) [N];
- ``e``: dry restitution coefficient [-].

Notation inside: the CM-frame speeds are ``v_i = frac_j w`` and ``v_j = frac_i w`` with the
mass fractions ``frac_i = m_i / (m_i + m_j)``; so the paper's distance shares
``v_i / (v_i + v_j)`` (Eqs. 13-16) are the mass fractions ``frac_j`` and ``frac_i``, and both
particles carry the same CM momentum ``P = m_r w`` (``m_r`` the reduced mass). Energies are
written through ``m_r`` so that a plate (infinite mass, zero CM speed) gives exact zeros,
never ``inf * 0``.

Per-particle viscous loss over a stretch with ``Delta = |ln f(D_a) - ln f(D_b)|``, for a
particle of mass ``m`` entering it at speed ``v`` (exact solution of the viscous-only
equation of motion, Eqs. 72-75, 88-90, 95-97, the printed forms rearranged)::

    L = c Delta (v - c Delta / (2 m)),   c = (3/2) pi mu_l r^2

valid while ``c Delta < m v``, which every caller checks first.
"""

from __future__ import annotations

import math

from numba import njit, prange

from .._jit import CACHE, parallel_launch
from . import _codes as codes
from . import stages
from .bridge import (
    bridge_volume,
    g_change,
    g_diff,
    gap_parts,
    ln_f_change,
    ln_f_diff_from,
)
from .physics import reduced_mass
from .records import Gap, Mover, StageResult, TierInputs, pair_at, tier_inputs

__all__ = ["paper_kernel", "run_paper"]

# Integer codes frozen into the compiled kernel.


#: Points of the geometric scan that isolates the first zero of a running energy before the
#: bracketed solve (Eq. 136 need not be monotonic). Adjacent points differ by the factor
#: ``(D_end / D_start)^(1/32)``: a dip below zero narrower than that can be missed.
SCAN_POINTS = 32


@njit(cache=CACHE)
def _running_energy(D, start, mover, bridge):
    """Energy left [J] to a particle (``mover``, a :class:`~.records.Mover`) at gap ``D``
    of a stage that began at the gap ``start`` (a :class:`~.records.Gap`), both particles
    moving (Eqs. 136-139 and their separation mirror); ``bridge`` a
    :class:`~.records.Bridge`.

    ``mover.share`` is the particle's fraction of the gap change, ``mover.f`` the body force
    projected on its direction of motion relative to the partner (Eqs. 118-119, 124-125).
    """
    d_start, _, start_kind, start_val = start
    k, v, share, m, force = mover
    c, kcap, a2 = bridge
    cap = share * kcap * g_diff(d_start, D, a2)
    vis = stages.viscous_loss(v, m, c * abs(ln_f_diff_from(start_kind, start_val, D, a2)))
    return k - cap - vis + force * share * abs(D - d_start)


@njit(cache=CACHE)
def _cap_vis(D, start, mover, bridge):
    """The capillary and viscous terms of :func:`_running_energy` at ``D`` [J], bitwise as
    there, with ``start.s = sqrt(d_start^2 + a^2)`` given and ``sqrt(D^2 + a^2)`` taken once
    for both (:func:`~.bridge.g_diff` and :func:`~.bridge.ln_f_parts` each take it)."""
    _, v, share, m, _ = mover
    c, kcap, a2 = bridge
    at = Gap(D, *gap_parts(D, a2))
    return (share * kcap * g_change(start, at, a2),
            stages.viscous_loss(v, m, c * abs(ln_f_change(start, at))))


@njit(cache=CACHE)
def _next_step(i, pos, fail_at, fail_val, default):
    """Points to try skipping next from point ``i`` with a positive bound ``pos`` there:
    short of where the line to the last unproven floor (``fail_val`` at point ``fail_at``)
    crosses zero, or ``default`` when no such point lies ahead."""
    gap = fail_at - i
    if gap <= 0:
        return default
    if gap == 1:
        return 1
    return max(1, min(int(gap * pos / (pos - fail_val)), gap - 1))


@njit(cache=CACHE)
def _first_zero(start, d_end, mover, bridge):
    """The gap between ``d_start = start.d`` and ``d_end`` nearest ``d_start`` where the
    running energy of :func:`_running_energy` (same arguments) first reaches zero (Eq. 136).

    ``E(d_start) = k > 0`` and ``E(d_end) <= 0`` on entry. The first of the
    :data:`SCAN_POINTS` geometric points ``d_start q^j`` with ``E <= 0`` is located, then the
    Illinois variant of regula falsi narrows the bracket it makes with the point before to a
    relative width of 1e-12 (every iterate stays inside the bracket; at most 100 steps).

    The first point with ``E <= 0`` is found without evaluating every point. Each term of
    the running energy is monotonic in the distance travelled: the capillary term (``g``
    increases with the gap), the viscous loss (``ln f`` increases with the gap, and the loss
    grows with ``c Delta`` while ``c Delta < m v``, which the stage checked over its whole
    length) and the body-force term (linear). Over a stretch of points the energy is
    therefore at least ``k`` + the smaller end value of the capillary and body-force terms -
    the viscous loss at the far end; where that floor exceeds a rounding margin (1e-9 of the
    terms' size plus 1e-10 ``c v``: ``ln f`` carries an absolute error of a few 1e-15) every
    point of the stretch is positive and the stretch is skipped; otherwise the next stretch
    aims short of where the floor, interpolated linearly in the point index, crosses zero
    (:func:`_next_step`), and single points are evaluated exactly. The result is bitwise
    that of the plain scan (:func:`_first_zero_scan`, kept as the tests' reference): the
    same points, made by the same repeated products, evaluated by the same arithmetic, and
    the same regula falsi. On the mixed benchmark batch, when it also served the
    separations of wetting liquids (now :func:`_stop_gap`'s), a search cost 12 evaluations
    of the capillary and viscous terms, regula falsi included, instead of 32. It serves the
    approach and non-wetting liquids, where the energy need not be convex; a dip below zero
    narrower than the spacing of the points can still be missed, exactly as by the plain
    scan.
    """
    d_start, s_start, _, _ = start
    k, v, share, _, force = mover
    c, _, _ = bridge
    ratio = (d_end / d_start) ** (1.0 / SCAN_POINTS)
    fs = force * share
    last = SCAN_POINTS - 1  # points d_1 .. d_last are scanned; d_end closes the bracket
    i = 0  # index of the last point known to have E > 0 (d_0 = d_start, E = k)
    d_i = d_start
    f_i = k
    cap_i = 0.0
    f_known = True  # f_i holds E(d_i)
    step = SCAN_POINTS // 2
    pos = k  # a positive lower bound of E at d_i
    fail_at = -1  # a point up to which the floor was not positive, and its floor value
    fail_val = 0.0
    hi = d_end
    f_hi = 0.0
    found = False
    while i < last:
        step = min(step, last - i)
        if step > 1:
            d_b = d_i
            for _ in range(step):
                d_b = d_b * ratio
            cap_b, vis_b = _cap_vis(d_b, start, mover, bridge)
            f_a = fs * abs(d_i - d_start)
            f_b = fs * abs(d_b - d_start)
            scale = k + abs(cap_i) + abs(cap_b) + vis_b + abs(f_a) + abs(f_b)
            val = (k - max(cap_i, cap_b) - vis_b + min(f_a, f_b)
                   - (1e-9 * scale + 1e-10 * c * v))
            if val > 0.0:  # every point up to d_b is positive: skip them
                i += step
                d_i = d_b
                cap_i = cap_b
                f_known = False
                pos = val
                step = _next_step(i, pos, fail_at, fail_val, step)
                continue
            # Not proven: aim short of where the floor crosses zero (linear in the index).
            fail_at, fail_val = i + step, val
            step = max(1, min(int(step * pos / (pos - val)), step - 1))
            continue
        d = d_i * ratio
        cap, vis = _cap_vis(d, start, mover, bridge)
        f_d = k - cap - vis + force * share * abs(d - d_start)
        if f_d <= 0.0:
            hi, f_hi = d, f_d
            found = True
            break
        i += 1
        d_i, f_i, cap_i = d, f_d, cap
        f_known = True
        pos = f_d
        step = _next_step(i, pos, fail_at, fail_val, 2)
    if not found:
        f_hi = _running_energy(d_end, start, mover, bridge)
    lo = d_i
    if f_known:
        f_lo = f_i
    else:
        f_lo = _running_energy(d_i, start, mover, bridge)
    return _narrow(lo, f_lo, hi, f_hi, start, mover, bridge)


@njit(cache=CACHE)
def _narrow(lo, f_lo, hi, f_hi, start, mover, bridge):
    """The zero of the running energy (:func:`_running_energy`, evaluated as
    :func:`_cap_vis` gives its terms) in the bracket ``[lo, hi]`` with ``E(lo) = f_lo > 0``
    and ``E(hi) = f_hi <= 0``: the Illinois variant of regula falsi, to a relative width of
    1e-12. Every iterate stays inside the bracket and the loop is capped at 100 steps: it
    cannot run away. Returns the bracket's end where ``E <= 0``. ``start, mover, bridge``:
    the running energy's parameters (:func:`_first_zero`'s). Shared by :func:`_first_zero`
    and its reference :func:`_first_zero_scan`."""
    d_start = start.d
    k, _, share, _, force = mover
    side = 0
    for _ in range(100):
        if abs(hi - lo) <= 1e-12 * max(abs(hi), abs(lo)) or f_hi == 0.0:
            break
        x = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        if not (min(lo, hi) < x < max(lo, hi)):
            x = 0.5 * (lo + hi)
        cap, vis = _cap_vis(x, start, mover, bridge)
        f_x = k - cap - vis + force * share * abs(x - d_start)
        if f_x <= 0.0:
            hi, f_hi = x, f_x
            if side == -1:
                f_lo *= 0.5
            side = -1
        else:
            lo, f_lo = x, f_x
            if side == 1:
                f_hi *= 0.5
            side = 1
    return hi


@njit(cache=CACHE)
def _stop_residual(D, start, p, two_p_vs, force, bridge):
    """:func:`_stop_gap` 's residual ``G`` at the gap ``D`` [kg m/s] and ``dG / d ln D``."""
    d_start = start.d
    c, kcap, a2 = bridge
    at = Gap(D, *gap_parts(D, a2))
    s = at.s
    g = g_change(start, at, a2)
    c_delta = c * abs(ln_f_change(start, at))
    gp = a2 / (s * (D + s))
    qq = two_p_vs * (kcap * g - force * (D - d_start))
    if qq > 0.0:
        root = math.sqrt(qq)
        return ((p - c_delta) - root,
                -c * gp * gp - 0.5 * two_p_vs * D * (kcap * gp - force) / root)
    return p - c_delta, -c * gp * gp


@njit(cache=CACHE)
def _stop_gap(start, end, u_end, l_cap, p, v_sum, force, bridge):
    """The gap where a particle stops first in a separation stage of a wetting liquid
    (from the gap ``start`` to ``end``, :class:`~.records.Gap` records with
    ``end.d > start.d``; ``bridge.kcap >= 0``): :func:`_first_zero` of its running energy,
    solved through a better-conditioned residual.

    Why one zero. Over the stage ``c Delta < p`` (the stage checked it at its end), so the
    viscous loss ``c Delta (v - c Delta / (2 m))`` is an increasing concave function of
    ``Delta``, and ``Delta = ln f(D) - ln f(d_start)`` is increasing and concave in ``D``
    (``d ln f / dD = (s - D)^2 / (D s^2)`` decreases): the loss is concave. The capillary
    term ``share kcap (g(D) - g(d_start))`` is concave (``g'' = -a^2 / s^3``) for
    ``kcap >= 0`` and the body-force term is linear. So the running energy is convex; with
    ``E(d_start) = k > 0`` and ``E(d_end) <= 0`` its set ``E <= 0`` is one interval
    reaching ``d_end``: the first zero is the only one.

    The residual. Each particle enters the stage with ``k = p v / 2`` and ``m v = p``, so
    its running energy is ``E = (v / (2 p)) (u^2 - Q)`` with ``u = p - c Delta > 0`` and
    ``Q = (2 p / v_sum) (kcap (g(D) - g(d_start)) - force (D - d_start))``; its share of the
    gap change is ``v / v_sum`` (for a plate, per unit speed: ``v = 1``, the same form). So
    ``E <= 0`` exactly where ``G = u - sqrt(max(Q, 0)) <= 0``. ``E`` has a near-double
    zero where the viscous loss dominates (``u^2`` touches ``Q``); ``G`` crosses zero with
    a slope, so Newton converges fast on it.

    The method: Newton in ``ln D`` on the bracket ``[lo, hi]`` (``G(lo) > 0 >= G(hi)``),
    started at ``d_end`` from the stage's own end values (``u_end``, ``l_cap``: no
    evaluation); a step that leaves the bracket or does not halve the previous one is
    replaced by bisection in ``ln D``. It stops when the next Newton step ``dy`` would
    change ``D`` by less than a relative 1e-8 and 1e-4 ``l``, ``l = ln(D / d_start)``
    (taking it: the error left is of the order of ``dy^2 / (4 l)``, at most 2.5e-13; the
    ``l`` term guards a zero just past ``d_start``, where ``sqrt(Q)`` bends sharply), when
    the bracket's relative width is 1e-12, or after at most 100 steps: it cannot run away.
    On the mixed benchmark batch it takes 3.7 evaluations (the one at ``d_end`` comes free
    from the stage) where the skipping scan and regula falsi of :func:`_first_zero` took
    about 12. Its result agrees with the plain scan's
    (:func:`_first_zero_scan`) within 2e-12 plus the zero's own conditioning, 8 units of
    rounding of ``k`` over ``|dE / d ln D|`` (tested).
    """
    d_start = start.d
    d_end, s_end = end.d, end.s
    c, kcap, a2 = bridge
    two_p_vs = 2.0 * p / v_sum
    qq = two_p_vs * (l_cap - force * (d_end - d_start))
    x = d_end
    gp = a2 / (s_end * (d_end + s_end))
    if qq > 0.0:
        root = math.sqrt(qq)
        f = u_end - root
        df = -c * gp * gp - 0.5 * two_p_vs * d_end * (kcap * gp - force) / root
    else:
        f = u_end
        df = -c * gp * gp
    if f > 0.0:  # rounding: the energy at d_end is zero to its last digits
        return d_end
    lo, hi = d_start, d_end
    dy_old = math.log(d_end / d_start)
    for _ in range(100):
        newton = df < 0.0
        if newton:
            dy = -f / df
            # Converged: the error left after this step is of the order of dy^2 / (4 l),
            # with l = ln(x / d_start) (near d_start, G has the curvature of sqrt(Q)).
            if abs(dy) <= 1e-8 and abs(dy) <= 1e-4 * math.log(x / d_start):
                return x * math.exp(dy)
            xn = x * math.exp(dy)
            newton = lo < xn < hi and abs(dy) <= 0.5 * dy_old
        if not newton:
            dy = 0.5 * math.log(hi / lo)
            xn = lo * math.exp(dy)
            if not lo < xn < hi:  # the bracket is down to adjacent doubles
                return hi
        dy_old = abs(dy)
        f, df = _stop_residual(xn, start, p, two_p_vs, force, bridge)
        x = xn
        if f <= 0.0:
            hi = x
        else:
            lo = x
        if hi - lo <= 1e-12 * hi:
            return x
    return hi


@njit(cache=CACHE)
def _first_zero_scan(start, d_end, mover, bridge):
    """Reference of :func:`_first_zero`: the same result by evaluating every scan point.

    ``E(d_start) = k > 0`` and ``E(d_end) <= 0`` on entry. A geometric scan of
    :data:`SCAN_POINTS` points isolates the first sign change; the same regula falsi
    (:func:`_narrow`) then narrows that bracket.
    """
    d_start = start.d
    ratio = (d_end / d_start) ** (1.0 / SCAN_POINTS)
    lo, f_lo = d_start, mover.k  # energy > 0 here
    hi = d_end  # energy <= 0 here
    f_hi = _running_energy(d_end, start, mover, bridge)
    d = d_start
    for _ in range(SCAN_POINTS - 1):
        d = d * ratio
        f_d = _running_energy(d, start, mover, bridge)
        if f_d <= 0.0:
            hi, f_hi = d, f_d
            break
        lo, f_lo = d, f_d
    return _narrow(lo, f_lo, hi, f_hi, start, mover, bridge)


@njit(cache=CACHE, inline="always")
def _stage(start, end, mover_i, mover_j, p, bridge):
    """One liquid stage (approach ``H0 -> Ha`` or separation ``Ha -> h_rupt``).

    ``start, end``: the two gaps with their :func:`~.bridge.gap_parts`
    (:class:`~.records.Gap`, computed once by the caller: the approach's end is the
    separation's start); ``mover_i, mover_j`` (:class:`~.records.Mover`): energies at the
    start [J], CM-frame speeds [m/s], each particle's share of the gap change (Eqs. 13-16:
    ``v_i / (v_i + v_j)``, which is the mass fraction ``frac_j``), masses [kg] and body
    forces along each particle's motion relative to its partner [N]; ``p``: the common CM
    momentum [kg m/s]; ``bridge`` the force constants (:class:`~.records.Bridge`). Returns
    a :class:`~.records.StageResult`: ``code`` 0 (both go on), 1 (viscous stop), 2 (energy
    spent), 3 (the lone mover runs out), 4 (viscosity stops the lone mover); ``flags`` 1 if
    i stopped first, 2 if j did; ``d_stop`` NaN when nobody stopped. Losses are those of the
    ordinary path (both moving over the whole stage).
    """
    d_start, d_end = start.d, end.d
    k_i, v_i, share_i, m_i, f_i = mover_i
    k_j, v_j, share_j, m_j, f_j = mover_j
    c, kcap, a2 = bridge
    nan = math.nan
    # ln f differences are formed from the gaps' parts as ln_f_diff_from forms them (bitwise);
    # |Delta ln f| for either direction in one expression (the relative-motion tiers sign it
    # by the direction, stages.stage_losses); each particle's share of the losses and its
    # own stop are the paper's frame (stages module docstring).
    c_delta = c * abs(ln_f_change(start, end))
    dist = abs(d_end - d_start)
    l_cap = kcap * g_change(start, end, a2)
    if not c_delta < p:  # viscosity alone stops both (Eqs. 73, 80 / 75, 82); also Delta = inf
        return StageResult(1, 0.0, 0.0, nan, 0, l_cap, nan, nan, nan)
    # Each particle carries the CM momentum p = m v, so its viscous loss (viscous_loss)
    # is c Delta v (1 - c Delta / (2 p)): one division for both, and the keep factor lies in
    # (1/2, 1] (no cancellation). A plate (v = 0) loses nothing, as there.
    keep = 1.0 - 0.5 * c_delta / p
    l_vis = c_delta * (v_i + v_j) * keep
    l_bdw_i = -f_i * share_i * dist
    l_bdw_j = -f_j * share_j * dist
    e_i = k_i - share_i * l_cap - c_delta * v_i * keep - l_bdw_i
    e_j = k_j - share_j * l_cap - c_delta * v_j * keep - l_bdw_j
    # A plate (infinite mass, zero CM speed) is the limit of a partner far heavier than the
    # particle: its energy and share vanish, but its running energy per unit CM speed stays
    # finite. With k/v = p/2, share/v = 1/(v_i + v_j) and m v = p, that ratio is the running
    # energy of a unit-speed particle of mass p (the same functions, scaled arguments); its
    # sign decides whether the plate "stops first" (a viscous-dominated approach) or the
    # particle takes the ordinary path with share 1.
    v_sum = v_i + v_j
    s_i = e_i
    s_j = e_j
    if math.isinf(m_i):
        s_i = 0.5 * p - l_cap / v_sum - c_delta * keep + f_i * dist / v_sum
    if math.isinf(m_j):
        s_j = 0.5 * p - l_cap / v_sum - c_delta * keep + f_j * dist / v_sum
    if s_i > 0.0 and s_j > 0.0:
        return StageResult(0, e_i, e_j, nan, 0, l_cap, l_vis, l_bdw_i, l_bdw_j)
    if s_i <= 0.0 and s_j <= 0.0:
        return StageResult(2, 0.0, 0.0, nan, 0, l_cap, l_vis, l_bdw_i, l_bdw_j)
    # One particle stops first (x); the other (y) goes on alone (Section 2.3.5, Eqs. 136-145).
    if s_i <= 0.0:
        flag = 1
        x = mover_i
        k_y, v_y, share_y, m_y, f_y = mover_j
    else:
        flag = 2
        x = mover_j
        k_y, v_y, share_y, m_y, f_y = mover_i
    if x.k <= 0.0 and not math.isinf(x.m):
        d_stop = d_start  # zero energy from the start: it never moves
    else:
        if math.isinf(x.m):
            # The plate stops first: where its running energy per unit speed reaches zero.
            z = Mover(0.5 * p, 1.0, 1.0 / v_sum, p, x.f)
        else:
            z = x
        if d_end > d_start and kcap >= 0.0:  # a separation, wetting: one zero
            d_stop = _stop_gap(start, end, p - c_delta, l_cap, p, v_sum, x.f, bridge)
        else:
            d_stop = _first_zero(start, d_end, z, bridge)
    dist_1 = abs(d_stop - d_start)
    dist_2 = abs(d_end - d_stop)
    # Eqs. 39-42, 140-142 (Eq. 142 read as Eq. 140: particle j's own share and force).
    stop = Gap(d_stop, *gap_parts(d_stop, a2))
    k_mid = (
        k_y
        - (share_y * kcap * g_change(start, stop, a2) + kcap * g_change(stop, end, a2))
        - stages.viscous_loss(v_y, m_y, c * abs(ln_f_change(start, stop)))
        + f_y * (share_y * dist_1 + dist_2)
    )
    if k_mid <= 0.0:
        return StageResult(3, 0.0, 0.0, d_stop, flag, l_cap, l_vis, l_bdw_i, l_bdw_j)
    v_mid = math.sqrt(2.0 * k_mid / m_y)  # Eqs. 40-41
    c_delta_2 = c * abs(ln_f_change(stop, end))
    if not c_delta_2 < m_y * v_mid:  # Eq. 144
        return StageResult(4, 0.0, 0.0, d_stop, flag, l_cap, l_vis, l_bdw_i, l_bdw_j)
    k_end_y = k_mid - stages.viscous_loss(v_mid, m_y, c_delta_2)  # Eqs. 37b, 145
    if flag == 1:
        return StageResult(0, 0.0, k_end_y, d_stop, flag, l_cap, l_vis, l_bdw_i, l_bdw_j)
    return StageResult(0, k_end_y, 0.0, d_stop, flag, l_cap, l_vis, l_bdw_i, l_bdw_j)


@njit(cache=CACHE, inline="always")
def _stage_path(det, separation, res):
    """The path flag of the stage ``res`` (a :class:`~.records.StageResult` of the approach,
    or of the separation where ``separation``): which particle stopped first, if one did;
    its losses and stop gap written to the details where ``det`` has length."""
    if det.shape[0] > 0:
        if separation:
            det[codes.L_CAP_SEP] = res.l_cap
            det[codes.L_VIS_SEP] = res.l_vis
            det[codes.L_BDW_SEP_I] = res.l_bdw_i
            det[codes.L_BDW_SEP_J] = res.l_bdw_j
            det[codes.D_STOP_SEP] = res.d_stop
        else:
            det[codes.L_CAP_APP] = res.l_cap
            det[codes.L_VIS_APP] = res.l_vis
            det[codes.L_BDW_APP_I] = res.l_bdw_i
            det[codes.L_BDW_APP_J] = res.l_bdw_j
            det[codes.D_STOP_APP] = res.d_stop
    if res.flags == 1:
        return codes.P_SEP_I if separation else codes.P_APP_I
    if res.flags == 2:
        return codes.P_SEP_J if separation else codes.P_APP_J
    return 0


@njit(cache=CACHE)
def paper_kernel(pair, w, det):
    """One collision (``pair`` a :class:`~.records.Pair`, relative normal impact speed
    ``w`` [m/s]) by the paper's flow chart. Returns ``(e_w, stage, path)``.

    ``det`` is a float64 array of length ``len(DETAIL_NAMES)`` to fill, or of length 0.
    """
    m_i, m_j, r, H0, Ha, mu_l, gamma, _, theta, fn_i, fn_j, e = pair
    want = stages.fresh_details(det)
    # Mass fractions and reduced mass, exact for a plate on either side.
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    path = 0
    # No bridge can form: a dry collision, no liquid losses at all.
    if not H0 > Ha:
        return stages.dry_contact(det, m_r, e, w)

    bridge = stages.bridge_constants(pair)  # Eqs. 25-26, 29-30
    c, kcap, a2 = bridge

    # ---- approach, H0 -> Ha (Eqs. 34-45, 72-73, 79-80, 88-90, 100-103, 112-119, 126-127)
    p = m_r * w
    k_i = 0.5 * p * frac_j * w
    k_j = 0.5 * p * frac_i * w
    if want:
        det[codes.K_INI_I] = k_i
        det[codes.K_INI_J] = k_j
        det[codes.ST_APP] = p / c
    gap_h0 = Gap(H0, *gap_parts(H0, a2))
    gap_ha = Gap(Ha, *gap_parts(Ha, a2))
    res = _stage(gap_h0, gap_ha, Mover(k_i, frac_j * w, frac_j, m_i, fn_i),
                 Mover(k_j, frac_i * w, frac_i, m_j, -fn_j), p, bridge)
    path |= _stage_path(det, False, res)
    if res.code != 0:
        return 0.0, res.code, path  # codes 1-4 are the approach stages
    ka_i, ka_j = res.k_end_i, res.k_end_j
    if want:
        det[codes.K_APP_I] = ka_i
        det[codes.K_APP_J] = ka_j

    # ---- contact (Eqs. 44-55, 131-135): new CM frame, restitution along n
    w_c = math.sqrt(2.0 * ka_i / m_i) + math.sqrt(2.0 * ka_j / m_j)
    w_s = e * w_c
    if want:
        stages.contact_details(det, m_r, e, w_c)
    if not w_s > 0.0:
        return 0.0, codes.CONTACT, path
    p_s = m_r * w_s
    ks_i = 0.5 * p_s * frac_j * w_s
    ks_j = 0.5 * p_s * frac_i * w_s

    # ---- separation, Ha -> h_rupt (Eqs. 56-66, 74-75, 81-82, 91-97, 101, 104-105, 120-129)
    vol3 = bridge_volume(r, a2) ** (1.0 / 3.0)  # as rupture_distance takes it
    ca, h_rupt = stages.rupture_at(w_s, mu_l, gamma, theta, vol3)
    if want:
        stages.rupture_details(det, ks_i, ks_j, ca, h_rupt)
    if not h_rupt > Ha:
        path |= codes.P_BROKEN
        kf_i, kf_j = ks_i, ks_j
    else:
        res = _stage(gap_ha, Gap(h_rupt, *gap_parts(h_rupt, a2)),
                     Mover(ks_i, frac_j * w_s, frac_j, m_i, -fn_i),
                     Mover(ks_j, frac_i * w_s, frac_i, m_j, fn_j), p_s, bridge)
        path |= _stage_path(det, True, res)
        if res.code != 0:
            return 0.0, codes.SEP_VIS + res.code - 1, path
        kf_i, kf_j = res.k_end_i, res.k_end_j
    if want:
        det[codes.K_FIN_I] = kf_i
        det[codes.K_FIN_J] = kf_j
    # Eq. 31 with Eqs. 67-70: the final CM-frame speeds add up to the relative speed.
    v_rel = math.sqrt(2.0 * kf_i / m_i) + math.sqrt(2.0 * kf_j / m_j)
    e_w = v_rel / w
    if not e_w > 0.0:
        # The energy left underflowed (e ~ 1e-200 makes K ~ 1e-400 J): nothing measurable
        # leaves the contact, a stick with the separation's energy spent.
        return 0.0, codes.SEP_EN, path
    return e_w, codes.REBOUND, path


@njit(parallel=True, cache=CACHE)
def _run_paper_batch(ins, e_w, stage, path, det):
    for k in prange(e_w.shape[0]):
        ew, st, pa = paper_kernel(pair_at(ins, k), ins.w[k], det[k])
        e_w[k] = ew
        stage[k] = st
        path[k] = pa


def run_paper(ins: TierInputs, *, details=False):
    """Evaluate :func:`paper_kernel` over the 1-D float64 arrays of equal length ``ins`` (a
    :class:`~.records.TierInputs`, or the same arrays in its order).

    Returns ``(e_w, stage, path, det)``; ``det`` has shape ``(n, len(DETAIL_NAMES))`` when
    ``details`` is true, else ``(n, 0)``.
    """
    ins = tier_inputs(ins)
    n = ins.w.shape[0]
    e_w, stage, path, det = stages.tier_outputs(n, details)
    parallel_launch(_run_paper_batch, ins, e_w, stage, path, det)
    return e_w, stage, path, det
