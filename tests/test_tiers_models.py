"""Model tiers "ode", "relative", "stokes" and "auto" (docs/model.md, "The tiers").

Reference data: Shabanian et al. (2024), Heliyon 10:e29397, Table 2 (cases I and II) and
Table 3 (variations). The integrated truth is checked against an independent integration
of the equation of motion in *time* with scipy's implicit Radau at rtol = 1e-12.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

import agglomtool as at
from agglomtool.collision.auto import TIER_ODE, TIER_RELATIVE, auto_batch
from agglomtool.collision.bridge import bridge_volume, rupture_distance
from agglomtool.collision.ode import ode_batch
from agglomtool.collision.relative import run_relative
from agglomtool.pair import prepare_pair

WATER = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
SLAG = at.Liquid(mu=10.0, gamma=0.4, rho=2500.0, theta_deg=10.0)
AIR_25 = at.Gas(mu=18.48e-6, rho=1.168)
AIR_800 = at.Gas(mu=45.48e-6, rho=0.324)
KERNEL_NAMES = ("m_i", "m_j", "r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta")


def case(name, beta=0.0, **over):
    """Table 2 case ``"water"`` (I) or ``"slag"`` (II) as collide() keywords; ``over``
    replaces p_i / p_j."""
    if name == "water":
        p, liq, gas = at.Particle(d=1000e-6, rho=2650, h0=5e-6, ha=0.1e-6), WATER, AIR_25
    else:
        p, liq, gas = at.Particle(d=1000e-6, rho=2650, h0=0.15e-6, ha=0.1e-6), SLAG, AIR_800
    kw = dict(p_i=p, p_j=p, liquid=liq, gas=gas, beta_deg=beta)
    kw.update(over)
    return kw


def glass_on_plate(film=50e-6):
    ball = at.Particle(d=1.74e-3, rho=2500.0, h0=0.0, ha=0.1e-6)
    return dict(p_i=at.Particle.plate(h0=film, ha=0.1e-6), p_j=ball, liquid=WATER, gas=AIR_25,
                bed=at.Bed(eps=0.99, U=0.0), beta_deg=90.0)


def kernel_inputs(kw, w):
    """Flat kernel arrays of one scene at relative speeds ``w`` [m/s]."""
    st_ = prepare_pair(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw.get("bed", at.Bed()),
                       kw["beta_deg"], kw.get("e", 0.9), True, "emulsion")
    w = np.atleast_1d(np.asarray(w, dtype=float))
    full = lambda name: np.full(w.size, float(np.ravel(getattr(st_, name))[0]))  # noqa: E731
    return [full(k) for k in KERNEL_NAMES] + [w] + [full(k) for k in ("fn_i", "fn_j", "e")]


def w_per_u0(kw):
    return 1.0 if (np.isinf(kw["p_i"].d) or np.isinf(kw["p_j"].d)) else 2.0


PAPER_SCENES = [(n, b) for n in ("water", "slag") for b in (0.0, 45.0, 90.0)]


@pytest.fixture(scope="module")
def ode_u0():
    """u0* of "ode" for the paper's cases (identical particles: independent of beta)."""
    return {n: float(at.critical_impact_speed(**case(n), mode="ode")) for n in ("water",
                                                                               "slag")}


# ---------------------------------------------------------------- ode: the integrated truth
def radau_reference(args, rtol=1e-12):
    """e_w of one collision by integrating m_r dv/dt = -kcap X_v - c X_v^2 v / D - F_b in time
    (v = dD/dt), with scipy's Radau; an implementation independent of the gap integrator."""
    m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta, w, fn_i, fn_j, e = (float(a[0]) for a in args)
    m_r = m_i if math.isinf(m_j) else m_j if math.isinf(m_i) else m_i * m_j / (m_i + m_j)
    acc = lambda f, m: 0.0 if math.isinf(m) else f / m  # noqa: E731
    f_b = m_r * (acc(fn_i, m_i) - acc(fn_j, m_j))
    a2 = H0**2 - Ha**2
    c = 1.5 * math.pi * mu * r * r
    kcap = 2 * math.pi * gamma * r * cos_t
    scale = H0 / (m_r * w * w)

    def rhs(_, y):
        x, u = y  # D / H0, v / w; time in H0 / w
        D = x * H0
        xv = 1.0 - D / math.sqrt(D * D + a2)
        return [u, scale * (-kcap * xv - c * xv * xv * u * w / D - f_b)]

    def stage(x0, u0, x_end):
        hit = lambda _, y: y[0] - x_end  # noqa: E731
        hit.terminal = True
        stop = lambda _, y: y[1]  # noqa: E731
        stop.terminal = True
        sol = solve_ivp(rhs, (0.0, 1e7), [x0, u0], method="Radau", rtol=rtol,
                        atol=[1e-14, 1e-14], events=(hit, stop))
        assert sol.status == 1, "no event reached"
        return (sol.y_events[0][0], True) if sol.t_events[0].size else (None, False)

    y, reached = stage(1.0, -1.0, Ha / H0)
    if not reached:
        return 0.0
    u_s = -e * y[1]
    h_rupt = rupture_distance(theta, mu * u_s * w / gamma, bridge_volume(r, a2))
    y, reached = stage(Ha / H0, u_s, h_rupt / H0)
    return y[1] if reached else 0.0


@pytest.mark.parametrize("name,beta", [("water", 90.0), ("slag", 90.0)])
@pytest.mark.parametrize("factor", [0.9, 1.05, 1.3, 3.0])
def test_ode_matches_radau_in_time(name, beta, factor, ode_u0):
    kw = case(name, beta, p_j=at.Particle(d=600e-6, rho=2650,
                                          h0=case(name)["p_i"].h0, ha=0.1e-6))
    args = kernel_inputs(kw, 2 * factor * ode_u0[name])
    ref = radau_reference(args)
    got = ode_batch(args)[0][0]
    assert abs(got - ref) < 1e-6, (got, ref)


def test_ode_matches_radau_glass_on_plate():
    kw = glass_on_plate()
    u_star = float(at.critical_impact_speed(**kw, mode="relative"))
    for factor in (0.8, 1.2, 3.0):
        args = kernel_inputs(kw, factor * u_star)
        assert abs(ode_batch(args)[0][0] - radau_reference(args)) < 1e-6


@pytest.mark.parametrize("name,beta", PAPER_SCENES)
def test_ode_converges(name, beta, ode_u0):
    """Halving rtol and atol changes e_w by < 1e-6 (the integrator's accuracy goal)."""
    args = kernel_inputs(case(name, beta), 2 * ode_u0[name] * np.geomspace(0.5, 10, 200))
    e1 = ode_batch(args)[0]
    e2 = ode_batch(args, rtol=0.5e-10, atol=0.5e-12)[0]
    assert np.abs(e1 - e2).max() < 1e-6
    assert np.any(e1 > 0) and np.any(e1 == 0)


def test_ode_self_consistent_rupture_is_consistent(ode_u0):
    kw = case("water")
    res = at.collide(**kw, u0=ode_u0["water"] * np.array([1.1, 2.0, 5.0]),
                     mode="ode_selfconsistent")
    d = res.details
    v_rupt = res.e_w * res.w
    np.testing.assert_allclose(d["Ca"], WATER.mu * v_rupt / WATER.gamma, rtol=1e-12)
    r, a2 = 500e-6, (10e-6) ** 2 - (0.2e-6) ** 2
    h = [rupture_distance(np.deg2rad(10.0), ca, bridge_volume(r, a2)) for ca in d["Ca"]]
    np.testing.assert_allclose(d["h_rupt"], h, rtol=1e-9)


def test_ode_energy_balance_in_details(ode_u0):
    """The integrated viscous loss is positive and the stage balances close."""
    res = at.collide(**case("slag", 90.0), u0=ode_u0["slag"] * 2.0, mode="ode")
    d = {k: float(v) for k, v in res.details.items()}
    assert d["L_vis_app"] > 0 and d["L_vis_sep"] > 0
    k0 = d["K_ini_i"] + d["K_ini_j"]
    k_app = d["K_app_i"] + d["K_app_j"]
    body = d["L_bdw_app_i"] + d["L_bdw_app_j"]
    assert k0 - d["L_cap_app"] - d["L_vis_app"] - body == pytest.approx(k_app, rel=1e-12)


# ---------------------------------------------------------------- relative
@pytest.mark.parametrize("name", ["water", "slag"])
@pytest.mark.parametrize(
    "pj", [None, dict(d=600e-6), dict(rho=4330.0), dict(ha=0.12e-6)], ids=str
)
def test_relative_equals_paper_at_beta_zero(name, pj):
    kw = case(name, 0.0)
    if pj is not None:
        p = kw["p_i"]
        kw["p_j"] = at.Particle(**{**dict(d=p.d, rho=p.rho, h0=p.h0, ha=p.ha), **pj})
    u = float(at.critical_impact_speed(**kw, mode="paper")) * np.geomspace(0.3, 10, 300)
    a = at.collide(**kw, u0=u, mode="paper")
    b = at.collide(**kw, u0=u, mode="relative")
    # Equal to rounding: e_w = sqrt(k_fin) with k_fin a sum of O(1) terms, so rounding of
    # ~1e-16 in k becomes ~1e-14 in e_w near the threshold (e_w ~ 0.01).
    np.testing.assert_allclose(b.e_w, a.e_w, rtol=1e-12, atol=1e-13)
    np.testing.assert_array_equal(b.stage, a.stage)


@pytest.mark.parametrize("name", ["water", "slag"])
def test_relative_u0_independent_of_direction_for_identical_particles(name):
    u = at.critical_impact_speed(**case(name, np.array([0.0, 30.0, 45.0, 60.0, 90.0])),
                                 mode="relative")
    np.testing.assert_allclose(u, u[0], rtol=1e-12)
    # ... while the paper's model moves with the direction (its CM-frame bookkeeping)
    p = at.critical_impact_speed(**case(name, np.array([0.0, 90.0])), mode="paper")
    assert p[1] < p[0] * (1 - 1e-3)


@settings(max_examples=30, deadline=None)
@given(beta=st.floats(0.0, 90.0), factor=st.floats(0.5, 10.0))
def test_relative_e_w_independent_of_direction(beta, factor):
    u = 0.034 * factor
    e0 = at.collide(**case("water", 0.0), u0=u, mode="relative").e_w
    eb = at.collide(**case("water", beta), u0=u, mode="relative").e_w
    assert eb == e0


def test_relative_plate_is_the_heavy_partner_limit():
    """A plate (held, no body force) is the m_j -> inf limit of the relative tier."""
    kw = glass_on_plate()
    u = float(at.critical_impact_speed(**kw, mode="relative")) * np.geomspace(0.5, 10, 50)
    plate = kernel_inputs(kw, u)
    heavy = [a.copy() for a in plate]
    assert np.isinf(plate[0][0])  # the plate is p_i here
    heavy[0][:] = 1e12 * plate[1][0]  # m_i finite, huge (r kept: the harmonic-radius limit)
    assert np.all(heavy[10] == 0.0)  # its body force stays 0: nothing accelerates it
    e_p = run_relative(plate)[0]
    e_h = run_relative(heavy)[0]
    np.testing.assert_allclose(e_h, e_p, rtol=1e-9, atol=1e-12)


# ---------------------------------------------------------------- stokes
def test_stokes_criterion_and_rebound_estimate():
    kw = case("water")
    st_ = prepare_pair(kw["p_i"], kw["p_j"], WATER, AIR_25, at.Bed(), 0.0, 0.9, True,
                       "emulsion")
    m_r = float(st_.m_i[()]) / 2
    c = 1.5 * math.pi * WATER.mu * float(st_.r[()]) ** 2
    w_crit = (1 + 1 / 0.9) * math.log(10.0 / 0.2) * c / m_r
    res = at.collide(**kw, u0=0.5 * w_crit * np.array([1 - 1e-9, 1 + 1e-9, 1e9]),
                     mode="stokes")
    assert res.e_w[0] == 0.0 and 0.0 < res.e_w[1] < 1e-8
    assert res.e_w[2] == pytest.approx(0.9, abs=1e-8)


# ---------------------------------------------------------------- every tier far above u0*
FAR_TIERS = ["paper", "relative", "ode_selfconsistent", "auto",
             pytest.param("stokes", marks=pytest.mark.xfail(
                 strict=True, reason="measured: Ennis' criterion has no capillary force, no "
                 "volume correction and ruptures at H0; its e_w is off by > 0.01 at 3 u0* "
                 "(benchmarks/results/fidelity.md)"))]


@pytest.mark.parametrize("mode", FAR_TIERS)
def test_every_tier_agrees_with_ode_far_above_u0(mode, ode_u0):
    for name, beta in PAPER_SCENES:
        kw = case(name, beta)
        u = 3.0 * ode_u0[name]
        truth = float(at.collide(**kw, u0=u, mode="ode").e_w)
        got = float(at.collide(**kw, u0=u, mode=mode).e_w)
        assert abs(got - truth) <= 0.01, (name, beta, got, truth)


# ---------------------------------------------------------------- auto
def auto_suite():
    scenes = [case(n, b) for n, b in PAPER_SCENES]
    scenes += [case(n, 90.0, p_j=at.Particle(d=600e-6, rho=2650, h0=case(n)["p_i"].h0,
                                             ha=0.1e-6)) for n in ("water", "slag")]
    scenes += [case(n, 90.0, p_j=at.Particle(d=1000e-6, rho=4330, h0=case(n)["p_i"].h0,
                                             ha=0.12e-6)) for n in ("water", "slag")]
    scenes += [glass_on_plate(f) for f in (20e-6, 100e-6)]
    scenes += [dict(case("slag", 90.0), liquid=at.Liquid(mu=1e4, gamma=0.4, rho=2500,
                                                         theta_deg=10.0))]
    parts = []
    for kw in scenes:
        u = float(at.critical_impact_speed(**kw, mode="relative"))
        parts.append(kernel_inputs(kw, w_per_u0(kw) * u * np.geomspace(0.5, 10, 150)))
    return [np.concatenate([p[k] for p in parts]) for k in range(13)]


@pytest.mark.parametrize("tol", [0.01, 0.002])
def test_auto_stays_within_tolerance(tol):
    args = auto_suite()
    truth = ode_batch(args)[0]
    e_w, _, _, _, tier, bound = auto_batch(args, tol=tol)
    assert np.abs(e_w - truth).max() <= tol
    assert np.all(bound <= tol)
    # Both tiers are used: the closed forms far from u0*, the integration near it.
    assert np.any(tier == TIER_ODE) and np.any(tier == TIER_RELATIVE)


def test_tol_passes_through_the_api_and_is_refused_elsewhere():
    kw = case("water")
    a = at.collide(**kw, u0=0.05, mode="auto", tol=1e-4)
    b = at.collide(**kw, u0=0.05, mode="ode")
    assert abs(float(a.e_w) - float(b.e_w)) <= 1e-4
    with pytest.raises(ValueError, match="takes no tolerance"):
        at.collide(**kw, u0=0.05, mode="paper", tol=0.01)
    with pytest.raises(ValueError, match="tol"):
        at.collide(**kw, u0=0.05, mode="auto", tol=2.0)
