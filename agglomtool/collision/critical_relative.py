"""The critical relative speed of mode "relative" in near-closed form.

Mode "relative" (:mod:`.relative`) decides a collision in two stages, each a quadratic
energy balance in the speed entering it. This module inverts those balances for the
smallest relative impact speed ``w*`` at which the pair rebounds; the only part without a
closed form is the rupture distance's dependence on the capillary number, which is solved by
a short Newton iteration. :mod:`.critical` checks every candidate with the kernel itself and
falls back to its bracketed search where the check fails.

Notation (as in :mod:`.relative`): reduced mass ``m_r``, ``c = (3/2) pi mu_l r^2``,
``kcap = 2 pi gamma r cos(theta)``, relative body force ``F_b`` (positive: pushes the pair
together), ``a^2 = H0^2 - Ha^2``, ``Delta(D1, D2) = ln f(D2) - ln f(D1)`` with the distance
function ``f`` of Eq. 76, and ``g(D) = D - sqrt(D^2 + a^2)`` the capillary potential
(Eqs. 100-105).

Approach (``H0 -> Ha``)
-----------------------
The exact viscous-only loss ``c Delta_a (w - c Delta_a / (2 m_r))`` (Eqs. 72-75) completes
the square of the kinetic energy, so the energy at contact is::

    K_app(w) = (m_r / 2) (w - w_v)^2 - E_a,   w_v = c |Delta(H0, Ha)| / m_r,
    E_a = kcap (g(Ha) - g(H0)) - F_b (H0 - Ha)

(capillary and body work, constant in ``w``). The pair passes the approach iff ``w > w_v``
(Eq. 73: viscosity alone stops it at or below ``w_v``) and ``K_app > 0``; it then reaches
contact at ``w_c = sqrt((w - w_v)^2 - 2 E_a / m_r)``, a strictly increasing function of ``w``,
and leaves it at ``w_s = e w_c`` (Eqs. 52-53). Over ``w > w_v``, ``w_s`` takes every value
above ``s_min = e sqrt(max(-2 E_a / m_r, 0))`` exactly once; the inverse is::

    w = w_v + sqrt((w_c - w_cmin) (w_c + w_cmin))      (E_a < 0, w_cmin = sqrt(-2 E_a / m_r))
    w = w_v + sqrt(w_c^2 + 2 E_a / m_r)                (E_a >= 0)

both sums of non-negative terms, with the difference of squares factored so that nothing
cancels.

Separation (``Ha -> h_rupt``)
-----------------------------
With ``t = sqrt(Ca)``, ``Ca = mu_l w_s / gamma`` (Eq. 57), the rupture distance (Eq. 94)
is linear in ``t``: ``h(t) = h_b (1 + t)``, ``h_b = (1 + theta/2) V_b^(1/3)``. Where
``h(t) <= Ha`` the bridge is already broken at contact and the pair rebounds. Otherwise the
same completed square gives the energy left at rupture::

    K_end = (m_r / 2) (w_s - V(t))^2 - E_s(t),   V = c Delta(Ha, h) / m_r,
    E_s = kcap (g(h) - g(Ha)) + F_b (h - Ha)

and the pair rebounds iff ``w_s > V`` and ``K_end > 0`` (Eqs. 75, 58-59), i.e. iff::

    F(t) = t^2 / kappa - V(t) - sqrt(2 max(E_s(t), 0) / m_r) > 0,   kappa = mu_l / gamma

(the quadratic's larger root, a sum of non-negative terms: no cancellation). At fixed ``h``
this is the closed form of the threshold; ``h`` itself depends on the answer through ``Ca``,
and ``F(t) = 0`` is solved for ``t`` by Newton's method.

Shape of ``F``: ``ln f`` and ``g`` are concave in the gap (their derivatives ``(1 - D/s)^2/D``
and ``1 - D/s``, ``s = sqrt(D^2 + a^2)``, decrease), ``h`` is linear in ``t``, so ``V`` and,
where ``E_s > 0``, ``sqrt(E_s)`` are concave in ``t`` and ``F`` is convex. ``E_s`` itself is
concave in ``h``; with ``F_b >= 0`` it never turns negative, and with ``F_b < 0`` it is
positive up to one gap ``h_E`` and negative beyond, where ``F = t^2/kappa - V`` is convex
again. So ``F`` is convex on ``[t_min, t_E]`` and on ``[t_E, inf)``: each piece holds at most
one upward crossing after a non-positive start. The first crossing is found by

1. ``t_min = sqrt(kappa s_min)``: if the pair rebounds there (broken bridge, or
   ``F(t_min) > 0``), the threshold is the approach's own, ``w* = w_v + sqrt(max(2 E_a / m_r,
   0))`` (the smallest speed that reaches contact with ``w_s > 0``);
2. with ``F_b < 0``, ``h_E`` from Newton on the concave ``E_s`` started on its right
   (monotone), and ``F(t_E)`` deciding which convex piece holds the first crossing;
3. in that piece, Newton on ``F`` from the quadratic model of ``F`` at the piece's left end
   ``a``: ``t^2/kappa`` exact and ``G = t^2/kappa - F`` (the post-contact speed the
   separation needs at the current rupture distance, the quadratic's root above) replaced
   by its tangent at ``a``. ``G`` is concave on the piece, so the tangent lies above it and
   the start lies at or right of the crossing; from there Newton on the convex ``F``
   decreases onto the crossing quadratically. (Where that start falls outside the piece,
   one fixed-point step ``t <- sqrt(kappa G(a))`` starts instead, a lower bound where
   ``G`` rises.) The iteration is safeguarded by a bracket ``F(lo) <= 0 < F(hi)``: a step
   that leaves it is replaced by its midpoint, or by a doubling while no upper end is
   known. Two or three evaluations of ``F`` after ``F(t_min)`` are typical.

Convergence: the iteration stops when a Newton step changes ``t`` by at most
:data:`NEWTON_RTOL` of ``t`` while ``|F|`` is below ``1e-9`` of the speed scale
``t^2/kappa`` (next to the kink at ``t_E``, where ``F'`` is unbounded, a small step alone
proves nothing), or when the bracket is that narrow; in the quadratic regime the error left
after such a step is far below it. It also stops one evaluation earlier where the iterate
lies right of the crossing (``F > 0``: on a convex piece the Newton step then lands at or
right of it again), the step is at most :data:`QUAD_RATIO` of the previous one (the start
counts as a step from ``a``), ``F'`` changed by less than a factor 2 over that previous
step, and the distance the step leaves, about ``F'' step^2 / (2 F')`` with ``F''`` from
the two slopes, is below ``early_rtol`` of ``t`` (:data:`EARLY_RTOL`, 1e-10, a tenth of the
check's window above the candidate; the caller's rounds with a speed-dependent drag ask for
1e-14). The answer then lies a little right of the crossing, the side the caller's check
allows up to ``rtol``. On the benchmark map: ``F(t_min)`` and one more evaluation. It
gives up after ``max_iter`` evaluations (default :data:`MAX_ITER`) and reports failure: the
caller then runs the bracketed search.

Accuracy: the stages are the kernel's formulas, so the threshold is exact up to the
rounding of ``F`` and of the kernel (which forms ``K`` as ``K_start - losses``, cancelling
where viscosity dominates); the caller verifies the candidate against the kernel at
``w* (1 + delta)`` (rebound) and ``w* (1 + delta)(1 - rtol)`` (stick).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from .._jit import CACHE
from .bridge import _LN4, bridge_volume, g_diff, ln_f_parts
from .relative import _viscous_loss, reduced_mass, relative_body_force

__all__ = ["relative_threshold", "threshold_from", "kernel_constants", "kernel_e_w",
           "KernelConstants", "Separation", "NewtonOptions", "NEWTON_RTOL", "EARLY_RTOL",
           "QUAD_RATIO", "MAX_ITER", "OK", "FAILED", "NEVER"]

#: Newton stops when a step changes ``t = sqrt(Ca)`` by at most this fraction of ``t``.
NEWTON_RTOL = 1e-10
#: Newton (and bracketing) steps allowed before the closed form gives up.
MAX_ITER = 60
#: A Newton step at most this fraction of the previous one counts as quadratic convergence
#: (:func:`_root_in_piece` may then stop one evaluation early).
QUAD_RATIO = 1e-2
#: The early stop's bound on the distance left to the crossing, relative to ``t``: a
#: tenth of the check's window above the candidate (``1e-3 rtol`` = 1e-9 at the default
#: ``rtol``), on the side the check allows (the stop lands right of the crossing).
EARLY_RTOL = 1e-10

#: Status codes of :func:`relative_threshold`.
OK, FAILED, NEVER = 0, 1, 2


class KernelConstants(NamedTuple):
    """The numbers of :func:`.relative.relative_kernel` that do not depend on the speed, for
    one collision with a bridge (:func:`kernel_constants`): what the threshold
    (:func:`threshold_from`), the check of its candidate (:func:`kernel_e_w`) and the
    sticking set (:mod:`.sticking`) share."""

    #: reduced mass [kg]
    m_r: float
    #: ``H0^2 - Ha^2`` [m^2]
    a2: float
    #: viscous constant ``(3/2) pi mu_l r^2`` [kg m]
    c: float
    #: capillary constant ``2 pi gamma r cos(theta)`` [N]
    kcap: float
    #: relative body force, positive pushing the pair together [N]
    f_b: float
    #: ``-Delta(H0, Ha)``, the approach's change of ``ln f`` [-]
    d_app: float
    #: ``g(Ha) - g(H0)``, the approach's capillary difference [m]
    g_app: float
    #: ``V_b^(1/3)``, the cube root of the bridge volume [m]
    v13: float
    #: :func:`.bridge.ln_f_parts` of ``Ha``: the power of 4 [-] ...
    k_ha: int
    #: ... and the logarithm [-]
    v_ha: float
    #: ``sqrt(Ha^2 + a^2)`` [m]
    s_ha: float


class Separation(NamedTuple):
    """The numbers of the separation's ``F(t)`` that do not depend on ``t = sqrt(Ca)``
    (module docstring), for one collision: what :func:`_sep` evaluates ``F`` from."""

    #: ``mu_l / gamma`` [s/m]
    kappa: float
    #: rupture distance at ``Ca = 0``, ``(1 + theta/2) V_b^(1/3)`` [m]
    hb: float
    #: gap at solid contact (the asperities) [m]
    Ha: float
    #: ``H0^2 - Ha^2`` [m^2]
    a2: float
    #: ``c / m_r``: the viscous loss's speed per unit ``Delta`` [m/s]
    c_m: float
    #: ``2 pi gamma r cos(theta)`` [N]
    kcap: float
    #: relative body force, positive pushing the pair together [N]
    f_b: float
    #: reduced mass [kg]
    m_r: float
    #: :func:`.bridge.ln_f_parts` of ``Ha``: the power of 4 [-] ...
    k_ha: int
    #: ... and the logarithm [-]
    v_ha: float
    #: ``sqrt(Ha^2 + a^2)`` [m]
    s_ha: float


class NewtonOptions(NamedTuple):
    """How far the Newton iterations of :func:`threshold_from` may go."""

    #: evaluations allowed before the closed form gives up (:data:`MAX_ITER`)
    max_iter: int
    #: the largest distance [-, of ``t``] the iteration may stop at one evaluation early
    #: (:data:`EARLY_RTOL`; 0: never early)
    early_rtol: float


@njit(cache=CACHE)
def _sep(t, sp):
    """``(F, dF/dt)`` of the separation at ``t = sqrt(Ca)`` (module docstring) from its
    numbers ``sp`` (:class:`Separation`); ``h(t) > Ha`` assumed.

    The same forms as :mod:`.bridge` with the square root shared: ``ln f`` as
    :func:`.bridge.ln_f` (``log1p`` where the gap is large), the capillary difference as
    :func:`.bridge.g_diff`."""
    kappa, hb, Ha, a2, c_m, kcap, f_b, m_r, k_ha, v_ha, s_ha = sp
    h = hb * (1.0 + t)
    s = math.sqrt(h * h + a2)
    hs = h + s
    qq = a2 / (hs * hs)
    if qq < 0.5:
        d_lnf = (math.log1p(-qq * qq) - v_ha) + (k_ha - 1) * _LN4
    else:
        d_lnf = (math.log(h) + math.log(s) - 2.0 * math.log(hs) - v_ha) + k_ha * _LN4
    v = c_m * d_lnf
    x = a2 / hs  # s - h without cancellation
    dv = c_m * (x / s) * (x / s) / h
    g = a2 * (h - Ha) * (1.0 + (Ha + h) / (s_ha + s)) / ((Ha + s_ha) * hs)
    e_s = kcap * g + f_b * (h - Ha)
    f = t * t / kappa - v
    df = 2.0 * t / kappa - hb * dv
    if e_s > 0.0:
        cap = math.sqrt(2.0 * e_s / m_r)
        f -= cap
        de = kcap * x / s + f_b  # dE_s/dh = kcap (1 - h/s) + F_b
        df -= hb * de / (m_r * cap)
    return f, df


@njit(cache=CACHE)
def _root_in_piece(a, f_a, df_a, b, sp, newton):
    """The crossing of ``F`` (:func:`_sep` of ``sp``) in the convex piece ``[a, b]`` (``b``
    may be ``inf``), given ``F(a) = f_a <= 0``, ``F'(a) = df_a`` and ``F(b) > 0`` where
    ``b`` is finite; ``newton``: :class:`NewtonOptions`. Returns ``(t*, ok)``.

    Start: the quadratic model of ``F`` at ``a``, ``t^2/kappa`` exact and ``G = t^2/kappa - F``
    replaced by its tangent; ``G`` is concave on the piece, so the tangent lies above it and
    the start lies at or right of the crossing (where that start is not inside the piece,
    one fixed-point step ``t <- sqrt(kappa G(a))`` instead, a lower bound where ``G``
    rises). Then safeguarded Newton: ``[lo, hi]`` always brackets the crossing
    (``F(lo) <= 0 < F(hi)``); a step that leaves it is replaced by the bracket's midpoint
    (or a doubling while ``hi`` is infinite). Converged when a Newton step changes ``t`` by
    at most ``NEWTON_RTOL t`` while ``|F|`` is at rounding level (a small step next to the
    kink at ``t_E``, where ``F'`` is unbounded, is no convergence), when the bracket itself
    is that narrow, or (``early_rtol > 0``) one evaluation early by the test in the loop.
    """
    kappa = sp.kappa
    max_iter, early_rtol = newton
    lo, hi = a, b
    # d = t - a solves d^2/kappa + F'(a) d + F(a) = 0 (F(a) <= 0: a real root d >= 0),
    # taken in the form without cancellation for either sign of F'(a).
    root = math.sqrt(df_a * df_a - 4.0 * f_a / kappa)
    d = -2.0 * f_a / (df_a + root) if df_a > 0.0 else 0.5 * kappa * (root - df_a)
    x = a + d
    last, df_last = d, df_a  # the last step's size and F' where it was taken (for the stop)
    if not (x > lo and x < hi):
        x = math.sqrt(kappa * (a * a / kappa - f_a))
        last = math.inf
        if not (x > lo and x < hi):
            x = 0.5 * (lo + hi) if hi < math.inf else max(2.0 * lo, 1e-300)
    for _ in range(max_iter):
        f, df = _sep(x, sp)
        step = math.nan
        if df > 0.0:
            step = f / df
            if abs(step) <= NEWTON_RTOL * x and abs(f) <= 1e-9 * (x * x / kappa):
                return x - step, True
            # Right of the crossing (F > 0) on a convex piece the step lands at or right of
            # it again, about F'' step^2 / (2 F') from it. Where F' changed by less than a
            # factor 2 over the last step (no kink nearby: the curvature estimate from the
            # two slopes holds) and that distance is below early_rtol t, this step ends
            # the iteration, one evaluation of F early.
            if (f > 0.0 and step <= QUAD_RATIO * last
                    and 0.5 * df_last < df < 2.0 * df_last):
                curv = abs(df_last - df) / last  # F'' over the last step
                if curv * step * step <= 2.0 * early_rtol * x * df:
                    return x - step, True
        if f > 0.0:
            hi = x
        else:
            lo = x
        if hi < math.inf and hi - lo <= NEWTON_RTOL * hi:
            return hi, True
        xn = x - step if df > 0.0 else math.nan
        last, df_last = abs(step), df
        if not (xn > lo and xn < hi):
            xn = 0.5 * (lo + hi) if hi < math.inf else 2.0 * x
            last = math.inf
        x = xn
    return x, False


@njit(cache=CACHE)
def _e_zero(Ha, a2, kcap, f_b, max_iter):
    """The gap ``h_E > Ha`` beyond which ``E_s < 0`` (``F_b < 0``, ``E_s`` rising at ``Ha``):
    Newton on the concave ``E_s`` from its right, monotone. Returns ``(h_E, ok)``."""
    h = Ha + kcap * (math.sqrt(Ha * Ha + a2) - Ha) / -f_b  # E_s <= 0 here (g_diff <= H0-Ha)
    for _ in range(max_iter):
        s = math.sqrt(h * h + a2)
        e_s = kcap * g_diff(Ha, h, a2) + f_b * (h - Ha)
        de = kcap * (a2 / (s + h)) / s + f_b
        if not de < 0.0:
            return h, False
        step = e_s / de
        h_new = h - step
        if not h_new > Ha:
            return h, False
        if abs(step) <= NEWTON_RTOL * h_new:
            return h_new, True
        h = h_new
    return h, False


@njit(cache=CACHE)
def kernel_constants(p):
    """The numbers of :func:`.relative.relative_kernel` that do not depend on the speed, for
    the collision ``p`` (a :class:`.records.Pair` with a bridge, ``H0 > Ha > 0``; its
    ``e`` is not read), each formed by the same operations as there: a
    :class:`KernelConstants` with ``d_app = -Delta(H0, Ha)``, ``g_app = g(Ha) - g(H0)``,
    ``v13 = V_b^(1/3)``, ``(k_ha, v_ha) = ln_f_parts(Ha)`` and ``s_ha = sqrt(Ha^2 + a^2)``.
    The threshold and the check of its candidate (:func:`kernel_e_w`) share them."""
    m_i, m_j, r, H0, Ha = p.m_i, p.m_j, p.r, p.H0, p.Ha
    mu_l, gamma, cos_t, fn_i, fn_j = p.mu_l, p.gamma, p.cos_t, p.fn_i, p.fn_j
    m_r, _, _ = reduced_mass(m_i, m_j)
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    kcap = 2.0 * math.pi * gamma * r * cos_t
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k_ha, v_ha = ln_f_parts(Ha, a2)
    k_h0, v_h0 = ln_f_parts(H0, a2)
    d_app = -((v_ha - v_h0) + (k_h0 - k_ha) * _LN4)  # -ln_f_diff(H0, Ha), Ha's parts once
    g_app = g_diff(H0, Ha, a2)
    v13 = bridge_volume(r, a2) ** (1.0 / 3.0)
    s_ha = math.sqrt(Ha * Ha + a2)
    return KernelConstants(m_r=m_r, a2=a2, c=c, kcap=kcap, f_b=f_b, d_app=d_app,
                           g_app=g_app, v13=v13, k_ha=k_ha, v_ha=v_ha, s_ha=s_ha)


@njit(cache=CACHE, inline="always")
def kernel_e_w(kc, H0, Ha, mu_l, gamma, theta, e, w):
    """``e_w`` of :func:`.relative.relative_kernel` at relative speed ``w`` [m/s] from its
    speed-independent numbers ``kc`` (:class:`KernelConstants`): the kernel's own
    operations in its own order (bitwise its ``e_w``; a test holds it to that), without
    the details and with the work that does not depend on ``w`` done once. 0 where the
    pair sticks. The gap ``sqrt(h^2 + a^2)`` at rupture is taken once for the distance
    function and the capillary difference (each of :func:`.bridge.ln_f_parts` and
    :func:`.bridge.g_diff` takes the same square root)."""
    m_r, a2, c, kcap, f_b, d_app, g_app, v13, k_ha, v_ha, s_ha = kc
    # ---- approach, H0 -> Ha
    k0 = 0.5 * m_r * w * w
    c_delta = c * d_app
    if not c_delta < m_r * w:
        return 0.0
    l_vis = _viscous_loss(w, m_r, c_delta)
    l_bdw = -f_b * (H0 - Ha)
    k_app = k0 - kcap * g_app - l_vis - l_bdw
    if not k_app > 0.0:
        return 0.0
    # ---- contact
    w_s = e * math.sqrt(2.0 * k_app / m_r)
    if not w_s > 0.0:
        return 0.0
    # ---- separation, Ha -> h_rupt
    k_s = 0.5 * m_r * w_s * w_s
    ca = mu_l * w_s / gamma
    h = (1.0 + 0.5 * theta) * (1.0 + math.sqrt(ca)) * v13
    if not h > Ha:
        k_end = k_s
    else:
        s = math.sqrt(h * h + a2)
        q = a2 / ((h + s) * (h + s))
        if q < 0.5:
            k_h, v_h = 1, math.log1p(-q * q)
        else:
            k_h, v_h = 0, math.log(h) + math.log(s) - 2.0 * math.log(h + s)
        c_delta = c * ((v_h - v_ha) + (k_ha - k_h) * _LN4)
        l_cap = kcap * (a2 * (h - Ha) * (1.0 + (Ha + h) / (s_ha + s))
                        / ((Ha + s_ha) * (h + s)))
        l_bdw = f_b * (h - Ha)
        if not c_delta < m_r * w_s:
            return 0.0
        l_vis = _viscous_loss(w_s, m_r, c_delta)
        k_end = k_s - l_cap - l_vis - l_bdw
        if not k_end > 0.0:
            return 0.0
    e_w = math.sqrt(k_end / k0)
    return e_w if e_w > 0.0 else 0.0


@njit(cache=CACHE)
def relative_threshold(p, max_iter, early_rtol=EARLY_RTOL):
    """Smallest relative impact speed ``w*`` [m/s] above which mode "relative" rebounds
    (module docstring), for the collision ``p`` (a :class:`.records.Pair` with a bridge,
    ``H0 > Ha > 0``, and ``e > 0``).

    Returns ``(w*, status)``: status :data:`OK`; :data:`FAILED` where the iteration did not
    converge (``w*`` meaningless: search instead); :data:`NEVER` where no speed rebounds.
    The kernel sticks at ``w*`` itself and rebounds just above it (to rounding).
    ``early_rtol``: the largest distance [-, of ``t``] the Newton iteration may stop at
    one evaluation early (:data:`EARLY_RTOL`); 0 never stops early (the reference the early
    stop is tested against).
    """
    return threshold_from(kernel_constants(p), p.H0, p.Ha, p.mu_l, p.gamma, p.theta, p.e,
                          NewtonOptions(max_iter=max_iter, early_rtol=early_rtol))


@njit(cache=CACHE, inline="always")
def approach(kc, H0, Ha, mu_l, gamma, theta, e):
    """The approach and the start of the separation of a collision, from its
    :func:`kernel_constants` ``kc``: ``(c_m, w_v, e_a, wc_min, w_app, kappa, hb, t_min)``.

    The approach's contact speed is ``w_c = sqrt((w - w_v)^2 - 2 E_a / m_r)`` for
    ``w > w_v`` (``c_m = c / m_r`` [1/s], ``w_v`` [m/s] its viscous loss, ``e_a`` [J] its
    capillary and body work, ``wc_min`` [m/s] the smallest contact speed, ``w_app`` [m/s]
    the speed up to which every approach sticks); the separation is taken in
    ``t = sqrt(Ca)`` with ``h(t) = hb (1 + t)`` (``kappa = mu_l / gamma`` [s/m], ``hb``
    [m]), from ``t_min`` at the smallest contact speed. Shared by the threshold
    (:func:`threshold_from`) and the sticking sets (:mod:`.sticking`)."""
    m_r, a2, c, kcap, f_b, d_app, g_app, v13, k_ha, v_ha, s_ha = kc
    c_m = c / m_r
    w_v = c_m * d_app
    e_a = kcap * g_app - f_b * (H0 - Ha)
    wc_min = math.sqrt(-2.0 * e_a / m_r) if e_a < 0.0 else 0.0
    w_app = w_v + (0.0 if e_a < 0.0 else math.sqrt(2.0 * e_a / m_r))
    kappa = mu_l / gamma
    hb = (1.0 + 0.5 * theta) * v13
    t_min = math.sqrt(kappa * e * wc_min)
    return c_m, w_v, e_a, wc_min, w_app, kappa, hb, t_min


@njit(cache=CACHE)
def speed_of_separation(t, kappa, e, e_a, m_r, w_v, wc_min, w_app):
    """Relative impact speed [m/s] at which the separation starts at ``t = sqrt(Ca)``: back
    through contact and the approach of :func:`approach` (``w_app`` where the contact
    speed is not above the approach's smallest)."""
    w_c = (t * t / kappa) / e
    if e_a < 0.0:
        if not w_c > wc_min:
            return w_app
        return w_v + math.sqrt((w_c - wc_min) * (w_c + wc_min))
    return w_v + math.sqrt(w_c * w_c + 2.0 * e_a / m_r)


@njit(cache=CACHE)
def threshold_from(kc, H0, Ha, mu_l, gamma, theta, e, newton):
    """:func:`relative_threshold` from the collision's :func:`kernel_constants` ``kc`` (a
    :class:`KernelConstants`); ``newton``: :class:`NewtonOptions`."""
    m_r, a2, c, kcap, f_b, d_app, g_app, v13, k_ha, v_ha, s_ha = kc
    c_m, w_v, e_a, wc_min, w_app, kappa, hb, t_min = approach(kc, H0, Ha, mu_l, gamma,
                                                              theta, e)
    if math.isinf(w_app) or math.isnan(w_app):
        return math.inf, NEVER if math.isinf(w_app) else FAILED
    if hb * (1.0 + t_min) <= Ha:
        return w_app, OK  # the bridge is broken at contact: every contact rebounds
    sp = Separation(kappa=kappa, hb=hb, Ha=Ha, a2=a2, c_m=c_m, kcap=kcap, f_b=f_b, m_r=m_r,
                    k_ha=k_ha, v_ha=v_ha, s_ha=s_ha)
    f_a, df_a = _sep(t_min, sp)
    if f_a > 0.0:
        return w_app, OK
    # The piece [a, b] of F's convexity holding the first crossing.
    a = t_min
    b = math.inf
    if f_b < 0.0 and kcap * (a2 / (H0 + Ha)) / H0 + f_b > 0.0:
        h_e, ok = _e_zero(Ha, a2, kcap, f_b, newton.max_iter)
        if not ok:
            return math.inf, FAILED
        t_e = h_e / hb - 1.0
        if t_e > a:
            f_e, df_e = _sep(t_e, sp)
            if f_e > 0.0:
                b = t_e
            else:
                a = t_e
                f_a = f_e
                df_a = df_e
    t, ok = _root_in_piece(a, f_a, df_a, b, sp, newton)
    if not ok:
        return math.inf, FAILED
    w = speed_of_separation(t, kappa, e, e_a, m_r, w_v, wc_min, w_app)
    if math.isinf(w):
        return math.inf, NEVER
    return w, OK
