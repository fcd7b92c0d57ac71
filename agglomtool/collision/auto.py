"""Mode "auto": per collision, the cheapest tier whose error bound is within a tolerance.

Contract
--------
:func:`run_auto` takes the kernel inputs of :func:`~.paper.run_paper` and a tolerance
``tol`` in ``e_w`` (default :data:`DEFAULT_TOL`, allowed 1e-6 to 0.5) and returns
``(e_w, stage, path, det)`` like the other tiers (:func:`auto_batch` also returns the form
used per collision; :func:`auto_fused` runs the same choice from the fused kernels' raw
inputs, bitwise the same). For each collision the answer is that of the first candidate, in
order of cost, whose error bound is within ``tol``:

1. the closed forms on the relative motion (:mod:`.relative`, ~0.1 us per collision): a
   rebound is taken when ``CLOSED_FORM_BOUND * g <= tol`` and ``g <= G_MAX``, where ``g``
   is the first-order error indicator of the closed forms (the viscous number of each
   liquid stage at its lowest viscous-only speed times the work of the capillary and body
   forces over it, summed and normalised by the initial relative kinetic energy ``eta``,
   ``g = eta / max(e_w, sqrt(eta))``); a stick is taken when the closed forms still stick
   at :data:`STICK_MARGIN` times the speed;
2. the same closed forms on each liquid stage cut into ``n`` pieces of equal ``ln f``
   (:data:`PIECES` in turn; 0.25-0.5 us), each piece re-anchored at the speed the previous
   one left; taken when ``PIECEWISE_BOUND * g_n <= tol`` (``g_n <= G_MAX``) and every piece
   is clear (its energy cannot come near 0 inside it), a stick when it holds at
   :data:`PIECE_STICK_MARGIN` times the speed (not where viscosity alone stops the
   separation against a body force pulling the pair apart: those go to "ode");
3. otherwise the integrated truth (:mod:`.ode`, ~2-3 us) with :data:`ODE_STEPS`, at an
   ``rtol`` chosen so that its error bound in ``k = e_w^2``, :data:`ODE_K_ERROR_PER_RTOL`
   ``rtol``, is within ``tol^2`` (:func:`ode_rtol`; at most :data:`ODE_RTOL_MAX`),
   stopping a separation as a stick as soon as the pair would stick even with that much
   more energy (:func:`~.ode._must_stick`).

The Ennis criterion (:mod:`.stokes`) and mode "paper" are never candidates (their errors
against "ode" are reported by ``benchmarks/fidelity.py``).

The bounds are empirical: each constant below states the measured quantity it bounds and
its safety factor. How they were measured (scenes, seeds, the figures, the cases where
the estimates fail) is written up in ``benchmarks/results/auto_calibration.md``, also
shown on the documentation's speed-against-error page (``docs/speed_vs_error.md``, "How
mode auto's constants were measured"); ``benchmarks/calibrate_auto.py`` reproduces it.

In the fused loop only the whole-stage forms are written into the loop body; the rest of
the choice is a function call (:func:`_decide_beyond`), which keeps the common case fast.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from . import _codes as codes
from . import stages
from .bridge import bridge_volume, g_diff, gap_parts, ln_f_change, ln_f_diff
from .fused import (
    BLOCK,
    NO_ANGLES,
    SERIAL_BELOW,
    _first_rule,
    _one,
    _rules_update,
    slip_flag,
)
from .ode import MAX_STEPS, ode_batch, ode_kernel
from .physics import reduced_mass, relative_body_force
from .records import Bridge, Gap, OdeOptions, Pair, TierInputs, WorkScale, pair_at, tier_inputs
from .relative import relative_kernel

__all__ = [
    "run_auto",
    "auto_batch",
    "CLOSED_FORM_BOUND",
    "G_MAX",
    "STICK_MARGIN",
    "DEFAULT_TOL",
    "TIER_RELATIVE",
    "TIER_ODE",
    "ode_options",
]

#: Measured 0.119 (``benchmarks/results/auto_calibration.md``), with a safety factor 1.7.
CLOSED_FORM_BOUND = 0.2
#: Largest ``g`` at which the closed-form bound is trusted (measured up to 0.1:
#: ``benchmarks/results/auto_calibration.md``).
G_MAX = 0.05
#: Measured largest ``u*(relative) / u*(ode)`` 1.036, with a safety factor ~2.6 on its log.
STICK_MARGIN = 1.10
#: Default tolerance in ``e_w`` [-].
DEFAULT_TOL = 0.01
#: Step settings of the "ode" tier inside "auto" (first trial step, largest step in ``ln D``
#: and the limit of the first step by the initial rate, see :func:`~.ode.ode_batch`): fewer
#: steps than mode "ode"'s start at 0.01 (about 15 against 18 per collision on the
#: benchmark batch at rtol 1e-5); without the cap the embedded error estimate lets
#: steps grow to several units of ``ln D`` and underestimates the error by up to two orders
#: of magnitude near the critical speed (measured: ``|k - k(ode)|`` up to 190 ``rtol``, an
#: error of 0.015 in ``e_w`` at ``rtol = 1e-5`` on the mixed benchmark batch).
ODE_STEPS = dict(first_step=0.2, max_step=1.0, first_change=0.03)
#: Bound of the error of "ode" (with :data:`ODE_STEPS`) in ``k = e_w^2`` per unit ``rtol``:
#: measured at most 2.9 for rtol 1e-7 to 1e-5 (``benchmarks/results/auto_calibration.md``),
#: with a safety factor 3.4.
ODE_K_ERROR_PER_RTOL = 10.0
#: Largest integration tolerance used (the bound above is relied on from 1e-5 down; 1e-4
#: was measured once, with the first step 0.1 and no rate limit, at 22 rtol).
ODE_RTOL_MAX = 1e-5
#: Codes of the tier used per collision.
TIER_RELATIVE, TIER_ODE = 1, 2
#: The numbers of pieces per liquid stage of the piecewise closed forms, tried in turn:
#: on the benchmark batch (tol 0.01) 4 pieces take 8 % of the collisions, 16 pieces 4.5 %
#: and leave 2.2 % to "ode" (14.7 % without the pieces); (8, 32) costs the same.
PIECES = (4, 16)
#: Measured at most 0.187 for 2 to 16 pieces (``benchmarks/results/auto_calibration.md``),
#: safety factor 1.6.
PIECEWISE_BOUND = 0.3
#: Stick margins of the piecewise closed forms, per entry of :data:`PIECES`: measured
#: ``u*(pieces) / u*(ode)`` at most 1.0165 (4) and 1.0063 (16) where the stick is trusted
#: (``benchmarks/results/auto_calibration.md``), with safety factors 3.0 and 3.2 on the log.
PIECE_STICK_MARGIN = (1.05, 1.02)

@njit(cache=CACHE)
def closed_form_indicator(pair, w, det):
    """The closed forms' ``e_w`` and their error indicator ``g`` (module docstring) for the
    collision ``pair`` (a :class:`~.records.Pair`) at the relative speed ``w`` [m/s].

    ``det`` (length 0 or ``len(DETAIL_NAMES)``) receives the closed forms' details: the
    indicator reads the stage quantities from it, so it must have full length here.
    Returns ``(e_w, stage, path, g)``; ``g = inf`` where a stage has no viscous-only end
    speed (the closed forms stick).
    """
    m_i, m_j, _, H0, Ha, _, _, _, _, fn_i, fn_j, e = pair
    ew, st, pa, _ = relative_kernel(pair, w, det)
    if not H0 > Ha:
        return ew, st, pa, 0.0
    if not ew > 0.0:
        return ew, st, pa, math.inf
    m_r, _, _ = reduced_mass(m_i, m_j)
    c, kcap, a2 = stages.bridge_constants(pair)
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    c_delta = c * -ln_f_diff(H0, Ha, a2)
    w_end = w - c_delta / m_r
    work = abs(kcap * g_diff(H0, Ha, a2))
    eta = c_delta / (m_r * w_end) * (work + abs(f_b) * (H0 - Ha))
    h_rupt = det[codes.H_RUPT]
    w_s = e * det[codes.W_CONTACT]
    if h_rupt > Ha:
        c_delta = c * ln_f_diff(Ha, h_rupt, a2)
        w_end = w_s - c_delta / m_r
        work = abs(kcap * g_diff(Ha, h_rupt, a2))
        eta += c_delta / (m_r * w_end) * (work + abs(f_b) * (h_rupt - Ha))
    eta /= k0
    return ew, st, pa, eta / max(ew, math.sqrt(eta))


@njit(cache=CACHE)
def closed_form_indicator_lean(pair, w):
    """:func:`closed_form_indicator` in one pass, without a details row: the closed forms of
    :func:`~.relative.relative_kernel` written out with the same arithmetic, each ``ln f``
    difference, capillary work and the rupture gap computed once for both the outcome and
    the indicator. Bitwise the same ``(e_w, stage, path, g)`` (tested)."""
    e = pair.e
    if not pair.H0 > pair.Ha:
        ew, st, pa = stages.no_bridge(e)
        return ew, st, pa, 0.0
    return _whole_at(w, e, pair.theta, pair.mu_l, pair.gamma, _whole_parts(pair))


@njit(cache=CACHE, inline="always")
def _whole_parts(pair):
    """What :func:`closed_form_indicator_lean` computes independently of the speed, for a
    collision with ``H0 > Ha``: the reduced mass, ``a^2``, the force constants, the square
    roots and ``ln f`` parts of ``H0`` and ``Ha`` (:func:`~.bridge.gap_parts`), the
    approach's ``c Delta``, capillary and body losses (:func:`_decide` evaluates the closed
    forms at two speeds, and the piecewise forms start from these, :func:`_pieces_parts`)."""
    m_i, m_j, r, H0, Ha, _, _, _, _, fn_i, fn_j, _ = pair
    m_r, _, _ = reduced_mass(m_i, m_j)
    bridge = stages.bridge_constants(pair)
    c, kcap, a2 = bridge
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    s_h0, k_h0, v_h0 = gap_parts(H0, a2)
    s_ha, k_ha, v_ha = gap_parts(Ha, a2)
    # the approach's losses, as relative_kernel takes them
    c_delta, l_cap, l_bdw = stages.stage_losses(
        Gap(H0, s_h0, k_h0, v_h0), Gap(Ha, s_ha, k_ha, v_ha), bridge, f_b)
    vol3 = bridge_volume(r, a2) ** (1.0 / 3.0)
    return (m_r, a2, c, kcap, f_b, H0, Ha, vol3, k_ha, v_ha, c_delta, l_cap, l_bdw, s_ha,
            k_h0, v_h0, s_h0)


@njit(cache=CACHE, inline="always")
def _whole_at(w, e, theta, mu_l, gamma, parts):
    """:func:`closed_form_indicator_lean` at the speed ``w`` from the collision's ``parts``
    (:func:`_whole_parts`): the stages of :func:`~.relative.relative_kernel`
    (:func:`~.stages.stage_losses`, :func:`~.stages.stage_energy`), the approach's losses
    taken from ``parts``."""
    m_r, a2, c, kcap, f_b, H0, Ha, vol3, k_ha, v_ha, c_delta, l_cap, l_bdw, s_ha = parts[:14]
    k0 = 0.5 * m_r * w * w
    code, k_app, _ = stages.stage_energy(k0, w, m_r, c_delta, l_cap, l_bdw)
    if code:
        return 0.0, (codes.APP_VIS if code == 1 else codes.APP_EN), 0, math.inf
    w_s = e * stages.contact_speed(k_app, m_r)
    if not w_s > 0.0:
        return 0.0, codes.CONTACT, 0, math.inf
    k_s = 0.5 * m_r * w_s * w_s
    _, h_rupt = stages.rupture_at(w_s, mu_l, gamma, theta, vol3)
    path = 0
    sep = h_rupt > Ha
    c_delta_s = 0.0
    l_cap_s = 0.0
    if not sep:
        path |= codes.P_BROKEN
        k_end = k_s
    else:
        c_delta_s, l_cap_s, l_bdw_s = stages.stage_losses(
            Gap(Ha, s_ha, k_ha, v_ha), Gap(h_rupt, *gap_parts(h_rupt, a2)), Bridge(c, kcap, a2),
            f_b)
        code, k_end, _ = stages.stage_energy(k_s, w_s, m_r, c_delta_s, l_cap_s, l_bdw_s)
        if code:
            return 0.0, (codes.SEP_VIS if code == 1 else codes.SEP_EN), path, math.inf
    ew = math.sqrt(k_end / k0)
    if not ew > 0.0:
        return 0.0, codes.SEP_EN, path, math.inf
    eta = c_delta / (m_r * (w - c_delta / m_r)) * (abs(l_cap) + abs(f_b) * (H0 - Ha))
    if sep:
        eta += c_delta_s / (m_r * (w_s - c_delta_s / m_r)) * (abs(l_cap_s)
                                                              + abs(f_b) * (h_rupt - Ha))
    eta /= k0
    return ew, codes.REBOUND, path, eta / max(ew, math.sqrt(eta))


_LN4 = math.log(4.0)


@njit(cache=CACHE, inline="always")
def _one_minus_4f(kind, value):
    """``1 - 4 f = -expm1(ln(4 f))`` of a gap from its :func:`~.bridge.ln_f_parts`
    (:func:`_stage_pieces`)."""
    return -math.expm1(value if kind == 1 else value + _LN4)


@njit(cache=CACHE, inline="always")
def _pieces_parts(m_i, m_j, whole):
    """The quantities of one collision the piecewise closed forms need at every speed and
    piece count, from its whole-stage parts (:func:`_whole_parts`), computed once
    (:func:`_decide` tries up to four of them): the masses, the force constants, ``a``, the
    parts of ``H0`` and ``Ha`` (``ln f`` parts, square root, ``1 - 4 f``) and the cube root of
    the bridge volume (the rupture gap of Eq. 94 is that times factors of ``theta`` and
    ``Ca``, as in :func:`~.bridge.rupture_distance`, bitwise). ``H0 > Ha``."""
    (m_r, a2, c, kcap, f_b, H0, Ha, vol3, k_ha, v_ha, _, _, _, s_ha, k_h0, v_h0,
     s_h0) = whole
    _, frac_i, frac_j = reduced_mass(m_i, m_j)
    return (m_r, frac_i, frac_j, a2, c, kcap, f_b, math.sqrt(a2), k_h0, v_h0, s_h0,
            _one_minus_4f(k_h0, v_h0), k_ha, v_ha, s_ha, _one_minus_4f(k_ha, v_ha), vol3)


@njit(cache=CACHE)
def _collision_parts(pair):
    """:func:`_pieces_parts` of one collision from its :class:`~.records.Pair`
    (``H0 > Ha``)."""
    return _pieces_parts(pair.m_i, pair.m_j, _whole_parts(pair))


@njit(cache=CACHE, error_model="numpy", inline="always")
def _stage_pieces(k, v, start, om_s, end, law, n, indicator=True):
    """One liquid stage from the gap ``start.d`` to ``end.d`` (:class:`~.records.Gap`
    records) in ``n`` pieces of equal ``ln f`` (module docstring), entering with kinetic
    energy ``k`` [J] at speed ``v`` [m/s]; ``law`` holds ``(a2, m_r, c, kcap, f_b, a)``
    (:func:`_piecewise`'s names).

    Returns ``(k_end, code, l_cap, l_vis, l_bdw, eta, clear)``: ``code`` 0 reached
    ``d_e``, 1 viscosity alone stopped the pair, 2 the energy ran out; the three losses [J]
    summed over the pieces run (with a viscous stop, the capillary and body losses of the
    piece where it happened too, as the whole-stage forms report them); ``eta`` the
    first-order error indicator [J] summed over them; ``clear`` False where the energy
    inside a piece may come near 0 (neither the energy at the start of a piece less its
    losses nor the energy at its end less its gains is above ``eta``). With ``n = 1``
    the arithmetic of :func:`~.relative.relative_kernel`'s stage, bitwise.

    The inner gaps invert ``ln f`` in closed form: with ``p = 4 f = exp(v4)`` and
    ``q = sqrt(1 - p)``, ``D + s = a / sqrt(q)``, ``D = a p / (2 (1 + q) sqrt(q))`` and
    the capillary potential ``g = -a sqrt(q)``; none of them cancels. ``p`` and
    ``1 - p`` go from piece to piece by the factor ``exp(dv4)`` and its ``expm1`` (no
    exponential per piece; ``1 - p`` loses digits only relative to its start, where it
    is tiny). The pieces next to the stage's ends take the capillary work in
    the form of :func:`~.bridge.g_diff`.

    The parts of the ends (``start``, ``end`` and ``om_s = 1 - 4 f`` of ``start.d``, see
    :func:`_pieces_parts`) and ``a = sqrt(a2)`` are computed by the caller, once per
    collision where they do not depend on the speed. ``indicator`` False skips ``eta`` and
    ``clear`` (returned as 0 and True) where only the outcome is wanted.
    """
    d_s, s_s, k1, val1 = start
    d_e, s_e, k2, val2 = end
    a2, m_r, c, kcap, f_b, a = law
    delta = abs(ln_f_change(start, end))
    cd = c * (delta / n)
    dv = cd / m_r
    v4_s = 0.0
    dv4 = 0.0
    p = 0.0
    one_m = 0.0
    ratio = 0.0
    em = 0.0
    if n > 1:
        v4_s = val1 if k1 == 1 else val1 + _LN4
        dv4 = ((val2 if k2 == 1 else val2 + _LN4) - v4_s) / n
        # p = 4 f and 1 - p from piece to piece by the step's factor exp(dv4) = 1 + em.
        em = math.expm1(dv4)
        ratio = 1.0 + em
        one_m = om_s
        p = 1.0 - one_m
    two_per_m = 2.0 / m_r
    d_prev = d_s
    s_prev = s_s
    u_prev = d_s + s_prev
    sq_prev = 0.0
    l_cap = 0.0
    l_vis = 0.0
    l_bdw = 0.0
    eta = 0.0
    fb_abs = abs(f_b)
    clear = True
    for j in range(1, n + 1):
        if j == n:
            d = d_e
            s = s_e
            u = d + s
            sq = 0.0
        else:
            one_m = one_m - p * em
            p = p * ratio
            if not one_m > 0.0:  # rounding where both ends lie far beyond a
                one_m = -math.expm1(v4_s + dv4 * j)
            q = math.sqrt(one_m)
            sq = math.sqrt(q)
            t = a / ((1.0 + q) * sq)
            u = (1.0 + q) * t
            s = 0.5 * (u + a * sq)
            d = 0.5 * p * t
        if j == 1 or j == n:
            lc = kcap * (a2 * (d - d_prev) * (1.0 + (d_prev + d) / (s_prev + s))
                         / (u_prev * u))
        else:
            lc = kcap * a * (sq_prev - sq)
        lb = f_b * (d - d_prev)
        if not cd < m_r * v:
            return 0.0, 1, l_cap + lc, l_vis, l_bdw + lb, math.inf, False
        lv = cd * (v - 0.5 * dv)
        k_lo = 0.0
        if indicator:
            k_lo = k - max(lc, 0.0) - lv - max(lb, 0.0)
        k = k - lc - lv - lb
        if indicator:
            k_lo = max(k_lo, k + min(lc, 0.0) + min(lb, 0.0))
            eta += cd / (m_r * (v - dv)) * (abs(lc) + fb_abs * abs(d_prev - d))
        l_cap += lc
        l_vis += lv
        l_bdw += lb
        if not k > 0.0:
            return k, 2, l_cap, l_vis, l_bdw, math.inf, False
        # Every loss and gain grows monotonically along a piece (each force keeps its
        # sign over a stage), so the energy inside it is at least its start less the
        # losses and at least its end less the gains (k_lo): the piece is clear of an
        # energy minimum near 0 between its ends when k_lo exceeds the indicator summed
        # so far.
        if indicator and not k_lo > eta:
            clear = False
        if j < n:
            v = math.sqrt(k * two_per_m)
        d_prev = d
        s_prev = s
        u_prev = u
        sq_prev = sq
    return k, 0, l_cap, l_vis, l_bdw, eta, clear


@njit(cache=CACHE)
def piecewise_kernel(pair, w, n, det):
    """One collision (``pair`` a :class:`~.records.Pair`, speed ``w`` [m/s]) by the closed
    forms of :func:`~.relative.relative_kernel` applied on ``n`` pieces of each liquid
    stage, each piece starting from the speed the previous one left (module docstring,
    item 2; ``benchmarks/results/auto_calibration.md``, "Piecewise closed forms").

    Returns ``(e_w, stage, path, g, clear)`` with ``g`` the error indicator summed over
    the pieces (``inf`` where the pair sticks) and ``clear`` False where the energy inside
    a piece may come near 0 (:func:`_stage_pieces`; then ``g`` bounds nothing). ``det``
    of length 0 or ``len(DETAIL_NAMES)`` as in :func:`~.relative.relative_kernel` (the
    stage losses summed over the pieces).
    ``n = 1`` gives the ``(e_w, stage, path, g)`` of :func:`closed_form_indicator` bitwise
    (tested).
    """
    e = pair.e
    if not pair.H0 > pair.Ha:
        stages.fresh_details(det)
        ew, st, pa = stages.dry_contact(det, reduced_mass(pair.m_i, pair.m_j)[0], e, w)
        return ew, st, pa, 0.0, True
    return _piecewise(pair, w, n, det, _collision_parts(pair))


@njit(cache=CACHE, error_model="numpy")
def _piecewise(pair, w, n, det, parts, indicator=True):
    """:func:`piecewise_kernel` with ``H0 > Ha`` from the collision's ``parts``
    (:func:`_collision_parts`); ``indicator`` False: the outcome only (``g`` and ``clear``
    then mean nothing; :func:`_stage_pieces`)."""
    H0, Ha, e = pair.H0, pair.Ha, pair.e
    (m_r, frac_i, frac_j, a2, c, kcap, f_b, a, k_h0, v_h0, s_h0, om_h0, k_ha, v_ha, s_ha,
     om_ha, vol3) = parts
    law = (a2, m_r, c, kcap, f_b, a)
    gap_ha = Gap(Ha, s_ha, k_ha, v_ha)
    nan = math.nan
    want = stages.fresh_details(det)
    k0 = 0.5 * m_r * w * w
    h_rupt = nan
    if want:
        stages.split_details(det, codes.K_INI_I, codes.K_INI_J, frac_i, frac_j, k0)
        det[codes.ST_APP] = m_r * w / c
    k_app, code, l_cap, l_vis, l_bdw, eta, clear = _stage_pieces(
        k0, w, Gap(H0, s_h0, k_h0, v_h0), om_h0, gap_ha, law, n, indicator)
    if want:
        # a viscous stop leaves the viscous loss NaN, as in relative_kernel
        stages.stage_details(det, False, l_cap, l_vis if code != 1 else nan, l_bdw, frac_i, frac_j)
    stage = codes.REBOUND
    path = 0
    k_end = 0.0
    if code == 1:
        stage = codes.APP_VIS
    elif code == 2:
        stage = codes.APP_EN
    else:
        w_s = stages.relative_contact(det, frac_i, frac_j, m_r, e, k_app)
        if not w_s > 0.0:
            stage = codes.CONTACT
        else:
            k_s, h_rupt = stages.separation_start(det, pair, frac_i, frac_j, m_r, w_s, vol3)
            if not h_rupt > Ha:
                path |= codes.P_BROKEN
                k_end = k_s
            else:
                k_end, code, l_cap, l_vis, l_bdw, eta_s, clear_s = _stage_pieces(
                    k_s, w_s, gap_ha, om_ha, Gap(h_rupt, *gap_parts(h_rupt, a2)), law, n,
                    indicator)
                eta = eta + eta_s
                clear = clear and clear_s
                if want:
                    stages.stage_details(det, True, l_cap, l_vis if code != 1 else nan, l_bdw,
                                         frac_i, frac_j)
                if code == 1:
                    stage = codes.SEP_VIS
                elif code == 2:
                    stage = codes.SEP_EN
            if stage == codes.REBOUND and want:
                stages.split_details(det, codes.K_FIN_I, codes.K_FIN_J, frac_i, frac_j, k_end)
    if want:
        stages.work_details(det, WorkScale(k0, w, c, kcap, f_b, H0, Ha, a2), h_rupt)
    if stage != codes.REBOUND:
        return 0.0, stage, path, math.inf, False
    ew = math.sqrt(k_end / k0)
    if not ew > 0.0:
        return 0.0, codes.SEP_EN, path, math.inf, False
    eta /= k0
    return ew, codes.REBOUND, path, eta / max(ew, math.sqrt(eta)), clear


@njit(parallel=True, cache=CACHE)
def _piecewise_batch(ins, n, e_w, stage, path, g, clear):
    empty = np.empty(0)
    for q in prange(e_w.shape[0]):
        ew, st, pa, gq, cl = piecewise_kernel(pair_at(ins, q), ins.w[q], n, empty)
        e_w[q] = ew
        stage[q] = st
        path[q] = pa
        g[q] = gq
        clear[q] = cl


def piecewise_batch(ins: TierInputs, n_pieces):
    """:func:`piecewise_kernel` over the 1-D arrays ``ins`` (a :class:`~.records.TierInputs`
    or its arrays in order): ``(e_w, stage, path, g, clear)``."""
    n_pieces = int(n_pieces)
    if n_pieces < 1:
        raise ValueError(f"n_pieces = {n_pieces!r} must be at least 1")
    ins = tier_inputs(ins)
    size = ins.w.shape[0]
    e_w, stage, path, _ = stages.tier_outputs(size, False)
    g = np.empty(size)
    clear = np.empty(size, dtype=np.bool_)
    parallel_launch(_piecewise_batch, ins, n_pieces, e_w, stage, path, g, clear)
    return e_w, stage, path, g, clear


@njit(cache=CACHE)
def _decide(pair, w, tol, empty):
    """The outcome and the form to use for one collision (``pair`` a
    :class:`~.records.Pair`, speed ``w`` [m/s], tolerance ``tol`` in ``e_w``): ``(e_w,
    stage, path, pieces, bound)`` with ``pieces`` 1 (the closed forms on whole stages),
    one of :data:`PIECES` (the piecewise closed forms) or 0 ("ode": the outcome returned is
    then the closed forms', to be replaced). ``empty`` is any array of length 0."""
    return _decide_inline(pair, w, tol, empty)


@njit(cache=CACHE, inline="always")
def _decide_inline(pair, w, tol, empty):
    """:func:`_decide` with the whole-stage forms written into the caller and the rest
    (:func:`_decide_beyond`, 15 % of the collisions on the benchmark batch) called."""
    e = pair.e
    if not pair.H0 > pair.Ha:
        ew, st, pa = stages.no_bridge(e)
        return ew, st, pa, 1, 0.0
    # closed_form_indicator_lean, its speed-independent part kept for a second speed
    whole = _whole_parts(pair)
    first = _whole_at(w, e, pair.theta, pair.mu_l, pair.gamma, whole)
    ew, st, pa, g = first
    if ew > 0.0:
        b = CLOSED_FORM_BOUND * g
        if g <= G_MAX and b <= tol:
            return ew, st, pa, 1, b
    return _decide_beyond(pair, w, tol, empty, whole, first)


@njit(cache=CACHE)
def _decide_beyond(pair, w, tol, empty, whole, first):
    """:func:`_decide` where the whole-stage forms' bound did not pass at once; ``whole``
    the collision's :func:`_whole_parts`, ``first`` the whole-stage forms'
    ``(e_w, stage, path, g)`` at ``w``."""
    e, theta, mu_l, gamma = pair.e, pair.theta, pair.mu_l, pair.gamma
    ew, st, pa, g = first
    if not ew > 0.0:
        # Stick: trust it if the closed forms still stick at STICK_MARGIN x the speed (the
        # same closed forms as relative_kernel, bitwise, tested, without a details array).
        ew2, _, _, _ = _whole_at(w * STICK_MARGIN, e, theta, mu_l, gamma, whole)
        if not ew2 > 0.0:
            return ew, st, pa, 1, 0.0
    assisted = whole[4] < 0.0  # the relative body force pulls the pair apart
    if st == codes.SEP_VIS and assisted:
        # Viscosity alone stopped the whole stages in the separation against a body force
        # that pulls the pair apart: the pieces' stick is not trusted there (below), and on
        # the benchmark batch none of these 8157 collisions (0.8 %) was decided by the
        # pieces, which cost 0.9 us each in vain: "ode" (cost only).
        return ew, st, pa, 0, 0.0
    rebound = ew > 0.0
    parts = _pieces_parts(pair.m_i, pair.m_j, whole)
    for i in range(len(PIECES)):
        n = PIECES[i]
        # The pieces divide the indicator by about n (measured at least 1/n of the whole
        # stages' on the benchmark batch): skip a count that cannot pass (cost only).
        if rebound and PIECEWISE_BOUND * g > n * tol:
            continue
        margin = PIECE_STICK_MARGIN[i]
        if not rebound:
            # The whole stages stick within their margin: try the margin's speed first (a
            # rebound there ends this count; measured on the benchmark batch: no stick of
            # the whole stages became a rebound of the pieces with a passing bound).
            ew2, st2, _, _, _ = _piecewise(pair, w * margin, n, empty, parts, False)
            if ew2 > 0.0 or (st2 == codes.SEP_VIS and assisted):
                continue
        ew_n, st_n, pa_n, g_n, clear = _piecewise(pair, w, n, empty, parts)
        if ew_n > 0.0:
            b = PIECEWISE_BOUND * g_n
            if clear and g_n <= G_MAX and b <= tol:
                return ew_n, st_n, pa_n, n, b
        elif not (st_n == codes.SEP_VIS and assisted):
            # A stick, trusted if the pieces still stick at the margin's speed, neither
            # time stopped by viscosity while the body force pulls the pair apart (then
            # the integrated pair keeps moving: such thresholds set the measured u* error
            # of 2.5 %, the others 1.6 % at n = 4, 0.6 % at n = 16).
            if not rebound:
                return ew_n, st_n, pa_n, n, 0.0
            ew2, st2, _, _, _ = _piecewise(pair, w * margin, n, empty, parts, False)
            if not ew2 > 0.0 and not (st2 == codes.SEP_VIS and assisted):
                return ew_n, st_n, pa_n, n, 0.0
    return ew, st, pa, 0, 0.0


class ChoiceFlags(NamedTuple):
    """The settings of the fused loop of "auto" (:func:`auto_fused`)."""

    #: True: body forces act (:func:`~.fused._one`'s ``body``)
    body: bool
    #: True: the drag on a particle from its own slip (:func:`~.fused.slip_flag`)
    particle_slip: bool
    #: True: the lab-speed rules are checked in the same pass
    check: bool
    #: the tolerance in ``e_w`` [-]
    tol: float


class ChoiceOutputs(NamedTuple):
    """The output arrays of the fused loop of "auto" (:func:`auto_fused`), one element per
    collision."""

    #: wet restitution coefficients [-]
    e_w: np.ndarray
    #: stage codes (:class:`~.outcome.Stage`)
    stage: np.ndarray
    #: path flags (:class:`~.outcome.Path`)
    path: np.ndarray
    #: relative normal impact speeds [m/s]
    w: np.ndarray
    #: the form used (``pieces`` of :func:`auto_batch`; -1 "ode" failed)
    pieces: np.ndarray


@njit(cache=CACHE, inline="always")
def _choose_block(ins, st, flags, opts, out, k0, k1):
    """The fused loop of "auto" over collisions ``k0 <= k < k1`` (one thread, carrying the
    angles' memo), as :func:`~.fused._fused_block`: each speed rule's first offender among
    them (``n``: none) is returned. ``ins, st``: the fused kernels' raw inputs and their
    steps; ``flags`` a :class:`ChoiceFlags`, ``opts`` the :class:`~.records.OdeOptions` of
    "ode" where it is chosen, ``out`` a :class:`ChoiceOutputs`. Written into both entries
    (inline): called as a function it cost about 1 % more on the benchmark batch."""
    body, particle_slip, check, tol = flags
    e_w, stage, path, w_out, pieces = out
    empty = np.empty(0)
    n = e_w.shape[0]
    g1 = n
    g2 = n
    g3 = n
    g4 = n
    last = NO_ANGLES
    for q in range(k0, k1):
        if check:
            g1, g2, g3, g4, skip = _rules_update(ins, st, q, g1, g2, g3, g4)
            if skip:  # no approach, or an infinite speed: nothing to compute
                e_w[q] = math.nan
                stage[q] = -1
                path[q] = 0
                w_out[q] = math.nan
                pieces[q] = 0
                continue
        (m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, _, a_t, a_c, a_b,
         a_s) = _one(ins, st, q, body, particle_slip, last)
        last = (a_t, a_c, a_b, a_s)
        mu_l = ins[8][q * st[8]]
        gamma = ins[9][q * st[9]]
        e = ins[17][q * st[17]]
        pair = Pair(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e)
        ew, sg, pa, nq, _ = _decide_inline(pair, w, tol, empty)
        if nq == 0:
            # "ode" here, on the numbers just prepared (what ode_batch does with them).
            ew, sg, pa, _, status = ode_kernel(pair, w, empty, opts)
            if status != 0:
                nq = -1
        e_w[q] = ew
        stage[q] = sg
        path[q] = pa
        w_out[q] = w
        pieces[q] = nq
    return g1, g2, g3, g4


# The serial and the parallel entry run the same block function (as in .fused).


@njit(cache=CACHE)
def _choose_serial(ins, st, flags, opts, out):
    return _choose_block(ins, st, flags, opts, out, 0, out.e_w.shape[0])


@njit(parallel=True, cache=CACHE)
def _choose_parallel(ins, st, flags, opts, out):
    n = out.e_w.shape[0]
    # Each speed rule's first offender as a min-reduction over the blocks.
    f1 = n
    f2 = n
    f3 = n
    f4 = n
    for b in prange((n + BLOCK - 1) // BLOCK):
        g1, g2, g3, g4 = _choose_block(ins, st, flags, opts, out, b * BLOCK,
                                       min(n, (b + 1) * BLOCK))
        f1 = min(f1, g1)
        f2 = min(f2, g2)
        f3 = min(f3, g3)
        f4 = min(f4, g4)
    return f1, f2, f3, f4


def auto_fused(ins, steps, n, *, body, particle_slip, tol=DEFAULT_TOL, return_pieces=False,
               check=False):
    """Mode "auto" without details from the fused kernels' inputs (:mod:`.fused`): the
    preparation, the choice and "ode" where it is chosen in one compiled loop (no details
    rows, no second pass). Returns ``(e_w, stage, path, w)``, bitwise what
    :func:`auto_batch` gives on the prepared arrays (tested); with ``return_pieces`` also
    the form used per collision (``pieces`` of :func:`auto_batch`). With ``check`` the lab
    speeds are validated in the same pass and ``(code, index)`` is appended, as by
    :func:`~.fused.fused_batch`; a caller must raise on a nonzero code (the collisions
    that break rule 3 or 4 are not computed)."""
    tol = _check_tol(tol)
    e_w, stage, path, _ = stages.tier_outputs(n, False)
    w = np.empty(n)
    pieces = np.empty(n, dtype=np.int8)
    o = ode_options(ode_rtol(tol))
    opts = OdeOptions(o["rtol"], o["atol"], False, True, o["first_step"], o["max_step"],
                      o["first_change"], o["stick_margin"])
    args = (ins, steps, ChoiceFlags(bool(body), slip_flag(particle_slip), bool(check), tol),
            opts, ChoiceOutputs(e_w, stage, path, w, pieces))
    if n < SERIAL_BELOW:
        first = _choose_serial(*args)
    else:
        first = parallel_launch(_choose_parallel, *args)
    rule = _first_rule(first, n)
    if check and rule[0]:
        out = (e_w, stage, path, w) + ((pieces,) if return_pieces else ())
        return out + (rule,)
    if pieces.min() < 0:
        bad = int(np.flatnonzero(pieces < 0)[0])
        raise RuntimeError(
            f"ode: collision {bad} needed more than {MAX_STEPS} steps in one stage "
            f"(w = {w[bad]!r} m/s); loosen tol = {tol!r}"
        )
    out = (e_w, stage, path, w) + ((pieces,) if return_pieces else ())
    return out + ((rule,) if check else ())


def ode_rtol(tol):
    """Integration tolerance of the "ode" tier inside "auto" for a tolerance ``tol`` in
    ``e_w``: its error bound in ``k`` (:data:`ODE_K_ERROR_PER_RTOL` ``rtol``) must stay
    below ``tol^2``, since near the critical speed an error ``dk`` in ``k = e_w^2`` moves
    ``e_w`` by up to ``sqrt(dk)``."""
    return min(ODE_RTOL_MAX, tol * tol / ODE_K_ERROR_PER_RTOL)


def ode_options(rtol):
    """The keywords of :func:`~.ode.ode_batch` for the "ode" tier inside "auto" at ``rtol``:
    ``atol = 1e-2 rtol``, :data:`ODE_STEPS`, and the stick stop of the separation with the
    error bound in ``k`` as its margin (``ODE_K_ERROR_PER_RTOL rtol``): the separation ends
    as a stick once the pair would stick even with that much more energy, so that a pair
    stopped there sticks in the exact integration too, as long as the integration error is
    within that bound (tested on pairs near the critical speed)."""
    rtol = float(rtol)
    return dict(rtol=rtol, atol=1e-2 * rtol, first_step=float(ODE_STEPS["first_step"]),
                max_step=float(ODE_STEPS["max_step"]),
                first_change=float(ODE_STEPS["first_change"]),
                stick_margin=ODE_K_ERROR_PER_RTOL * rtol)


def ode_bound(e_w, rtol):
    """Error bound in ``e_w`` [-] of "ode" results ``e_w`` at ``rtol``: with ``dk`` the
    bound in ``k``, ``|e_w - e_w(ode)| = |k - k(ode)| / (e_w + e_w(ode))``, at most
    ``min(sqrt(dk), dk / e_w)``."""
    dk = ODE_K_ERROR_PER_RTOL * rtol
    return np.minimum(math.sqrt(dk), dk / np.maximum(e_w, 1e-300))


def _check_tol(tol):
    tol = float(tol)
    if not (1e-6 <= tol <= 0.5):
        raise ValueError(f"tol = {tol!r} is outside the allowed range [1e-6, 0.5]")
    return tol


@njit(parallel=True, cache=CACHE)
def _choose(ins, tol, e_w, stage, path, pieces, bound, det):
    empty = np.empty(0)
    want = det.shape[1] > 0
    for q in prange(e_w.shape[0]):
        pair = pair_at(ins, q)
        w = ins.w[q]
        ew, st, pa, nq, b = _decide(pair, w, tol, empty)
        e_w[q] = ew
        stage[q] = st
        path[q] = pa
        pieces[q] = nq
        bound[q] = b
        if want and nq > 0:
            # The details of the form chosen (its outcome is the one above, bitwise).
            if nq == 1:
                relative_kernel(pair, w, det[q])
            else:
                piecewise_kernel(pair, w, nq, det[q])


def auto_batch(ins: TierInputs, *, details=False, tol=DEFAULT_TOL, return_pieces=False):
    """:func:`run_auto` that also returns the tier used per collision (``TIER_RELATIVE``:
    the closed forms on the relative motion, on whole stages or piecewise; ``TIER_ODE``)
    and its error bound in ``e_w`` [-] (fifth and sixth arrays). With ``return_pieces`` a
    seventh array says which form: 1 the closed forms on whole stages, ``n`` in
    :data:`PIECES` the piecewise closed forms on ``n`` pieces, 0 "ode". ``ins``: the input
    arrays (a :class:`~.records.TierInputs`, or its arrays in order)."""
    tol = _check_tol(tol)
    ins = tier_inputs(ins)
    n = ins.w.shape[0]
    e_w, stage, path, det = stages.tier_outputs(n, details)
    pieces = np.empty(n, dtype=np.int8)
    bound = np.empty(n)
    parallel_launch(_choose, ins, tol, e_w, stage, path, pieces, bound, det)
    idx = np.flatnonzero(pieces == 0)
    if idx.size:
        rtol = ode_rtol(tol)
        sub = TierInputs(*(np.ascontiguousarray(a[idx]) for a in ins))
        e_o, st_o, pa_o, det_o, _ = ode_batch(sub, details=details, **ode_options(rtol))
        e_w[idx], stage[idx], path[idx] = e_o, st_o, pa_o
        bound[idx] = ode_bound(e_o, rtol)
        if details:
            det[idx] = det_o
    tier = np.where(pieces == 0, TIER_ODE, TIER_RELATIVE).astype(np.int8)
    if return_pieces:
        return e_w, stage, path, det, tier, bound, pieces
    return e_w, stage, path, det, tier, bound


def run_auto(ins: TierInputs, *, details=False, tol=DEFAULT_TOL):
    """Evaluate each collision of ``ins`` (a :class:`~.records.TierInputs`) with the
    cheapest tier whose error bound in ``e_w`` is within ``tol`` [-] (module docstring).
    Returns ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`."""
    e_w, stage, path, det, _, _ = auto_batch(ins, details=details, tol=tol)
    return e_w, stage, path, det
