"""Mode "auto": per collision, the cheapest tier whose error bound is within a tolerance.

Two tiers are candidates, in order of cost: the closed forms on the relative motion
(:mod:`.relative`, ~0.1 us per collision) and the integrated truth (:mod:`.ode`). The
Ennis criterion (:mod:`.stokes`) is cheaper still but is never a candidate: against the
integrated truth its error in ``e_w`` stays above 0.1 over most of the calibration set, even
far above the critical speed (no capillary force, no volume correction, rupture at ``H0``);
``benchmarks/fidelity.py`` reports it. Mode "paper" is not a candidate either: it costs as
much as "relative" and is further from the truth wherever body forces act.

Error bound of the closed forms
-------------------------------
The closed forms take each stage's viscous loss along the viscous-only speed history, while
the capillary and body forces change that history. To first order the energy error of a
stage is bounded by ``(c Delta / (m_r v_min)) |W_cons|``: its viscous number at the stage's
lowest viscous-only speed ``v_min`` (the speed at its end) times the work ``W_cons`` of the
capillary and body forces over it. Summed over approach and separation and divided by the
initial relative kinetic energy this is ``eta`` [-]; the error of
``e_w = sqrt(k_fin)`` then scales as ``g = eta / max(e_w, sqrt(eta))``. The bound used is

``|e_w(relative) - e_w(ode)| <= CLOSED_FORM_BOUND * g``, trusted for ``g <= G_MAX``.

Where the closed forms say "stick", the pair is far enough below the critical speed when the
closed forms still stick at ``STICK_MARGIN`` times the speed; then "ode" sticks too.

How the constants were measured
-------------------------------
``benchmarks/calibrate_auto.py``: 400 random scenes (seed 20240611; diameters 0.2-3 mm, 15 %
plates, densities 1000-5000 kg/m3, asperities 0.01-1 um, H0/Ha 1.2-500, viscosities
1e-3-1e6 Pa s, surface tensions 0.02-0.5 N/m, contact angles 0-60 deg, e 0.3-1, beta 0-90
deg, voidage 0.4-0.9, air at 25 or 800 C), 310 with a finite critical speed, each at 60
speeds from 0.3 to 30 times its "ode" critical speed. Measured: the largest
``|e_w(relative) - e_w(ode)| / g`` over the rebounds with ``g < 0.1`` was 0.119 (bins of
``g`` from 1e-6 to 0.1 all gave 0.118-0.119; above ``g = 0.1`` up to 0.73); the largest
ratio of the critical speeds ``u*(relative) / u*(ode)`` was 1.036. Re-run on the current
property layer (314 scenes, 18840 collisions) the closed-form ratio reads 0.138 for
``g < 1e-3`` (errors below 1.4e-4) and 0.115-0.122 from there to ``g = 0.1``: the bound
below keeps a safety factor of at least 1.45.

The integrated tier inside "auto" runs with :data:`ODE_STEPS` (steps capped at 1 in
``ln D``). Its error is measured in ``k = e_w^2``, the quantity the integration controls:
the largest ``|k - k(ode)| / rtol`` against ``rtol = 1e-10`` was 2.3, 2.9 and 0.77 at
``rtol`` 1e-7, 1e-6 and 1e-5 (0.78 at 1e-4, not used), with no outcome flipped; on the
fidelity suite 1.6, 1.3, 0.87; on 2e5 collisions of the mixed benchmark batch 2.4 and 1.0
at 1e-6 and 1e-5. With mode "ode"'s own first step and no cap the same ratio was 90-190:
the error estimate of the embedded pair is only asymptotic and was fooled by steps of
several units of ``ln D``, which put ``e_w`` off by up to 0.015 at ``rtol = 1e-5`` just
above the critical speed. The constants below add a safety factor to each.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._codes import APP_EN, APP_VIS, CONTACT, P_BROKEN, P_NO_BRIDGE, REBOUND, SEP_EN, SEP_VIS
from ._jit import CACHE, parallel_launch
from .bridge import bridge_volume, g_diff, ln_f_diff, rupture_distance
from .fused import _one, prepare_at
from .ode import ode_batch
from .outcome import DETAIL_NAMES
from .paper import _viscous_loss
from .relative import reduced_mass, relative_body_force, relative_kernel

__all__ = [
    "run_auto",
    "auto_batch",
    "CLOSED_FORM_BOUND",
    "G_MAX",
    "STICK_MARGIN",
    "DEFAULT_TOL",
    "TIER_RELATIVE",
    "TIER_ODE",
]

#: Measured 0.119 (see the module docstring), with a safety factor 1.7.
CLOSED_FORM_BOUND = 0.2
#: Largest ``g`` at which the closed-form bound is trusted (measured up to 0.1).
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
#: measured at most 2.9 for rtol 1e-7 to 1e-5 (module docstring), with a safety factor 3.4.
ODE_K_ERROR_PER_RTOL = 10.0
#: Largest integration tolerance used (the bound above is relied on from 1e-5 down; 1e-4
#: was measured once, with the first step 0.1 and no rate limit, at 22 rtol).
ODE_RTOL_MAX = 1e-5
#: Codes of the tier used per collision.
TIER_RELATIVE, TIER_ODE = 1, 2

_H_RUPT = DETAIL_NAMES.index("h_rupt")
_W_CONTACT = DETAIL_NAMES.index("w_contact")


@njit(cache=CACHE)
def closed_form_indicator(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e,
                          det):
    """The closed forms' ``e_w`` and their error indicator ``g`` (module docstring).

    ``det`` (length 0 or ``len(DETAIL_NAMES)``) receives the closed forms' details: the
    indicator reads the stage quantities from it, so it must have full length here.
    Returns ``(e_w, stage, path, g)``; ``g = inf`` where a stage has no viscous-only end
    speed (the closed forms stick).
    """
    ew, st, pa, _ = relative_kernel(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i,
                                    fn_j, e, det)
    if not H0 > Ha:
        return ew, st, pa, 0.0
    if not ew > 0.0:
        return ew, st, pa, math.inf
    m_r, _, _ = reduced_mass(m_i, m_j)
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    kcap = 2.0 * math.pi * gamma * r * cos_t
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    c_delta = c * -ln_f_diff(H0, Ha, a2)
    w_end = w - c_delta / m_r
    work = abs(kcap * g_diff(H0, Ha, a2))
    eta = c_delta / (m_r * w_end) * (work + abs(f_b) * (H0 - Ha))
    h_rupt = det[_H_RUPT]
    w_s = e * det[_W_CONTACT]
    if h_rupt > Ha:
        c_delta = c * ln_f_diff(Ha, h_rupt, a2)
        w_end = w_s - c_delta / m_r
        work = abs(kcap * g_diff(Ha, h_rupt, a2))
        eta += c_delta / (m_r * w_end) * (work + abs(f_b) * (h_rupt - Ha))
    eta /= k0
    return ew, st, pa, eta / max(ew, math.sqrt(eta))


@njit(cache=CACHE)
def closed_form_indicator_lean(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j,
                               e):
    """:func:`closed_form_indicator` in one pass, without a details row: the closed forms of
    :func:`~.relative.relative_kernel` written out with the same arithmetic, each ``ln f``
    difference, capillary work and the rupture gap computed once for both the outcome and
    the indicator. Bitwise the same ``(e_w, stage, path, g)`` (tested)."""
    m_r, _, _ = reduced_mass(m_i, m_j)
    if not H0 > Ha:
        if e > 0.0:
            return e, REBOUND, P_NO_BRIDGE, 0.0
        return 0.0, CONTACT, P_NO_BRIDGE, 0.0
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu_l * r * r
    kcap = 2.0 * math.pi * gamma * r * cos_t
    f_b = relative_body_force(m_i, m_j, fn_i, fn_j)
    k0 = 0.5 * m_r * w * w
    c_delta = c * -ln_f_diff(H0, Ha, a2)
    l_cap = kcap * g_diff(H0, Ha, a2)
    l_bdw = -f_b * (H0 - Ha)
    if not c_delta < m_r * w:
        return 0.0, APP_VIS, 0, math.inf
    k_app = k0 - l_cap - _viscous_loss(w, m_r, c_delta) - l_bdw
    if not k_app > 0.0:
        return 0.0, APP_EN, 0, math.inf
    w_s = e * math.sqrt(2.0 * k_app / m_r)
    if not w_s > 0.0:
        return 0.0, CONTACT, 0, math.inf
    k_s = 0.5 * m_r * w_s * w_s
    h_rupt = rupture_distance(theta, mu_l * w_s / gamma, bridge_volume(r, a2))
    path = 0
    sep = h_rupt > Ha
    c_delta_s = 0.0
    l_cap_s = 0.0
    if not sep:
        path |= P_BROKEN
        k_end = k_s
    else:
        c_delta_s = c * ln_f_diff(Ha, h_rupt, a2)
        l_cap_s = kcap * g_diff(Ha, h_rupt, a2)
        if not c_delta_s < m_r * w_s:
            return 0.0, SEP_VIS, path, math.inf
        k_end = k_s - l_cap_s - _viscous_loss(w_s, m_r, c_delta_s) - f_b * (h_rupt - Ha)
        if not k_end > 0.0:
            return 0.0, SEP_EN, path, math.inf
    ew = math.sqrt(k_end / k0)
    if not ew > 0.0:
        return 0.0, SEP_EN, path, math.inf
    eta = c_delta / (m_r * (w - c_delta / m_r)) * (abs(l_cap) + abs(f_b) * (H0 - Ha))
    if sep:
        eta += c_delta_s / (m_r * (w_s - c_delta_s / m_r)) * (abs(l_cap_s)
                                                              + abs(f_b) * (h_rupt - Ha))
    eta /= k0
    return ew, REBOUND, path, eta / max(ew, math.sqrt(eta))


@njit(cache=CACHE)
def _decide(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e, tol):
    """The closed forms' outcome and the tier to use for one collision:
    ``(e_w, stage, path, tier, bound)`` as :func:`_choose` decides."""
    ew, st, pa, g = closed_form_indicator_lean(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t,
                                               theta, w, fn_i, fn_j, e)
    tier = TIER_RELATIVE
    bound = 0.0
    if ew > 0.0:
        b = CLOSED_FORM_BOUND * g
        if g <= G_MAX and b <= tol:
            bound = b
        else:
            tier = TIER_ODE
    elif H0 > Ha:
        # The same closed forms as relative_kernel (bitwise, tested), without a details
        # array to allocate per collision.
        ew2, _, _, _ = closed_form_indicator_lean(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t,
                                                  theta, w * STICK_MARGIN, fn_i, fn_j, e)
        if ew2 > 0.0:
            tier = TIER_ODE
    return ew, st, pa, tier, bound


@njit(parallel=True, cache=CACHE)
def _choose_fused(ins, st, body, particle_slip, tol, e_w, stage, path, w_out, tier, bound):
    for q in prange(e_w.shape[0]):
        m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, _ = _one(ins, st, q, body,
                                                                   particle_slip)
        ew, sg, pa, ti, b = _decide(m_i, m_j, r, H0, Ha, ins[8][q * st[8]], ins[9][q * st[9]],
                                    cos_t, theta, w, fn_i, fn_j, ins[17][q * st[17]], tol)
        e_w[q] = ew
        stage[q] = sg
        path[q] = pa
        w_out[q] = w
        tier[q] = ti
        bound[q] = b


def auto_fused(ins, steps, n, body, particle_slip, tol=DEFAULT_TOL):
    """Mode "auto" without details from the fused kernels' inputs (:mod:`.fused`): the
    preparation and the choice in one compiled loop (no details rows), then "ode" on the
    collisions that need it, prepared for those only. Returns ``(e_w, stage, path, w)``,
    bitwise what :func:`auto_batch` gives on the prepared arrays (tested)."""
    tol = _check_tol(tol)
    e_w = np.empty(n)
    stage = np.empty(n, dtype=np.int8)
    path = np.empty(n, dtype=np.int8)
    w = np.empty(n)
    tier = np.empty(n, dtype=np.int8)
    bound = np.empty(n)
    parallel_launch(_choose_fused, ins, steps, bool(body), bool(particle_slip), tol, e_w,
                    stage, path, w, tier, bound)
    idx = np.flatnonzero(tier == TIER_ODE)
    if idx.size:
        rtol = ode_rtol(tol)
        k = prepare_at(ins, steps, idx, body, particle_slip)
        e_o, st_o, pa_o, _, _ = ode_batch(*k[:13], details=False, rtol=rtol,
                                          atol=1e-2 * rtol, **ODE_STEPS)
        e_w[idx], stage[idx], path[idx] = e_o, st_o, pa_o
    return e_w, stage, path, w


def ode_rtol(tol):
    """Integration tolerance of the "ode" tier inside "auto" for a tolerance ``tol`` in
    ``e_w``: its error bound in ``k`` (:data:`ODE_K_ERROR_PER_RTOL` ``rtol``) must stay
    below ``tol^2``, since near the critical speed an error ``dk`` in ``k = e_w^2`` moves
    ``e_w`` by up to ``sqrt(dk)``."""
    return min(ODE_RTOL_MAX, tol * tol / ODE_K_ERROR_PER_RTOL)


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
def _choose(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e, tol,
            e_w, stage, path, tier, bound, det):
    n = e_w.shape[0]
    for q in prange(n):
        scratch = det[q]
        ew, st, pa, g = closed_form_indicator(
            m_i[q], m_j[q], r[q], H0[q], Ha[q], mu_l[q], gamma[q], cos_t[q], theta[q], w[q],
            fn_i[q], fn_j[q], e[q], scratch,
        )
        e_w[q] = ew
        stage[q] = st
        path[q] = pa
        tier[q] = TIER_RELATIVE
        bound[q] = 0.0
        if ew > 0.0:
            b = CLOSED_FORM_BOUND * g
            if g <= G_MAX and b <= tol:
                bound[q] = b
            else:
                tier[q] = TIER_ODE
        elif H0[q] > Ha[q]:
            # Stick: trust it if the closed forms still stick at STICK_MARGIN x the speed.
            ew2, _, _, _ = relative_kernel(
                m_i[q], m_j[q], r[q], H0[q], Ha[q], mu_l[q], gamma[q], cos_t[q], theta[q],
                w[q] * STICK_MARGIN, fn_i[q], fn_j[q], e[q], scratch[:0],
            )
            if ew2 > 0.0:
                tier[q] = TIER_ODE


def auto_batch(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e,
               details=False, tol=DEFAULT_TOL):
    """:func:`run_auto` that also returns the tier used per collision (``TIER_RELATIVE`` or
    ``TIER_ODE``) and its error bound in ``e_w`` [-] (fifth and sixth arrays)."""
    tol = _check_tol(tol)
    n = w.shape[0]
    e_w = np.empty(n)
    stage = np.empty(n, dtype=np.int8)
    path = np.empty(n, dtype=np.int8)
    tier = np.empty(n, dtype=np.int8)
    bound = np.empty(n)
    det = np.empty((n, len(DETAIL_NAMES)))
    args = (m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e)
    parallel_launch(_choose, *args, tol, e_w, stage, path, tier, bound, det)
    idx = np.flatnonzero(tier == TIER_ODE)
    if idx.size:
        rtol = ode_rtol(tol)
        sub = [np.ascontiguousarray(a[idx]) for a in args]
        e_o, st_o, pa_o, det_o, _ = ode_batch(*sub, details=details, rtol=rtol,
                                              atol=1e-2 * rtol, **ODE_STEPS)
        e_w[idx], stage[idx], path[idx] = e_o, st_o, pa_o
        bound[idx] = ode_bound(e_o, rtol)
        if details:
            det[idx] = det_o
    if not details:
        det = det[:, :0]
    return e_w, stage, path, det, tier, bound


def run_auto(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e,
             details=False, tol=DEFAULT_TOL):
    """Evaluate each collision with the cheapest tier whose error bound in ``e_w`` is within
    ``tol`` [-] (module docstring). Returns ``(e_w, stage, path, det)`` like
    :func:`agglomtool.collision.paper.run_paper`."""
    e_w, stage, path, det, _, _ = auto_batch(
        m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e, details=details,
        tol=tol,
    )
    return e_w, stage, path, det
