"""The integrated truth under the paper's force laws (mode "ode"; docs/model.md).

The relative equation of motion of the pair along the collision axis, integrated numerically
in the gap, with the same force laws as the paper (Shabanian et al. 2024, Heliyon
10:e29397, doi:10.1016/j.heliyon.2024.e29397):

- capillary force ``kcap X_v(D)``, ``kcap = 2 pi gamma r cos(theta)`` (Eq. 25), attractive;
- viscous force ``c X_v(D)^2 v / D``, ``c = (3/2) pi mu_l r^2`` (Eq. 26), against the
  relative speed ``v``;
- ``X_v(D) = a^2 / (s (s + D))``, ``s = sqrt(D^2 + a^2)``, ``a^2 = H0^2 - Ha^2``: the
  bridge-volume correction (Eqs. 28-30), written without cancellation;
- the body forces held at their impact values and acting on the relative motion through
  ``F_b = m_r (fn_i / m_i - fn_j / m_j)`` (a plate is held: its term is 0), see
  :func:`agglomtool.collision.relative.relative_body_force`;
- instantaneous solid contact at ``D = Ha`` with restitution ``e``;
- rupture at ``h_rupt`` of Eq. 94 with ``Ca = mu_l v / gamma`` from the opening speed at
  contact (as the analytic models do), or, with ``rupture="self-consistent"``, at the first
  gap where ``D >= h_rupt(Ca(v(D)))`` with the current opening speed ``v(D)``.

The pair sticks when its relative kinetic energy reaches zero inside the bridge.
``e_w = v(h_rupt) / w``.

Numerics
--------
The independent variable is ``y = ln D`` and the state the relative kinetic energy over its
initial value, ``k = K / K0``, ``K0 = m_r w^2 / 2``. Then

``dk/dy = -D (kcap X_v + F_b) / K0 + sigma (2 c / (m_r w)) X_v^2 sqrt(k)``

with ``sigma = +1`` on the approach (integrated from ``ln H0`` down to ``ln Ha``) and
``sigma = -1`` on the separation (``ln Ha`` up to ``ln h_rupt``). The ``1/D`` of the
lubrication force is gone (``d ln f / dD = X_v^2 / D``). The equation is stiff only where
the local Stokes number ``m_r v / (c X_v^2)`` is small, i.e. when a slow pair creeps towards
contact at the speed where capillary pull and viscous drag balance; there the integration
stops early with a rigorous bound (see :func:`_cannot_rebound`), so an explicit embedded
Runge-Kutta pair (Dormand-Prince 5(4), FSAL, with step control on ``|k5 - k4| <=
atol + rtol |k|``) is enough. It is compiled with Numba and run over collisions with
``prange``. Convergence and the agreement with scipy's implicit Radau at ``rtol = 1e-12``
are checked in ``tests/test_tiers_models.py``.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from . import _codes as codes
from . import stages
from .bridge import (
    _LN4,
    bridge_volume,
    g_diff,
    g_diff_s,
    ln_f,
    ln_f_parts_s,
    rupture_distance,
    rupture_gap,
)
from .physics import reduced_mass, relative_body_force
from .records import (
    OdeForces,
    OdeOptions,
    OdeStops,
    RuptureEnd,
    RuptureLaw,
    TierInputs,
    WorkScale,
    pair_at,
    tier_inputs,
)

__all__ = [
    "run_ode",
    "ode_batch",
    "ode_kernel",
    "volume_correction",
    "DEFAULT_RTOL",
    "DEFAULT_ATOL",
    "RUPTURE_MODES",
]

#: Default relative and absolute tolerances of the step control (``k`` is dimensionless).
DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12
#: Accepted steps per stage before the integration gives up (an error is raised).
MAX_STEPS = 200_000
#: How the rupture gap is taken: Ca from the opening speed at contact, or self-consistent.
RUPTURE_MODES = ("contact", "self-consistent")
#: First trial step of the step control in ``ln D`` (each stage).
DEFAULT_FIRST_STEP = 1e-2



# Status codes of one integrated stage.
_REACHED, _STOPPED, _CANNOT, _EVENT, _TOO_MANY = 0, 1, 2, 3, 4


@njit(cache=CACHE)
def volume_correction(D, a2):
    """Bridge-volume correction ``X_v(D) = 1 - D / sqrt(D^2 + a^2)`` [-] (Eqs. 25-26, 28),
    evaluated as ``a^2 / (s (s + D))`` without cancellation; ``a2`` = ``a^2`` [m2]."""
    s = math.sqrt(D * D + a2)
    return a2 / (s * (s + D))


@njit(cache=CACHE, error_model="numpy")
def _rhs_at(D, x, k, sigma, kc, fb, vis):
    """``dk/dy`` (module docstring) at the gap ``D = exp(y)`` with its volume correction
    ``x``; ``kc = kcap/K0``, ``fb = F_b/K0`` [1/m], ``vis = 2 c / (m_r w)`` [-]."""
    return -D * (kc * x + fb) + sigma * vis * x * x * math.sqrt(max(k, 0.0))


@njit(cache=CACHE, error_model="numpy")
def _x_v_s(D, s, a2):
    """:func:`volume_correction` from ``s = sqrt(D^2 + a^2)`` already taken (the same
    operations, so the same number)."""
    return a2 / (s * (s + D))


@njit(cache=CACHE, error_model="numpy")
def _vc(D, a2, volcorr):
    """``X_v(D)`` (:func:`volume_correction`) with ``volcorr``, else 1."""
    if volcorr:
        return _x_v_s(D, math.sqrt(D * D + a2), a2)
    return 1.0


@njit(cache=CACHE, error_model="numpy")
def _dp_step(y, d, k, h, f1, sigma, forces):
    """One Dormand-Prince 5(4) step from ``(y, k)`` (gap ``d = exp(y)``) of size ``h``
    with ``f1 = dk/dy`` there, under the force law ``forces`` (:class:`~.records.OdeForces`).

    Returns ``(k5, k5 - k4, dk/dy at the new point, the gap there, sqrt(D^2 + a^2) there
    (0 without the volume correction), X_v there, sqrt(max(k5, 0)))``: the third is the
    next step's ``f1``; the last two stages share the new point's gap, and the early stops
    of :func:`_integrate` reuse its square roots and ``X_v``. The stage gaps
    ``exp(y + c h)`` are ``d`` times powers of ``exp(h / 10)`` (``c`` = 1/5, 3/10, 4/5)
    and the new point's gap over ``exp(h / 9)`` (``c`` = 8/9): three exponentials a step.
    """
    a2, kc, fb, vis, volcorr = forces
    e1 = math.exp(0.1 * h)
    e2 = e1 * e1
    e4 = e2 * e2
    d2 = d * e2
    d3 = d * (e2 * e1)
    d4 = d * (e4 * e4)
    d_new = math.exp(y + h)
    d5 = d_new * math.exp(h * (-1.0 / 9.0))
    x2 = _vc(d2, a2, volcorr)
    x3 = _vc(d3, a2, volcorr)
    x4 = _vc(d4, a2, volcorr)
    x5 = _vc(d5, a2, volcorr)
    s_new = 0.0
    x_new = 1.0
    if volcorr:
        s_new = math.sqrt(d_new * d_new + a2)
        x_new = _x_v_s(d_new, s_new, a2)
    # Each stage's dk/dy is p + q sqrt(k_stage) (_rhs_at): p of the bridge and body forces
    # and q of viscosity do not depend on k. The next stage's k adds the last stage's term
    # last, as h a p + (h a q) sqrt(k_stage), so that only a product and a sum separate one
    # stage's square root from the next.
    vs = sigma * vis
    p2 = -d2 * (kc * x2 + fb)
    q2 = vs * x2 * x2
    p3 = -d3 * (kc * x3 + fb)
    q3 = vs * x3 * x3
    p4 = -d4 * (kc * x4 + fb)
    q4 = vs * x4 * x4
    p5 = -d5 * (kc * x5 + fb)
    q5 = vs * x5 * x5
    p6 = -d_new * (kc * x_new + fb)
    q6 = vs * x_new * x_new
    c2 = h * (1.0 / 5.0)
    r2 = math.sqrt(max(k + c2 * f1, 0.0))
    f2 = p2 + q2 * r2
    c3 = h * (9.0 / 40.0)
    r3 = math.sqrt(max((k + h * (3.0 / 40.0 * f1) + c3 * p2) + (c3 * q2) * r2, 0.0))
    f3 = p3 + q3 * r3
    c4 = h * (32.0 / 9.0)
    r4 = math.sqrt(max((k + h * (44.0 / 45.0 * f1 - 56.0 / 15.0 * f2) + c4 * p3)
                       + (c4 * q3) * r3, 0.0))
    f4 = p4 + q4 * r4
    c5 = h * (-212.0 / 729.0)
    r5 = math.sqrt(max((k + h * (19372.0 / 6561.0 * f1 - 25360.0 / 2187.0 * f2
                                 + 64448.0 / 6561.0 * f3) + c5 * p4) + (c5 * q4) * r4, 0.0))
    f5 = p5 + q5 * r5
    c6 = h * (-5103.0 / 18656.0)
    r6 = math.sqrt(max((k + h * (9017.0 / 3168.0 * f1 - 355.0 / 33.0 * f2
                                 + 46732.0 / 5247.0 * f3 + 49.0 / 176.0 * f4) + c6 * p5)
                       + (c6 * q5) * r5, 0.0))
    f6 = p6 + q6 * r6
    c7 = h * (11.0 / 84.0)
    k5 = (k + h * (35.0 / 384.0 * f1 + 500.0 / 1113.0 * f3 + 125.0 / 192.0 * f4
                   - 2187.0 / 6784.0 * f5) + c7 * p6) + (c7 * q6) * r6
    sk5 = math.sqrt(max(k5, 0.0))
    # the new point's dk/dy (the next step's f1): the last two stages share its gap
    f7 = p6 + q6 * sk5
    # b5 - b4 of the embedded pair
    c8 = h * (-1.0 / 40.0)
    err = (h * (71.0 / 57600.0 * f1 - 71.0 / 16695.0 * f3 + 71.0 / 1920.0 * f4
                - 17253.0 / 339200.0 * f5 + 22.0 / 525.0 * f6) + c8 * p6) + (c8 * q6) * sk5
    return k5, err, f7, d_new, s_new, x_new, sk5


@njit(cache=CACHE, error_model="numpy")
def _cannot_rebound(D, x, sk, kc, fb, vis, e2, need):
    """True when the approach, now at gap ``D`` with ``k``, cannot end in a rebound; ``x``
    is ``X_v(D)`` and ``sk = sqrt(max(k, 0))``.

    On the approach the closing speed cannot rise above ``M = max(v, sup v_term)``, where
    ``v_term(D') = D' (kcap X_v + F_b) / (c X_v^2)`` is the speed at which the bridge forces
    balance (below it the speed grows, above it falls); ``sup`` over ``[Ha, D]`` is bounded by
    the value at ``D`` with ``max(F_b, 0)``, as ``D / X_v`` and ``D / X_v^2`` increase with
    ``D``. So ``k_s <= e^2 M^2`` (in units of the initial energy). ``need`` is a lower bound
    of the ``k_s`` any rebound requires (see :func:`ode_kernel`).
    """
    m_term = D * (kc * x + max(fb, 0.0)) / (vis * x * x)
    m = max(sk, m_term)
    return e2 * m * m <= need


@njit(cache=CACHE, error_model="numpy")
def _ln_f_s(D, s, a2):
    """:func:`~.bridge.ln_f` at ``D`` from ``s = sqrt(D^2 + a^2)`` already taken
    (:func:`~.bridge.ln_f_parts_s`, so the same number)."""
    kind, value = ln_f_parts_s(D, s, a2)
    return value - _LN4 if kind else value


@njit(cache=CACHE, error_model="numpy")
def _must_stick(D, s, k, forces, end):
    """True when the separation, now at gap ``D`` (``s = sqrt(D^2 + a^2)``) with ``k``,
    cannot reach the rupture gap ``end.h_end`` (a :class:`~.records.RuptureEnd`) with
    energy left (normalised as in :func:`_rhs_at`; ``forces`` an
    :class:`~.records.OdeForces`).

    Two bounds, each exact for the equation of motion: (1) the energy at ``h_end`` is ``k``
    less the work ``W`` of the capillary and body forces from ``D`` to ``h_end`` less the
    viscous loss (never negative), so ``k <= W`` sticks; (2) where the capillary and body
    forces together pull the pair back all the way to ``h_end`` (``pulls``), the speed
    ``v = sqrt(k)`` falls monotonically and, with ``dv/dy = -D (kc X_v + fb) / (2 v) -
    vis X_v^2 / 2``, ``v(h_end) <= v - W / (2 v) - (vis / 2) (ln f(h_end) - ln f(D))``;
    that at most 0 sticks too.
    """
    a2, kc, fb, vis, _ = forces
    h_end, s_end, lnf_end, pulls = end
    w_rest = kc * g_diff_s(D, s, h_end, s_end, a2) + fb * (h_end - D)
    if k <= w_rest:
        return True
    if pulls:
        v = math.sqrt(k)
        return v - 0.5 * w_rest / v - 0.5 * vis * (lnf_end - _ln_f_s(D, s, a2)) <= 0.0
    return False


@njit(cache=CACHE, error_model="numpy")
def _rupture_gap_log(theta, ca_per_sqrtk, vol, k):
    """``ln h_rupt`` (Eq. 94) at the opening speed ``w sqrt(k)``."""
    return math.log(rupture_distance(theta, ca_per_sqrtk * math.sqrt(max(k, 0.0)), vol))


@njit(cache=CACHE, error_model="numpy")
def _integrate(y0, y1, k0, sigma, forces, opts, stops, rupture):
    """Integrate ``dk/dy`` from ``y0`` towards ``y1``, starting with ``k0``, ``sigma`` +1 on
    the approach and -1 on the separation, under the force law ``forces``
    (:class:`~.records.OdeForces`).

    ``opts`` (:class:`~.records.OdeOptions`) gives the tolerances and the step settings:
    ``h_first`` is the first trial step and ``h_max`` the largest step, both in ``ln D``;
    the first trial step is also at most the one over which ``k`` changes by
    ``first_change`` times ``max(k, 1e-3)`` at its initial rate. ``stops``
    (:class:`~.records.OdeStops`): ``need >= 0`` enables the early stop of
    :func:`_cannot_rebound` (approach only; -1 disables it); ``event`` stops at the first
    ``y >= ln h_rupt(k)`` (self-consistent rupture, of the law ``rupture``, a
    :class:`~.records.RuptureLaw`); ``stick_margin >= 0`` (separation to the fixed gap
    ``exp(y1)`` only; -1 disables it) stops the stage as a stick once :func:`_must_stick`
    holds for ``k + stick_margin``: with ``stick_margin`` a bound of the integration error
    in ``k``, the pair it integrates sticks then too. Returns ``(k, y, status, steps)``.
    """
    a2, kc, fb, vis, volcorr = forces
    rtol, atol = opts.rtol, opts.atol
    h_first, h_max, first_change = opts.h_first, opts.h_max, opts.first_change
    e2, need, event, stick_margin = stops
    theta, ca_per_sqrtk, vol = rupture
    direction = 1.0 if y1 > y0 else -1.0
    y, k = y0, k0
    end = RuptureEnd(0.0, 0.0, 0.0, False)
    if stick_margin >= 0.0:
        h_end = math.exp(y1)
        s_end = math.sqrt(h_end * h_end + a2)
        # kc X_v + fb keeps its sign between its values at the ends (X_v is monotonic).
        end = RuptureEnd(h_end, s_end, _ln_f_s(h_end, s_end, a2),
                         min(kc * volume_correction(math.exp(y0), a2),
                             kc * _x_v_s(h_end, s_end, a2)) + fb >= 0.0)
    d = math.exp(y)
    f1 = _rhs_at(d, _vc(d, a2, volcorr), k, sigma, kc, fb, vis)
    h = direction * min(abs(y1 - y0), h_first,
                        first_change * max(abs(k), 1e-3) / max(abs(f1), 1e-300))
    steps = 0
    while steps < MAX_STEPS:
        if direction * (y + h - y1) > 0.0:
            h = y1 - y
        k_new, err, f_new, d_new, s_new, x_new, sk_new = _dp_step(y, d, k, h, f1, sigma, forces)
        scale = atol + rtol * max(abs(k), abs(k_new))
        ratio = abs(err) / scale
        if ratio > 1.0:
            h *= max(0.2, 0.9 * ratio ** -0.2)
            continue
        steps += 1
        if event and y + h >= _rupture_gap_log(theta, ca_per_sqrtk, vol, k_new):
            # Locate the crossing by bisecting the step length (single steps from (y, k)).
            lo, hi = 0.0, 1.0
            k_hi = k_new
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                k_mid = _dp_step(y, d, k, mid * h, f1, sigma, forces)[0]
                if k_mid > 0.0 and y + mid * h >= _rupture_gap_log(
                    theta, ca_per_sqrtk, vol, k_mid
                ):
                    hi, k_hi = mid, k_mid
                else:
                    lo = mid
                if (hi - lo) * abs(h) < 1e-14:
                    break
            if not k_hi > 0.0:
                return 0.0, y + hi * h, _STOPPED, steps
            return k_hi, y + hi * h, _EVENT, steps
        y += h
        d = d_new
        k = k_new
        f1 = f_new
        if not k > 0.0:
            return 0.0, y, _STOPPED, steps
        if direction * (y - y1) >= 0.0:
            return k, y1, _REACHED, steps
        # d_new = exp(y) here (y advanced by h: the same sum as in the step)
        if not volcorr and (need >= 0.0 or stick_margin >= 0.0):
            s_new = math.sqrt(d_new * d_new + a2)
            x_new = _x_v_s(d_new, s_new, a2)
        if need >= 0.0 and _cannot_rebound(d_new, x_new, sk_new, kc, fb, vis, e2, need):
            return k, y, _CANNOT, steps
        if stick_margin >= 0.0 and _must_stick(d_new, s_new, k + stick_margin, forces, end):
            return 0.0, y, _STOPPED, steps
        # 0.9 ratio^-0.2 exceeds 5 below ratio = 1.8e-4 (5.05 there): no power needed.
        factor = 5.0 if ratio <= 1.8e-4 else min(5.0, max(0.2, 0.9 * ratio ** -0.2))
        h *= factor
        if abs(h) > h_max:
            h = direction * h_max
    return k, y, _TOO_MANY, steps


@njit(cache=CACHE)
def ode_kernel(pair, w, det, opts):
    """One collision (``pair`` a :class:`~.records.Pair`, relative normal impact speed
    ``w`` [m/s]) integrated. Returns ``(e_w, stage, path, steps, status)``.

    ``status`` is 4 when :data:`MAX_STEPS` was exceeded (the wrapper raises), else 0.
    ``det`` as in :func:`agglomtool.collision.paper.paper_kernel`; the per-particle columns
    hold the CM-frame split of the relative energies; the viscous losses are the energy
    balance of the integrated stage (``K_start - K_end - L_cap - L_bdw``). ``opts`` (an
    :class:`~.records.OdeOptions`): the tolerances, the rupture rule, the force law and
    the step settings of :func:`ode_batch`; its ``stick_margin`` (>= 0 enables it, contact
    rupture only): the separation stops as a stick where :func:`_must_stick` holds for
    ``k + stick_margin``.
    """
    m_i, m_j, r, H0, Ha, mu_l, gamma, _, theta, fn_i, fn_j, e = pair
    self_consistent = opts.self_consistent
    stick_margin = opts.stick_margin
    nan = math.nan
    want = stages.fresh_details(det)
    m_r, frac_i, frac_j = reduced_mass(m_i, m_j)
    if not H0 > Ha:
        e_w, stage, path = stages.dry_contact(det, m_r, e, w)
        return e_w, stage, path, 0, 0
    c, kcap, a2 = stages.bridge_constants(pair)
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    kc = kcap / k0
    fb = f_b / k0
    vis = 2.0 * c / (m_r * w)
    vol = bridge_volume(r, a2)
    # rupture_distance(theta, ca, vol) is (1 + theta/2) (1 + sqrt(ca)) vol^(1/3): the
    # cube root is taken once for both gaps below (the same operations, the same numbers)
    vol3 = vol ** (1.0 / 3.0)
    e2 = e * e
    if want:
        stages.split_details(det, codes.K_INI_I, codes.K_INI_J, frac_i, frac_j, k0)
        det[codes.ST_APP] = m_r * w / c
        # (the approach's body-force loss in the order of its own products, and its viscous
        # loss below, are ode's: the stage is integrated, not taken in closed form)
        det[codes.L_CAP_APP] = kcap * g_diff(H0, Ha, a2)
        det[codes.L_BDW_APP_I] = -frac_j * f_b * (H0 - Ha)
        det[codes.L_BDW_APP_J] = -frac_i * f_b * (H0 - Ha)
    if not Ha > 0.0:  # an infinite lubrication loss before contact
        return 0.0, codes.APP_VIS, 0, 0, 0

    # A lower bound of the opening energy any rebound needs: the bridge must at least be
    # stretched to h_min = h_rupt(Ca = 0). Capillary and (if F_b >= 0) body forces and
    # viscosity all slow the opening; with F_b >= 0 the viscous-only speed loss alone is a
    # bound, and in any case the potential barrier at h_min.
    h_min = rupture_gap(theta, 0.0, vol3)  # Ca = 0
    need = -1.0
    if h_min > Ha:
        barrier = kc * g_diff(Ha, h_min, a2) + fb * (h_min - Ha)
        need = max(barrier, 0.0)
        if fb >= 0.0:
            v_min = 0.5 * vis * (ln_f(h_min, a2) - ln_f(Ha, a2))
            need = max(need, v_min * v_min)

    # ---- approach
    forces = OdeForces(a2, kc, fb, vis, opts.volcorr)
    k_c, _, status, steps = _integrate(
        math.log(H0), math.log(Ha), 1.0, 1.0, forces, opts, OdeStops(e2, need, False, -1.0),
        RuptureLaw(theta, 0.0, vol),
    )
    if status == _TOO_MANY:
        return nan, codes.APP_EN, 0, steps, _TOO_MANY
    if status == _STOPPED:
        return 0.0, codes.APP_EN, 0, steps, 0
    if status == _CANNOT:
        return 0.0, codes.APP_VIS, 0, steps, 0
    w_c = w * math.sqrt(k_c)
    if want:
        det[codes.K_APP_I] = frac_j * k_c * k0
        det[codes.K_APP_J] = frac_i * k_c * k0
        det[codes.L_VIS_APP] = k0 * (1.0 - k_c) - det[codes.L_CAP_APP] + f_b * (H0 - Ha)
        stages.contact_details(det, m_r, e, w_c)
    if not e > 0.0:
        return 0.0, codes.CONTACT, 0, steps, 0

    # ---- separation
    k_s = e2 * k_c
    w_s = e * w_c
    ca, h_rupt = stages.rupture_at(w_s, mu_l, gamma, theta, vol3)
    path = 0
    if not h_rupt > Ha:
        path |= codes.P_BROKEN
        k_end = k_s
        status = _REACHED
    else:
        y_end = math.log(h_rupt)
        if self_consistent:
            # The rupture gap follows the speed; a far bound, the event ends the stage.
            y_end = math.log(Ha) + 60.0
        k_end, y_stop, status, steps_sep = _integrate(
            math.log(Ha), y_end, k_s, -1.0, forces, opts,
            OdeStops(e2, -1.0, self_consistent, -1.0 if self_consistent else stick_margin),
            RuptureLaw(theta, mu_l * w / gamma, vol),
        )
        steps += steps_sep
        if status == _TOO_MANY:
            return nan, codes.SEP_EN, path, steps, _TOO_MANY
        if self_consistent and status == _EVENT:
            h_rupt = math.exp(y_stop)
            ca = mu_l * w * math.sqrt(k_end) / gamma
    if want:
        stages.rupture_details(det, frac_j * k_s * k0, frac_i * k_s * k0, ca, h_rupt)
        stages.work_details(det, WorkScale(k0, w, c, kcap, f_b, H0, Ha, a2), h_rupt)
        if h_rupt > Ha and status != _STOPPED:
            l_cap = kcap * g_diff(Ha, h_rupt, a2)
            l_bdw = f_b * (h_rupt - Ha)
            stages.stage_details(det, True, l_cap, k0 * (k_s - k_end) - l_cap - l_bdw, l_bdw,
                                 frac_i, frac_j)
    if status == _STOPPED:
        return 0.0, codes.SEP_EN, path, steps, 0
    if want:
        det[codes.K_FIN_I] = frac_j * k_end * k0
        det[codes.K_FIN_J] = frac_i * k_end * k0
    return math.sqrt(k_end), codes.REBOUND, path, steps, 0


@njit(parallel=True, cache=CACHE)
def _run_ode_batch(ins, opts, e_w, stage, path, steps, status, det):
    for q in prange(e_w.shape[0]):
        ew, st, pa, ns, stat = ode_kernel(pair_at(ins, q), ins.w[q], det[q], opts)
        e_w[q] = ew
        stage[q] = st
        path[q] = pa
        steps[q] = ns
        status[q] = stat


def ode_batch(ins: TierInputs, *, details=False, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL,
              rupture="contact", volume_corrected=True, first_step=DEFAULT_FIRST_STEP,
              max_step=math.inf, first_change=math.inf, stick_margin=None):
    """:func:`run_ode` that also returns the accepted steps per collision (fifth array).

    Parameters
    ----------
    ins : TierInputs
        The input arrays (:class:`~.records.TierInputs`, or the same arrays in its order).
    rtol, atol : float
        Step-control tolerances on ``k = K / K0`` [-].
    rupture : {"contact", "self-consistent"}
        Capillary number of Eq. 94 from the opening speed at contact (the analytic models'
        rule), or from the speed at the rupture gap itself.
    volume_corrected : bool
        False sets ``X_v = 1`` in both bridge forces (the uncorrected force laws).
    first_step, max_step, first_change : float
        First trial step and largest step of the step control, in ``ln D`` [-]; the first
        trial step of each stage is also at most the one over which ``k`` would change by
        ``first_change`` times ``max(k, 1e-3)`` at its initial rate. The error
        estimate of an embedded pair is only asymptotic: at loose tolerances the step
        control alone lets steps grow to several units of ``ln D``, where the estimate can
        be two orders of magnitude below the true error (measured near the critical speed,
        where ``k`` ends close to 0); mode "auto" caps the step (:mod:`.auto`). The
        defaults (0.01, no cap, no limit) are those of mode "ode".
    stick_margin : float or None
        A bound of the integration error in ``k`` [-] (>= 0), or None (mode "ode"): with
        it the separation (contact rupture) stops as a stick as soon as the pair would
        stick even with that much more energy (:func:`_must_stick`), instead of
        integrating on until its energy is spent.
    """
    if rupture not in RUPTURE_MODES:
        raise ValueError(f"rupture = {rupture!r} is not one of {RUPTURE_MODES}")
    if not (0.0 < rtol < 1e-2 and 0.0 < atol < 1e-2):
        raise ValueError(f"rtol = {rtol!r}, atol = {atol!r}: both must be in (0, 0.01)")
    if not (0.0 < first_step <= max_step and first_change > 0.0):
        raise ValueError(f"first_step = {first_step!r}, max_step = {max_step!r}, "
                         f"first_change = {first_change!r}: need 0 < first_step <= max_step "
                         "and first_change > 0")
    if stick_margin is None:
        margin = -1.0
    else:
        margin = float(stick_margin)
        if not margin >= 0.0:
            raise ValueError(f"stick_margin = {stick_margin!r} must be >= 0 (or None)")
    ins = tier_inputs(ins)
    n = ins.w.shape[0]
    e_w, stage, path, det = stages.tier_outputs(n, details)
    steps = np.empty(n, dtype=np.int64)
    status = np.empty(n, dtype=np.int8)
    opts = OdeOptions(float(rtol), float(atol), rupture == "self-consistent",
                      bool(volume_corrected), float(first_step), float(max_step),
                      float(first_change), margin)
    parallel_launch(_run_ode_batch, ins, opts, e_w, stage, path, steps, status, det)
    if np.any(status == _TOO_MANY):
        bad = int(np.flatnonzero(status == _TOO_MANY)[0])
        raise RuntimeError(
            f"ode: collision {bad} needed more than {MAX_STEPS} steps in one stage "
            f"(w = {ins.w[bad]!r} m/s); loosen rtol = {rtol!r}"
        )
    return e_w, stage, path, det, steps


def run_ode(ins: TierInputs, *, details=False, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL,
            rupture="contact", volume_corrected=True):
    """Integrate the relative equation of motion of each collision (``ins``: the flat
    float64 arrays, a :class:`~.records.TierInputs`).

    Returns ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
    Options as in :func:`ode_batch`.
    """
    e_w, stage, path, det, _ = ode_batch(
        ins, details=details, rtol=rtol, atol=atol, rupture=rupture,
        volume_corrected=volume_corrected,
    )
    return e_w, stage, path, det


#: The self-consistent-rupture variant as a tier function.
run_ode_self_consistent = partial(run_ode, rupture="self-consistent")
