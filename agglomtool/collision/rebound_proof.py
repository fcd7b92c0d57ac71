"""Proof that modes "paper" and "relative" rebound at every speed of an interval.

The bracketed propensity (:mod:`.sticking_bracketed`) evaluates the tier's kernel at the
speed law's nodes above ``u0*`` to find where the pair sticks again. Far above ``u0*``
nearly every pair rebounds, and in modes "paper" and "relative" that can be proven for a
whole interval of speeds at once, with no kernel evaluation, from the closed forms the
kernels are made of. This module gives that proof; the bracketing then skips the
candidates inside it. It serves the settings that have no closed-form sticking set: body
forces on the axis in mode "paper", and the drag's slip from the particle's own speed in
either mode.

The bound
---------
Both kernels take each liquid stage with the viscous loss ``c Delta v (1 - c Delta /
(2 p))`` (``p = m_r v``, the stage's momentum, which in the paper's frame each particle
carries), the capillary loss ``l_cap = kcap (g(end) - g(start))`` and the work of the body
forces over the stage's length ``dist``. In mode "paper" particle i's energy at the end of
a stage entered at relative speed ``v`` is ``frac_j`` times

    A = m_r (v - c Delta / m_r)^2 / 2 - l_cap + f dist,

``f`` its own force along its motion relative to the partner (``fn_i`` on the approach,
``-fn_i`` on the separation; ``-fn_j`` and ``fn_j`` for particle j, with ``frac_i``); in
mode "relative" the one energy of the relative motion has the same form with
``f = f_b = frac_j fn_i - frac_i fn_j``. Viscosity alone stops a stage unless
``v > c Delta / m_r``, and above that speed ``A`` rises with ``v``. So over relative impact
speeds ``w_a <= w <= w_b``, with ``phi <= f <= psi``:

- the approach leaves between ``A_lo = A(w_a, phi)`` and ``A_hi = A(w_b, psi)``;
- the contact sends the pair apart at ``w_s = e sqrt(2 A / m_r)`` (mode "paper" adds the
  two particles' speeds, ``sqrt(2 frac_j A_i / m_i) + sqrt(2 frac_i A_j / m_j)``, which lies
  between the same bounds, ``sqrt(frac_j / m_i) + sqrt(frac_i / m_j)`` being
  ``1 / sqrt(m_r)``), so ``w_s`` lies in ``[ws_lo, ws_hi]``;
- the rupture gap ``(1 + theta/2) (1 + sqrt(mu_l w_s / gamma)) V^(1/3)`` rises with
  ``w_s``, and the separation's ``c Delta``, capillary loss (the larger gap for a wetting
  liquid, ``kcap >= 0``; the smaller for a non-wetting one) and body work are each
  monotonic in that gap, so each is bounded at an end of its range; the separation then
  leaves at least ``B_lo = m_r (ws_lo - c Delta_max / m_r)^2 / 2 - l_cap_max + (its least
  body work)``.

Where ``w_a > c Delta_app / m_r``, ``A_lo > 0``, ``ws_lo > c Delta_max / m_r`` and
``B_lo > 0`` every test of the kernels passes at every speed of the interval: both stages
go through and energy is left, so the pair rebounds (:func:`energy_floors`,
:func:`rebounds_between`). Each inequality must hold by :data:`MARGIN` of its terms' size,
far above the rounding of the bound and of the kernels.

The body forces: without the drag's slip from the particle's own speed they do not depend
on the speed (``fn_i``, ``fn_j`` of :func:`.fused.prepare_one`); with it they are bounded
over the interval by :func:`.fused.body_force_range`: each is monotonic in the speed (the
drag's projection on the axis falls for particle i and rises for particle j as the speed
grows), so it lies between its values at the interval's ends.

One particle stopping first (mode "paper")
------------------------------------------
Just above ``u0*`` the bound above fails in mode "paper" with a body force on the axis:
there the particle whose force works against its motion (``x``) stops in the
separation, and its partner (``y``) goes on alone and leaves with little energy (the
kernel's path of Section 2.3.5). That band, 1-3 % above ``u0*`` for the water pairs of
the benchmarks, is where most of the law's nodes lie when ``u0*`` sits in the speed
law's tail. :func:`survivor_floors` bounds that path over an interval as well.

Write ``p = m_r w_s`` (the momentum each particle carries in the separation), ``L`` the
``ln f`` of a gap, ``g`` its capillary potential, ``h`` the rupture gap and ``d`` the gap
where ``x`` stops. ``x`` stops where its running energy reaches zero, which has the sign
of

    G_x(D) = (p - c (L(D) - L(Ha)))^2 - 2 m_r (kcap (g(D) - g(Ha)) - f_x (D - Ha)),

rising with ``p`` (while ``p > c Delta``, which the stage checks) and with ``f_x``;
``G_x`` is convex in ``D`` for a wetting liquid (:func:`.paper._stop_gap`), so where the
kernel takes this path (``G_x(h) <= 0``) the set ``G_x <= 0`` is one interval reaching
``h``. A gap ``D_lo`` with ``G_x(D_lo) > 0`` at the interval's least ``p`` and ``f_x``
therefore lies below every stop of the interval, and a gap ``D_hi <= h`` with
``G_x(D_hi) <= 0`` at the largest ``p`` and ``f_x`` lies above every stop. The partner
leaves with energy exactly where

    R = (p - c Delta) (p - c Delta + 2 c (L(h) - L(d)))
        - 2 m_y kcap (g(h) - g(Ha) - s_x (g(d) - g(Ha)))
        + 2 m_y f_y ((h - Ha) - s_x (d - Ha)) > 0

(``Delta = L(h) - L(Ha)``, ``s_x`` the share of the gap change of ``x``, ``m_y`` the
partner's mass: the kernel's ``2 m_y k_mid - (c Delta_2)^2``, whose sign decides Eq. 144).
Each term is monotonic in ``p``, ``h`` and ``d``, so it is bounded at an end of their
ranges. Where ``x`` does not stop, both go on and the pair rebounds; both stop only where
``G_y(h) <= 0``, which the floor of ``G_y`` excludes. The opening speed is bounded from
each particle's own approach (its own force), not from the worse of the two: the band's
margin is a few parts in 1e4 of the terms. :func:`extended_down` proves intervals below
a proven speed with this bound, geometric in the distance from the floor; the
bracketing asks it down to an element's first node. The tests hold this bound, too, to
the kernel at random speeds of random intervals.

Mode "auto" is not served: where the proof holds for its closed forms it takes them only
where their error indicator is small enough, and bounding that indicator over an interval
(tried) cost as much as the closed-form evaluations it spared; the speeds where it
integrates, its dear ones, lie nearer ``u0*`` than any such proof reaches.

Which interval: :func:`proven_from` solves the inequalities for the lowest ``w_a`` below a
top speed (:func:`lowest_provable`, the rupture gap's bound taken at the top), checks that
interval, and repeats below it while that gains.

Not proven here (no interval is): a plate on either side (mode "paper" tracks a plate's
stop apart), no bridge (the kernels' dry contact), ``e = 0``, a final energy below
:data:`LEAST` of the impact's (it underflows in the kernels), and a pair whose bound fails.
The tests hold the bound to both kernels' own energies at random speeds of random
intervals (``tests/test_rebound_proof.py``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from .._jit import CACHE
from . import stages
from .bridge import bridge_volume, g_change, gap_parts, ln_f_change, rupture_gap
from .fused import TIER_PAPER, TIER_RELATIVE, body_force_range
from .paper import _stop_gap
from .physics import reduced_mass
from .records import Bridge, Gap, Pair

__all__ = ["MARGIN", "LEAST", "NUDGE", "ROUNDS", "STEP", "STEP_LEAST", "CHECKS",
           "ProofConstants", "proof_constants", "energy_floors", "rebounds_between",
           "lowest_provable", "floors_over", "rebounds_over", "proven_from",
           "survivor_floors", "survivor_floors_over", "survivor_over", "extended_down",
           "PAPER", "RELATIVE"]

#: Relative margin every inequality of the proof must clear, of the size of its terms.
MARGIN = 1e-9
#: Least final energy, over the impact's, that the proof accepts: a rebound with less
#: (a restitution coefficient below about 1e-100) underflows in the kernels to a stick.
LEAST = 1e-200
#: Relative step above :func:`lowest_provable`'s speed at which the proof is checked (its
#: inequalities then hold with room for :data:`MARGIN`).
NUDGE = 1e-3
#: Rounds of :func:`proven_from` (each proposes an interval below the last one proven).
ROUNDS = 3
#: :func:`extended_down`'s first step: the interval below a proven speed ``lo`` reaches
#: down to ``floor + (lo - floor) / (1 + STEP)``; the step doubles after an interval
#: proven (up to ``4 STEP``) and falls to a quarter after one that is not, down to
#: :data:`STEP_LEAST`.
STEP = 2.0
STEP_LEAST = 0.1
#: Intervals :func:`extended_down` checks at most.
CHECKS = 12
#: The kinds of :func:`proven_from`: the kernels of modes "paper" and "relative" (the fused
#: tiers' codes).
PAPER, RELATIVE = TIER_PAPER, TIER_RELATIVE


class ProofConstants(NamedTuple):
    """What the proof needs of one collision, none of it speed-dependent."""

    #: reduced mass [kg]
    m_r: float
    #: viscous constant ``c`` [kg m] and capillary constant ``kcap`` [N]
    c: float
    kcap: float
    #: ``a^2 = H0^2 - Ha^2`` [m2]
    a2: float
    #: the approach's ``c Delta`` [kg/s * m], capillary loss [J] and length [m]
    c_app: float
    l_app: float
    d_app: float
    #: the gap ``Ha`` with its parts (:class:`~.records.Gap`)
    gap_ha: tuple
    #: cube root of the bridge volume [m]
    vol3: float
    #: dry restitution coefficient [-]
    e: float
    #: ``mu_l / gamma`` [s/m] and the contact angle [rad]
    mu_per_gamma: float
    theta: float


@njit(cache=CACHE)
def proof_constants(pair):
    """``(ok, constants)`` of a :class:`~.records.Pair`; ``ok`` false where nothing is
    proven (a plate, no bridge, a NaN)."""
    m_i, m_j, r, H0, Ha, mu_l, gamma, _, theta, _, _, e = pair
    bridge = stages.bridge_constants(pair)
    c, kcap, a2 = bridge
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    gap_h0 = Gap(H0, *gap_parts(H0, a2))
    gap_ha = Gap(Ha, *gap_parts(Ha, a2))
    k = ProofConstants(m_r, c, kcap, a2, c * abs(ln_f_change(gap_h0, gap_ha)),
                       kcap * g_change(gap_h0, gap_ha, a2), H0 - Ha, gap_ha,
                       bridge_volume(r, a2) ** (1.0 / 3.0), e, mu_l / gamma, theta)
    # a mass ratio beyond 1e30 is left alone: a particle's share of the energy could
    # underflow in mode "paper"
    ok = (math.isfinite(m_i) and math.isfinite(m_j) and H0 > Ha and e > 0.0
          and min(frac_i, frac_j) > 1e-30
          and math.isfinite(k.c_app) and math.isfinite(k.l_app) and math.isfinite(k.vol3)
          and math.isfinite(k.mu_per_gamma) and math.isfinite(m_r) and m_r > 0.0)
    return ok, k


@njit(cache=CACHE)
def energy_floors(k, w_a, w_b, phi_a, psi_a, phi_s):
    """Lower bounds at every relative speed ``w_a <= w <= w_b`` [m/s] of the energy [J] the
    kernels leave at the end of the approach and of the separation (module docstring;
    mode "paper": each particle's energy over its partner's mass fraction) of the collision
    of constants ``k`` (:class:`ProofConstants`), its body forces bounded by
    ``phi_a <= f <= psi_a`` on the approach and ``f >= phi_s`` on the separation [N]
    (positive: along each particle's motion relative to its partner).

    Returns ``(a_lo, a_size, b_lo, b_size)``, each bound with the size of its terms; a bound
    is NaN where viscosity alone may stop its stage, ``b_lo`` also where ``a_lo <= 0``."""
    m_r, c, kcap, a2, c_app, l_app, d_app, gap_ha, vol3, e, mu_per_gamma, theta = k
    nan = math.nan
    if not (w_a > 0.0 and w_b >= w_a):
        return nan, nan, nan, nan
    # ---- the approach: viscosity alone does not stop it, and energy is left
    x_a = w_a - c_app / m_r  # the speed left by viscosity alone [m/s]
    x_b = w_b - c_app / m_r
    a_size = 0.5 * m_r * w_b * w_b + abs(l_app) + (abs(phi_a) + abs(psi_a)) * d_app
    if not x_a > MARGIN * w_a:
        return nan, a_size, nan, nan
    a_lo = 0.5 * m_r * x_a * x_a - l_app + phi_a * d_app
    a_hi = 0.5 * m_r * x_b * x_b - l_app + psi_a * d_app
    if not a_lo > 0.0:
        return a_lo, a_size, nan, nan
    # ---- the opening speeds and the rupture gaps (at least Ha: a broken bridge has none)
    ws_lo = e * math.sqrt(2.0 * a_lo / m_r)
    ws_hi = e * math.sqrt(2.0 * a_hi / m_r)
    ha = gap_ha.d
    h_lo = max(rupture_gap(theta, mu_per_gamma * ws_lo, vol3), ha)
    h_hi = max(rupture_gap(theta, mu_per_gamma * ws_hi, vol3), ha)
    top = Gap(h_hi, *gap_parts(h_hi, a2))
    c_sep = c * abs(ln_f_change(gap_ha, top))
    if kcap >= 0.0:
        l_sep = kcap * g_change(gap_ha, top, a2)
    else:
        l_sep = kcap * g_change(gap_ha, Gap(h_lo, *gap_parts(h_lo, a2)), a2)
    d_hi = h_hi - ha
    b_size = 0.5 * m_r * ws_hi * ws_hi + abs(l_sep) + abs(phi_s) * d_hi
    x_s = ws_lo - c_sep / m_r
    if not x_s > MARGIN * ws_lo:
        return a_lo, a_size, nan, b_size
    body = phi_s * (h_lo - ha) if phi_s >= 0.0 else phi_s * d_hi
    return a_lo, a_size, 0.5 * m_r * x_s * x_s - l_sep + body, b_size


@njit(cache=CACHE)
def rebounds_between(k, w_a, w_b, phi_a, psi_a, phi_s):
    """True where both floors of :func:`energy_floors` (same arguments) clear
    :data:`MARGIN` of their terms' size: the kernel rebounds at every relative speed of
    ``[w_a, w_b]``. False says nothing."""
    a_lo, a_size, b_lo, b_size = energy_floors(k, w_a, w_b, phi_a, psi_a, phi_s)
    return (a_lo > MARGIN * a_size and b_lo > MARGIN * b_size
            and b_lo > LEAST * (0.5 * k.m_r * w_b * w_b))


@njit(cache=CACHE)
def lowest_provable(k, w_b, phi_a, psi_a, phi_s):
    """The smallest relative speed ``w_a`` [m/s] for which :func:`rebounds_between` can hold
    on ``[w_a, w_b]`` with the rupture gap taken at its largest over the whole interval
    (``w_b``'s) and at ``Ha`` where its smaller value would help: the proof's inequalities
    solved for ``w_a``, the approach's and the separation's in turn. ``inf`` where even
    ``w_b`` cannot be proven. A proposal, which :func:`rebounds_between` then checks."""
    m_r, c, kcap, a2, c_app, l_app, d_app, gap_ha, vol3, e, mu_per_gamma, theta = k
    x_b = w_b - c_app / m_r
    a_hi = 0.5 * m_r * x_b * x_b - l_app + psi_a * d_app
    if not (x_b > 0.0 and a_hi > 0.0):
        return math.inf
    ha = gap_ha.d
    h_hi = max(rupture_gap(theta, mu_per_gamma * e * math.sqrt(2.0 * a_hi / m_r), vol3), ha)
    top = Gap(h_hi, *gap_parts(h_hi, a2))
    c_sep = c * abs(ln_f_change(gap_ha, top))
    l_sep = kcap * g_change(gap_ha, top, a2) if kcap >= 0.0 else 0.0
    body = phi_s * (h_hi - ha) if phi_s < 0.0 else 0.0
    ws_need = c_sep / m_r + math.sqrt(2.0 * max(l_sep - body, 0.0) / m_r)
    a_need = 0.5 * m_r * (ws_need / e) ** 2
    x_need = math.sqrt(2.0 * max(a_need + l_app - phi_a * d_app, 0.0) / m_r)
    w_a = c_app / m_r + x_need
    return w_a if w_a <= w_b else math.inf


@njit(cache=CACHE)
def _forces(kind, lo_i, hi_i, lo_j, hi_j, frac_i, frac_j):
    """``(phi_a, psi_a, phi_s)`` of :func:`rebounds_between` from ``lo_i <= fn_i <= hi_i``
    and ``lo_j <= fn_j <= hi_j`` [N]: each particle's own force in mode "paper" (``fn_i``
    and ``-fn_j`` on the approach, ``-fn_i`` and ``fn_j`` on the separation), the relative
    motion's ``f_b = frac_j fn_i - frac_i fn_j`` in mode "relative"."""
    if kind != PAPER:
        f_lo = frac_j * lo_i - frac_i * hi_j
        f_hi = frac_j * hi_i - frac_i * lo_j
        return f_lo, f_hi, -f_hi
    return min(lo_i, -hi_j), max(hi_i, -lo_j), min(-hi_i, lo_j)


@njit(cache=CACHE)
def _setup(kind, raw, vals, body, particle_slip):
    """``(ok, constants, frac_i, frac_j, slip, forces)`` of one collision for
    :func:`proven_from` and :func:`_interval`: ``slip`` where the drag depends on the
    speed (``forces`` then bounded per interval), else the constant ``forces``."""
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, _, _ = vals
    pair = Pair(m_i, m_j, r, H0, Ha, raw[8], raw[9], cos_t, theta, fn_i, fn_j, raw[17])
    ok, k = proof_constants(pair)
    _, frac_i, frac_j = reduced_mass(m_i, m_j)
    slip = False
    if particle_slip:
        if body:
            slip = True
    return ok, k, frac_i, frac_j, slip, _forces(kind, fn_i, fn_i, fn_j, fn_j, frac_i, frac_j)


@njit(cache=CACHE)
def _forces_between(kind, raw, lo, hi, frac_i, frac_j):
    """The forces' bounds of :func:`rebounds_between` at every head-on speed from ``lo`` to
    ``hi`` [m/s], the drag's slip from the particle's own speed
    (:func:`.fused.body_force_range`: each force lies between its values at the ends)."""
    lo_i, hi_i, lo_j, hi_j = body_force_range(raw, lo, hi)
    return _forces(kind, lo_i, hi_i, lo_j, hi_j, frac_i, frac_j)


@njit(cache=CACHE)
def _interval(kind, raw, vals, body, particle_slip, u_a, u_b):
    """``(ok, constants, w_a, w_b, forces)``: the proof's inputs over the head-on speeds
    ``u_a <= u <= u_b`` [m/s] (relative speeds ``w_a``, ``w_b``; the forces bounded over
    those speeds); arguments as :func:`proven_from`'s."""
    ok, k, frac_i, frac_j, slip, forces = _setup(kind, raw, vals, body, particle_slip)
    if slip:
        forces = _forces_between(kind, raw, u_a, u_b, frac_i, frac_j)
    wpu = vals[10]
    return ok, k, u_a * wpu, u_b * wpu, forces


@njit(cache=CACHE)
def floors_over(kind, raw, vals, body, particle_slip, u_a, u_b):
    """:func:`energy_floors` of the kernel ``kind`` (:data:`PAPER`, :data:`RELATIVE`) over
    the head-on speeds ``u_a <= u <= u_b`` [m/s]; arguments as :func:`proven_from`'s."""
    ok, k, w_a, w_b, forces = _interval(kind, raw, vals, body, particle_slip, u_a, u_b)
    if not ok:
        return math.nan, math.nan, math.nan, math.nan
    return energy_floors(k, w_a, w_b, *forces)


@njit(cache=CACHE)
def rebounds_over(kind, raw, vals, body, particle_slip, u_a, u_b):
    """True where the kernel ``kind`` (:data:`PAPER`, :data:`RELATIVE`) provably rebounds
    at every head-on speed ``u_a <= u <= u_b`` [m/s] (:func:`rebounds_between`); arguments
    as :func:`proven_from`'s."""
    ok, k, w_a, w_b, forces = _interval(kind, raw, vals, body, particle_slip, u_a, u_b)
    return ok and rebounds_between(k, w_a, w_b, *forces)


@njit(cache=CACHE)
def proven_from(kind, raw, vals, body, particle_slip, floor, top):
    """The lowest head-on speed ``W`` [m/s], ``floor <= W < top``, that this module proves
    the kernel ``kind`` (:data:`PAPER`, :data:`RELATIVE`) rebounds at, at
    every speed from ``W`` to ``top``; ``inf`` where none is proven. ``raw``: the
    collision's :class:`~.records.RawPair`; ``vals``: its :func:`.fused.prepare_one` at
    speed 0 under the flags ``body``, ``particle_slip``.

    Each of at most :data:`ROUNDS` rounds proposes the interval ``[W', hi]`` below the last
    one proven (``hi = top`` first) by :func:`lowest_provable`, ``W'`` nudged up by
    :data:`NUDGE` and at least ``floor``, and proves it (:func:`rebounds_between`); a
    later round gains where the smaller ``hi`` tightens the bounds of the rupture gap and
    of a drag that depends on the speed."""
    ok, k, frac_i, frac_j, slip, forces = _setup(kind, raw, vals, body, particle_slip)
    if not (ok and top > floor and floor > 0.0 and math.isfinite(top)):
        return math.inf
    wpu = vals[10]
    proven = math.inf
    hi = top
    for _ in range(ROUNDS):
        if slip:  # bounded from the floor (any lower end proposed lies above it)
            forces = _forces_between(kind, raw, floor, hi, frac_i, frac_j)
        lo = max(lowest_provable(k, hi * wpu, *forces) / wpu * (1.0 + NUDGE), floor)
        if not lo < hi:
            break
        if slip:  # and proven over the interval proposed, where they are tighter
            forces = _forces_between(kind, raw, lo, hi, frac_i, frac_j)
        if not rebounds_between(k, lo * wpu, hi * wpu, *forces):
            break
        proven = lo
        hi = lo
        if lo == floor:
            break
    return proven


@njit(cache=CACHE)
def _stop_sign(at, p, f, k):
    """``(G_x(D), size)``: the sign function of a separating particle's running energy at
    the gap ``at`` (a :class:`~.records.Gap`; module docstring: momentum ``p`` [kg m/s],
    its force ``f`` [N] along its motion) and the size of its terms."""
    m_r, c, kcap, a2 = k.m_r, k.c, k.kcap, k.a2
    ha = k.gap_ha
    u = p - c * abs(ln_f_change(ha, at))
    cap = kcap * g_change(ha, at, a2)
    work = f * (at.d - ha.d)
    return u * u - 2.0 * m_r * (cap - work), p * p + 2.0 * m_r * (abs(cap) + abs(work))


@njit(cache=CACHE)
def _first_stop(p, f, low, k):
    """The zero of :func:`_stop_sign` between ``Ha`` and the gap ``low`` (a
    :class:`~.records.Gap` with ``G_x(low) <= 0``): the kernel's own search
    (:func:`.paper._stop_gap`)."""
    c, kcap, a2 = k.c, k.kcap, k.a2
    ha = k.gap_ha
    return _stop_gap(ha, low, p - c * abs(ln_f_change(ha, low)), kcap * g_change(ha, low, a2),
                     p, p / k.m_r, f, Bridge(c, kcap, a2))


@njit(cache=CACHE)
def survivor_floors(k, w_a, w_b, forces, m_i, m_j):
    """Lower bounds over the relative speeds ``w_a <= w <= w_b`` [m/s] of mode "paper"'s
    separation where one particle may stop first (module docstring), for the collision of
    constants ``k`` (:class:`ProofConstants`, a wetting liquid), masses ``m_i``, ``m_j``
    [kg] and body forces ``forces = (lo_i, hi_i, lo_j, hi_j)``: ``lo_i <= fn_i <= hi_i``,
    ``lo_j <= fn_j <= hi_j`` [N] (:func:`.fused.prepare_one`'s, along the axis).

    Returns ``(r_lo, r_size, y_lo, y_size, x)``: the floor of ``R`` (the partner's
    survival where ``x`` stops first) and of ``G_y(h)`` (the partner's own running energy
    at the rupture gap on the ordinary path, in the units of ``G``), each with the size of
    its terms, and ``x`` (1: particle i stops first, 2: particle j); NaN floors and
    ``x = 0`` where the bound does not apply (a non-wetting liquid, forces whose ranges
    overlap, either particle stopped in the approach, a bridge broken at contact, or
    viscosity alone stopping the separation)."""
    m_r, c, kcap, a2, c_app, l_app, d_app, ha, vol3, e, mu_per_gamma, theta = k
    lo_i, hi_i, lo_j, hi_j = forces
    nan = math.nan
    fail = (nan, nan, nan, nan, 0)
    if not (kcap >= 0.0 and w_a > 0.0 and w_b >= w_a):
        return fail
    _, frac_i, frac_j = reduced_mass(m_i, m_j)
    # ---- the approach, each particle with its own force (fn_i; -fn_j for particle j)
    x_a = w_a - c_app / m_r
    x_b = w_b - c_app / m_r
    a_size = (0.5 * m_r * w_b * w_b + abs(l_app)
              + (abs(lo_i) + abs(hi_i) + abs(lo_j) + abs(hi_j)) * d_app)
    if not x_a > MARGIN * w_a:
        return fail
    base_lo = 0.5 * m_r * x_a * x_a - l_app
    base_hi = 0.5 * m_r * x_b * x_b - l_app
    ai_lo = base_lo + lo_i * d_app
    aj_lo = base_lo - hi_j * d_app
    if not (ai_lo > MARGIN * a_size and aj_lo > MARGIN * a_size):
        return fail
    ai_hi = base_hi + hi_i * d_app
    aj_hi = base_hi - lo_j * d_app
    # the opening speed: each particle's speed from its own energy (frac_j A_i on i)
    ws_lo = e * (math.sqrt(2.0 * frac_j * ai_lo / m_i) + math.sqrt(2.0 * frac_i * aj_lo / m_j))
    ws_hi = e * (math.sqrt(2.0 * frac_j * ai_hi / m_i) + math.sqrt(2.0 * frac_i * aj_hi / m_j))
    h_lo = rupture_gap(theta, mu_per_gamma * ws_lo, vol3)
    h_hi = rupture_gap(theta, mu_per_gamma * ws_hi, vol3)
    if not h_lo > ha.d:
        return fail
    # ---- who stops first: the particle whose force along its motion is the smaller
    # (-fn_i on particle i, fn_j on particle j, in the separation), over the whole interval
    if -lo_i <= lo_j:
        x, fx_lo, fx_hi, fy_lo, m_y, share_x = 1, -hi_i, -lo_i, lo_j, m_j, frac_j
    elif hi_j <= -hi_i:
        x, fx_lo, fx_hi, fy_lo, m_y, share_x = 2, lo_j, hi_j, -hi_i, m_i, frac_i
    else:
        return fail
    p_lo, p_hi = m_r * ws_lo, m_r * ws_hi
    top = Gap(h_hi, *gap_parts(h_hi, a2))
    low = Gap(h_lo, *gap_parts(h_lo, a2))
    first = p_lo - c * abs(ln_f_change(ha, top))  # p - c Delta at its least
    if not first > MARGIN * p_lo:
        return fail
    # ---- D_lo: below every stop (G_x > 0 there at the least p and f_x)
    at_lo = low
    g, size = _stop_sign(low, p_lo, fx_lo, k)
    if not g > MARGIN * size:
        z = _first_stop(p_lo, fx_lo, low, k)
        at_lo = ha
        for back in (1e-6, 1e-3):
            d = ha.d + (z - ha.d) * (1.0 - back)
            at = Gap(d, *gap_parts(d, a2))
            g, size = _stop_sign(at, p_lo, fx_lo, k)
            if g > MARGIN * size:
                at_lo = at
                break
    # ---- D_hi: above every stop (G_x <= 0 there at the largest p and f_x), else h_hi
    at_hi = top
    g, size = _stop_sign(low, p_hi, fx_hi, k)
    if g < -MARGIN * size:
        z = _first_stop(p_hi, fx_hi, low, k)
        d = min(ha.d + (z - ha.d) * (1.0 + 1e-6), h_lo)
        at = Gap(d, *gap_parts(d, a2))
        g, size = _stop_sign(at, p_hi, fx_hi, k)
        if g < -MARGIN * size:
            at_hi = at
    d_lo, d_hi = at_lo.d, at_hi.d
    # (p - c Delta_1) + c Delta_2, at its least: Delta_1 up to D_hi, Delta_2 from D_hi to h
    second = p_lo - c * abs(ln_f_change(ha, at_hi))
    if d_hi < h_lo:
        second += c * abs(ln_f_change(at_hi, low))
    second = max(first, second)
    cap_top = kcap * g_change(ha, top, a2)
    cap = 2.0 * m_y * (cap_top - share_x * kcap * g_change(ha, at_lo, a2))
    # the partner's path length weighted as the kernel does: (h - Ha) - s_x (d - Ha)
    q_lo = max((h_lo - ha.d) - share_x * (d_hi - ha.d), (1.0 - share_x) * (h_lo - ha.d))
    q_hi = (h_hi - ha.d) - share_x * (d_lo - ha.d)
    work = 2.0 * m_y * (fy_lo * q_lo if fy_lo >= 0.0 else fy_lo * q_hi)
    r_lo = first * second - cap + work
    r_size = p_hi * p_hi + 2.0 * m_y * (abs(cap_top) + abs(fy_lo) * (h_hi - ha.d))
    # ---- G_y(h): the partner reaches the rupture on the ordinary path (not both stop)
    y_work = fy_lo * (h_lo - ha.d) if fy_lo >= 0.0 else fy_lo * (h_hi - ha.d)
    y_lo = first * first - 2.0 * m_r * (cap_top - y_work)
    y_size = p_hi * p_hi + 2.0 * m_r * (abs(cap_top) + abs(fy_lo) * (h_hi - ha.d))
    return r_lo, r_size, y_lo, y_size, x


@njit(cache=CACHE)
def _survives(k, w_a, w_b, forces, m_i, m_j):
    """True where :func:`survivor_floors` proves a rebound at every relative speed of
    ``[w_a, w_b]`` (``forces``: ``(lo_i, hi_i, lo_j, hi_j)``): both floors clear
    :data:`MARGIN` of their size, and the partner's energy left, at least
    ``R^2 / (8 m_y size)``, clears :data:`LEAST` of the impact's."""
    r_lo, r_size, y_lo, y_size, x = survivor_floors(k, w_a, w_b, forces, m_i, m_j)
    if not (r_lo > MARGIN * r_size and y_lo > MARGIN * y_size):
        return False
    m_y = m_j if x == 1 else m_i
    return r_lo * (r_lo / (8.0 * m_y * r_size)) > LEAST * (0.5 * k.m_r * w_b * w_b)


@njit(cache=CACHE)
def _paper_setup(kind, raw, vals, body, particle_slip):
    """``(ok, constants, slip, forces)`` of one collision for :func:`survivor_over` and
    :func:`extended_down`: ``ok`` false outside mode "paper" (the survivor's path is
    its own) or where :func:`proof_constants` proves nothing; ``forces`` the constant
    ``(fn_i, fn_i, fn_j, fn_j)`` where the drag does not depend on the speed."""
    ok, k, _, _, slip, _ = _setup(kind, raw, vals, body, particle_slip)
    fn_i, fn_j = vals[7], vals[8]
    return ok and kind == PAPER, k, slip, (fn_i, fn_i, fn_j, fn_j)


@njit(cache=CACHE)
def survivor_floors_over(kind, raw, vals, body, particle_slip, u_a, u_b):
    """:func:`survivor_floors` of mode "paper" (``kind`` :data:`PAPER`; NaN floors for any
    other) over the head-on speeds ``u_a <= u <= u_b`` [m/s]; arguments as
    :func:`proven_from`'s."""
    ok, k, slip, forces = _paper_setup(kind, raw, vals, body, particle_slip)
    if not ok:
        return math.nan, math.nan, math.nan, math.nan, 0
    if slip:
        forces = body_force_range(raw, u_a, u_b)
    wpu = vals[10]
    return survivor_floors(k, u_a * wpu, u_b * wpu, forces, vals[0], vals[1])


@njit(cache=CACHE)
def survivor_over(kind, raw, vals, body, particle_slip, u_a, u_b):
    """True where mode "paper" (``kind`` :data:`PAPER`; any other kind: False) provably
    rebounds at every head-on speed ``u_a <= u <= u_b`` [m/s] by the survivor's bound
    (:func:`survivor_floors`), whichever particle stops first; arguments as
    :func:`proven_from`'s."""
    ok, k, slip, forces = _paper_setup(kind, raw, vals, body, particle_slip)
    if not ok:
        return False
    if slip:
        forces = body_force_range(raw, u_a, u_b)
    wpu = vals[10]
    return _survives(k, u_a * wpu, u_b * wpu, forces, vals[0], vals[1])


@njit(cache=CACHE)
def extended_down(kind, raw, vals, body, particle_slip, floor, lo, need):
    """The lowest head-on speed ``W`` [m/s], ``floor <= W <= lo``, down to which mode
    "paper" is proven to rebound, given that it rebounds from ``lo`` up: intervals below
    ``lo`` proven one after another by the survivor's bound (:func:`survivor_floors`),
    until one reaches ``need`` or below (at most :data:`CHECKS`; steps of
    :data:`STEP`, geometric in the distance from ``floor``). ``lo`` where nothing more is
    proven, or for any kind but :data:`PAPER`; other arguments as :func:`proven_from`'s."""
    ok, k, slip, forces = _paper_setup(kind, raw, vals, body, particle_slip)
    if not (ok and floor > 0.0 and lo > floor and need < lo):
        return lo
    wpu = vals[10]
    m_i, m_j = vals[0], vals[1]
    step = STEP
    for _ in range(CHECKS):
        below = max(floor + (lo - floor) / (1.0 + step), floor)
        if slip:
            forces = body_force_range(raw, below, lo)
        if _survives(k, below * wpu, lo * wpu, forces, m_i, m_j):
            lo = below
            if lo <= need or lo == floor:
                break
            step = min(2.0 * step, 4.0 * STEP)
        else:
            step *= 0.25
            if step < STEP_LEAST:
                break
    return lo
