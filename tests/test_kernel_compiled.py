"""The compiled kernel and its pure-Python source agree.

``paper_kernel.py_func`` (the flow chart run by the interpreter; the helpers it calls stay
compiled) against the compiled, parallel batch ``run_paper`` on a few hundred random but
valid collisions: identical, unequal and plate pairs over wide ranges, the special-case
paths near u0* at beta = 45 and 90 (one particle stops first), and no-bridge cases. Same
e_w (rtol 1e-12), same stage and path, same details. Total asperity height Ha > 0
throughout: ``math.log(0)`` raises in the interpreter where Numba returns -inf.
"""

from __future__ import annotations

import numpy as np

import agglomtool as at
from agglomtool.collision.outcome import DETAIL_NAMES
from agglomtool.collision.paper import paper_kernel, run_paper
from agglomtool.collision.records import Pair, TierInputs
from agglomtool.pair import prepare_pair

AIR = at.Gas(mu=18.48e-6, rho=1.168)


def _kernel_inputs(p_i, p_j, liquid, bed, beta, e, u0):
    """Flat float64 kernel arguments for head-on collisions at lab speed ``u0``."""
    st = prepare_pair(p_i, p_j, liquid, AIR, bed, beta, e, True, "emulsion")
    w = np.asarray(u0, dtype=float) * st.w_per_u0
    fields = (st.m_i, st.m_j, st.r, st.H0, st.Ha, st.mu_l, st.gamma, st.cos_t, st.theta, w,
              st.fn_i, st.fn_j, st.e)
    return [np.ascontiguousarray(a, dtype=np.float64).ravel()
            for a in np.broadcast_arrays(*fields)]


def _random_cases(rng, n):
    def lu(lo, hi, size=n):
        return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), size)

    d_i = lu(10e-6, 10e-3)
    d_j = d_i * lu(1e-3, 1e3)
    d_j[: n // 5] = np.inf  # plates in slot j
    rho_j = np.where(np.isinf(d_j), np.inf, rng.uniform(500.0, 10000.0, n))
    ha_i, ha_j = lu(1e-9, 1e-5), lu(1e-9, 1e-5)
    h0_i = np.where(rng.random(n) < 0.2, 0.0, lu(1e-8, 5e-4))
    h0_j = lu(1e-8, 5e-4)
    p_i = at.Particle(d=d_i, rho=rng.uniform(500.0, 10000.0, n), h0=h0_i, ha=ha_i)
    p_j = at.Particle(d=d_j, rho=rho_j, h0=h0_j, ha=ha_j)
    liq = at.Liquid(mu=lu(1e-4, 1e7), gamma=lu(1e-3, 1.0), rho=rng.uniform(500, 3000, n),
                    theta_deg=rng.uniform(0.0, 85.0, n))
    bed = at.Bed(eps=rng.uniform(0.3, 0.99, n))
    e = rng.uniform(0.0, 1.0, n)
    e[:10] = 0.0
    e[10:20] = 1.0
    first = _kernel_inputs(p_i, p_j, liq, bed, rng.uniform(-180.0, 540.0, n), e,
                           lu(1e-5, 100.0))
    # The mirror: plates in slot i.
    second = _kernel_inputs(p_j, p_i, liq, bed, rng.uniform(0.0, 360.0, n), e,
                            lu(1e-5, 100.0))
    return [np.concatenate([a, b]) for a, b in zip(first, second, strict=True)]


def _near_threshold_cases(checks):
    """The paper's two cases at beta 45 and 90 around u0*, where one particle stops first,
    a particle on a plate around its u0*, and a big grain above a small one."""
    out = []
    plate = at.Particle.plate(h0=100e-6, ha=0.5e-6)
    glass = at.Particle(d=1.74e-3, rho=2500.0, h0=0.0, ha=1e-6)
    _, water, _ = checks.case_water()
    specs = [(p, p, liq, gas, b) for (p, liq, gas) in (checks.case_water(), checks.case_slag())
             for b in (45.0, 90.0, 225.0, 270.0)]
    specs.append((plate, glass, water, AIR, 90.0))
    specs.append((glass, plate, water, AIR, 270.0))
    # A 2 mm grain above a 200 um one: the big one stops first on the approach (a plate,
    # the heavy-partner limit, does so only in a viscous-dominated approach).
    big = at.Particle(d=2e-3, rho=2650.0, h0=20e-6, ha=0.1e-6)
    small = at.Particle(d=200e-6, rho=2650.0, h0=20e-6, ha=0.1e-6)
    specs.append((big, small, water, AIR, 90.0))
    specs.append((small, big, water, AIR, 270.0))  # the mirror: j stops first
    factors = np.geomspace(0.7, 1.5, 25)
    for p_i, p_j, liq, gas, beta in specs:
        u_star = float(at.critical_impact_speed(p_i, p_j, liquid=liq, gas=gas, beta_deg=beta))
        out.append(_kernel_inputs(p_i, p_j, liq, at.Bed(), beta, 0.9, u_star * factors))
    return [np.concatenate(parts) for parts in zip(*out, strict=True)]


def _no_bridge_cases():
    p = at.Particle(d=1e-3, rho=2650.0, h0=np.array([0.0, 0.05e-6, 0.1e-6]), ha=0.1e-6)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0)
    e = np.array([0.0, 0.5, 1.0]).reshape(3, 1)
    return _kernel_inputs(p, p, liq, at.Bed(), 30.0, e, 0.1)


def _compare(args):
    e_w, stage, path, det = run_paper(args, details=True)
    n = e_w.size
    for k in range(n):
        d = np.empty(len(DETAIL_NAMES))
        x = TierInputs(*(a[k] for a in args))
        pair = Pair(*(getattr(x, name) for name in Pair._fields))
        ew, st, pa = paper_kernel.py_func(pair, x.w, d)
        np.testing.assert_allclose(ew, e_w[k], rtol=1e-12, atol=0.0, err_msg=f"e_w at {k}")
        assert st == stage[k], (k, st, stage[k])
        assert pa == path[k], (k, pa, path[k])
        np.testing.assert_allclose(d, det[k], rtol=1e-12, atol=0.0, equal_nan=True,
                                   err_msg=f"details at {k}")
    return stage, path


def test_random_cases_agree():
    args = _random_cases(np.random.default_rng(7), 150)
    assert np.all(args[4] > 0.0)  # Ha > 0 (see the module docstring)
    stage, path = _compare(args)
    # The sample must exercise plates, several stages and both outcomes.
    assert np.any(np.isinf(args[0])) and np.any(np.isinf(args[1]))
    assert len(np.unique(stage)) >= 4
    assert np.any(stage == int(at.Stage.REBOUND)) and np.any(stage != int(at.Stage.REBOUND))
    assert np.any(path & int(at.Path.NO_BRIDGE))


def test_special_paths_near_threshold_agree(checks):
    args = _near_threshold_cases(checks)
    stage, path = _compare(args)
    special = (at.Path.APPROACH_I_STOPS, at.Path.APPROACH_J_STOPS, at.Path.SEPARATION_I_STOPS,
               at.Path.SEPARATION_J_STOPS)
    for flag in special:
        assert np.any(path & int(flag)), f"no case took {flag.name}"
    assert np.any(stage == int(at.Stage.REBOUND)) and np.any(stage != int(at.Stage.REBOUND))


def test_no_bridge_cases_agree():
    args = _no_bridge_cases()
    stage, path = _compare(args)
    assert np.all(path & int(at.Path.NO_BRIDGE))
    assert np.any(stage == int(at.Stage.CONTACT))  # e = 0
