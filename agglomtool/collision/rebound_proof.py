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
from .physics import reduced_mass
from .records import Gap, Pair

__all__ = ["MARGIN", "LEAST", "NUDGE", "ROUNDS", "ProofConstants", "proof_constants",
           "energy_floors", "rebounds_between", "lowest_provable", "floors_over",
           "rebounds_over", "proven_from", "PAPER", "RELATIVE"]

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
