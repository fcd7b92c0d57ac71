"""The stopping gap of a particle that stops first in a separation (mode "paper").

:func:`agglomtool.collision.paper._stop_gap` solves a separation of a wetting liquid, where
the running energy is convex and has one zero, by Newton on a better-conditioned residual.
Its result must be the zero the plain scan (``_first_zero_scan``, the reference) finds, to
the scan's bracket width (1e-12) plus the zero's own conditioning: a zero where the energy
crosses with a small slope is only defined to ``rounding(k) / |dE / d ln D|``.

Checked on random stages (both particles' forms and a plate's, body forces of either sign,
some making the energy rise again), and on the collisions of the paper kernel itself that
take this path.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from agglomtool.collision import _codes as C
from agglomtool.collision.bridge import g_diff, gap_parts, ln_f_diff
from agglomtool.collision.paper import _first_zero_scan, _running_energy, _stop_gap
from agglomtool.collision.records import Bridge, Gap, Mover

EPS = np.finfo(float).eps


def _gap(d, a2):
    return Gap(d, *gap_parts(d, a2))


def _slope(D, d_start, k, share, v, m, force, c, kcap, a2):
    """dE / d ln D of the running energy at D (written out here, independently)."""
    s = math.sqrt(D * D + a2)
    gp = a2 / (s * (D + s))  # g'(D) = 1 - D / s
    c_delta = c * abs(ln_f_diff(d_start, D, a2))
    return D * share * (force - kcap * gp) - c * gp * gp * (v - c_delta / m)


def _bound(x_ref, d_start, k, share, v, m, force, c, kcap, a2):
    slope = abs(_slope(x_ref, d_start, k, share, v, m, force, c, kcap, a2))
    return 2e-12 + 8.0 * EPS * k / slope if slope > 0.0 else math.inf


def _check(d_start, d_end, k, share, v, m, force, c, kcap, a2, p, v_sum):
    """(new, reference, allowed relative difference) or None when the stage does not
    make the particle stop (the caller's conditions)."""
    start = _gap(d_start, a2)
    mover = Mover(k, v, share, m, force)
    bridge = Bridge(c, kcap, a2)
    c_delta = c * abs(ln_f_diff(d_start, d_end, a2))
    if not c_delta < p:
        return None
    if _running_energy(d_end, start, mover, bridge) > 0.0:
        return None
    l_cap = kcap * g_diff(d_start, d_end, a2)
    new = _stop_gap(start, _gap(d_end, a2), p - c_delta, l_cap, p, v_sum, force, bridge)
    ref = _first_zero_scan(start, d_end, mover, bridge)
    return new, ref, _bound(ref, d_start, k, share, v, m, force, c, kcap, a2)


def _stages(rng, n):
    """Random separation stages whose particle enters with k = p v / 2 and m v = p (as every
    stage of the kernel does); a tenth are a plate's per-unit-speed form (v = 1, m = p)."""
    ha = 10.0 ** rng.uniform(-8, -6, n)
    h0 = ha * 10.0 ** rng.uniform(0.01, 2.5, n)
    a2 = (h0 - ha) * (h0 + ha)
    d_end = np.maximum(h0 * 10.0 ** rng.uniform(-0.5, 1.0, n), 1.001 * ha)
    m = 10.0 ** rng.uniform(-9, -5, n)
    v = 10.0 ** rng.uniform(-3, 1, n)
    share = rng.uniform(0.01, 1.0, n)
    share[: n // 5] = 1.0
    p = m * v
    plate = np.arange(n) < n // 10
    v_sum = v / share
    v = np.where(plate, 1.0, v)
    m = np.where(plate, p, m)
    share = np.where(plate, 1.0 / v_sum, share)
    k = 0.5 * p * v
    c = 10.0 ** rng.uniform(-12, -6, n)
    kcap = 10.0 ** rng.uniform(-6, -3, n)
    kcap[n // 10: n // 8] = 0.0  # a contact angle of 90 deg: no capillary force
    scale = k / (share * np.abs(d_end - ha))
    force = scale * rng.choice([-3.0, -0.3, 0.0, 0.3, 3.0], n)
    return ha, d_end, k, share, v, m, force, c, kcap, a2, p, v_sum


def test_stop_gap_is_the_scans_zero_on_random_stages():
    rng = np.random.default_rng(11)
    checked = rising = 0
    worst = 0.0
    for args in zip(*_stages(rng, 30000), strict=True):
        out = _check(*args)
        if out is None:
            continue
        new, ref, allowed = out
        checked += 1
        rising += args[6] > 0.0
        worst = max(worst, abs(new - ref) / ref / allowed)
        assert abs(new - ref) <= allowed * ref, (args, new, ref, allowed)
    assert checked > 3000
    assert rising > 300  # body forces that help the motion (a convex energy with a minimum)
    assert worst > 1e-3  # the comparison is not vacuous (the two methods differ)


def test_the_kernels_stopping_gaps_are_the_scans():
    """Paper-kernel collisions where one particle stops first in the separation (water and
    slag, body forces at every angle): the stopping gap the kernel reports in its details
    equals the reference scan's zero of that particle's running energy."""
    import agglomtool as at
    from agglomtool.api import _fused_inputs
    from agglomtool.collision.fused import TIER_PAPER, fused_batch, prepare_flat

    rng = np.random.default_rng(5)
    n = 40000
    slag = rng.random(n) < 0.5
    p_i = at.Particle(d=rng.uniform(3e-4, 1.5e-3, n), rho=rng.choice([2650.0, 4330.0], n),
                      h0=np.where(slag, rng.uniform(0.11e-6, 0.3e-6, n),
                                  rng.uniform(1e-6, 9e-6, n)), ha=0.1e-6)
    p_j = at.Particle(d=rng.uniform(3e-4, 1.5e-3, n), rho=rng.choice([2650.0, 4330.0], n),
                      h0=p_i.h0 * rng.uniform(0.8, 1.2, n), ha=0.1e-6)
    liquid = at.Liquid(mu=np.where(slag, 10.0, 8.9e-4), gamma=np.where(slag, 0.4, 0.073),
                       rho=np.where(slag, 2500.0, 997.0), theta_deg=10.0)
    gas = at.Gas(mu=np.where(slag, 45.48e-6, 18.48e-6), rho=np.where(slag, 0.324, 1.168))
    u_star = at.critical_impact_speed(p_i, p_j, liquid=liquid, gas=gas, beta_deg=0.0,
                                      mode="paper")
    beta = rng.uniform(0.0, 360.0, n)
    u0 = np.maximum(u_star, 0.01) * rng.uniform(1.0, 3.0, n)
    _, ins, steps, _ = _fused_inputs(p_i, p_j, liquid, gas, at.Bed(eps=0.55), beta, 0.9, u0,
                                     None)
    _, _, path, _, det = fused_batch(ins, steps, n, TIER_PAPER, body=True, particle_slip=False,
                                  details=True)
    sel = np.flatnonzero((path & (C.P_SEP_I | C.P_SEP_J)) != 0)
    assert sel.size > 500
    m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, _, _, fn_i, fn_j, e, _ = prepare_flat(
        ins, steps, n, True, False)[:, sel]
    d = det[sel]
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * np.pi * mu_l * r * r
    kcap = 2.0 * np.pi * gamma * r * cos_t
    frac_i, frac_j = m_i / (m_i + m_j), m_j / (m_i + m_j)
    w_s = e * d[:, C.W_CONTACT]
    i_stops = (path[sel] & C.P_SEP_I) != 0
    k = np.where(i_stops, d[:, C.K_SEP_I], d[:, C.K_SEP_J])
    share = np.where(i_stops, frac_j, frac_i)
    m = np.where(i_stops, m_i, m_j)
    force = np.where(i_stops, -fn_i, fn_j)
    for q in range(sel.size):
        ref = _first_zero_scan(_gap(Ha[q], a2[q]), d[q, C.H_RUPT],
                               Mover(k[q], share[q] * w_s[q], share[q], m[q], force[q]),
                               Bridge(c[q], kcap[q], a2[q]))
        allowed = _bound(ref, Ha[q], k[q], share[q], share[q] * w_s[q], m[q], force[q], c[q],
                         kcap[q], a2[q])
        got = d[q, C.D_STOP_SEP]
        assert abs(got - ref) <= allowed * ref, (q, got, ref, allowed)


@pytest.mark.parametrize("force_sign", [-1.0, 1.0])
def test_a_stop_at_the_very_end_returns_the_end(force_sign):
    """When the energy at the stage's end is zero to its last digits, the residual there may
    come out positive: the particle stops at the end, nothing beyond it is returned."""
    ha, d_end, a2 = 1e-7, 1e-5, 1e-12
    got = _stop_gap(_gap(ha, a2), _gap(d_end, a2), 1e-9, 0.0, 1e-9, 1.0, force_sign * 1e-30,
                    Bridge(1e-6, 0.0, a2))
    assert got == d_end
