"""The fused kernels (:mod:`agglomtool.collision.fused`) against the numpy reference.

The reference is the path ``collide`` took before the fusion: ``pair.prepare_pair`` (numpy)
then the tier's batch runner on the flat arrays. Stated bounds:

- the prepared numbers agree to a relative 1e-12, the bound the kernels' callers rely on;
  the ones computed without a power (radius, gaps, contact angle, restitution, the speed)
  are bitwise equal here, and since the pair physics is written once
  (``agglomtool.collision.physics``) the masses and body forces are bitwise equal as well
  (``tests/test_one_source.py`` holds them to that);
- given the same prepared numbers the kernels are the same compiled functions: the fused
  batch is bitwise equal to the batch runner on the compiled preparation, serial or parallel;
- end to end: identical stage, path and stick/rebound outcome everywhere, bitwise equal
  ``w``, and ``e_w`` within 1e-12 relative or 1e-10 absolute: the one-particle-stops path
  solves its stopping gap to a relative 1e-12 (regula falsi), so an ulp of input can move
  ``e_w`` by that much.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import agglomtool as at
from agglomtool.api import _evaluate, _fused_inputs, _lab_speeds
from agglomtool.collision import fused
from agglomtool.collision.paper import run_paper
from agglomtool.collision.records import Pair, RawPair
from agglomtool.collision.relative import run_relative
from agglomtool.pair import prepare_pair
from agglomtool.properties.fluidization import GRAVITY

AIR = at.Gas(mu=18.48e-6, rho=1.168)
HOT = at.Gas(mu=45.48e-6, rho=0.324)
ROWS = ("m_i", "m_j", "r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta", "w", "fn_i", "fn_j",
        "e", "w_per_u0")
EXACT = {"r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta", "w", "e", "w_per_u0"}


def _lu(rng, lo, hi, n):
    return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), n)


def _random_scene(rng, n, plates=True):
    """Wide random inputs (as in ``test_kernel_compiled``): sizes 10 um-10 mm and ratios
    1e-3-1e3, plates in either slot, dry sides, viscosities 1e-4-1e7 Pa s, voidage on both
    sides of Gidaspow's switch, angles -180-540 deg, speeds 1e-5-100 m/s."""
    d_i = _lu(rng, 10e-6, 10e-3, n)
    d_j = d_i * _lu(rng, 1e-3, 1e3, n)
    if plates:
        d_j[: n // 6] = np.inf
        d_i[n // 6: n // 3] = np.inf
        d_j[n // 6: n // 3] = _lu(rng, 10e-6, 10e-3, n // 3 - n // 6)
    rho_i = np.where(np.isinf(d_i), np.inf, rng.uniform(500.0, 10000.0, n))
    rho_j = np.where(np.isinf(d_j), np.inf, rng.uniform(500.0, 10000.0, n))
    h0_i = np.where(rng.random(n) < 0.2, 0.0, _lu(rng, 1e-8, 5e-4, n))
    p_i = at.Particle(d=d_i, rho=rho_i, h0=h0_i, ha=_lu(rng, 1e-9, 1e-5, n))
    p_j = at.Particle(d=d_j, rho=rho_j, h0=_lu(rng, 1e-8, 5e-4, n), ha=_lu(rng, 1e-9, 1e-5, n))
    liq = at.Liquid(mu=_lu(rng, 1e-4, 1e7, n), gamma=_lu(rng, 1e-3, 1.0, n),
                    rho=rng.uniform(500, 3000, n), theta_deg=rng.uniform(0.0, 85.0, n))
    gas = at.Gas(mu=rng.uniform(15e-6, 50e-6, n), rho=rng.uniform(0.2, 1.5, n))
    bed = at.Bed(eps=rng.uniform(0.3, 0.99, n))
    e = rng.uniform(0.0, 1.0, n)
    e[:10] = 0.0
    beta = rng.uniform(-180.0, 540.0, n)
    u0 = _lu(rng, 1e-5, 100.0, n)
    u0[np.isinf(d_i)] = _lu(rng, 1e-5, 100.0, int(np.isinf(d_i).sum()))
    return p_i, p_j, liq, gas, bed, beta, e, u0


def _plate_speeds(p_i, p_j, u0):
    """Head-on speeds with a plate in slot i: the mover is j at u0, the plate at 0."""
    plate_i = np.isinf(p_i.d)
    return np.where(plate_i, 0.0, u0), np.where(plate_i, u0, np.where(np.isinf(p_j.d), 0.0,
                                                                          u0))


def _near_threshold(checks):
    """The paper's two cases around u0* at beta 45-270 (one particle stops first), and a
    particle on a plate around its u0*."""
    out = []
    plate = at.Particle.plate(h0=100e-6, ha=0.5e-6)
    glass = at.Particle(d=1.74e-3, rho=2500.0, h0=0.0, ha=1e-6)
    _, water, _ = checks.case_water()
    specs = [(p, p, liq, gas, b) for (p, liq, gas) in (checks.case_water(), checks.case_slag())
             for b in (45.0, 90.0, 225.0, 270.0)]
    specs.append((plate, glass, water, AIR, 90.0))
    factors = np.geomspace(0.7, 1.5, 41)
    for p_i, p_j, liq, gas, beta in specs:
        u_star = float(at.critical_impact_speed(p_i, p_j, liquid=liq, gas=gas, beta_deg=beta))
        out.append((p_i, p_j, liq, gas, at.Bed(), beta, 0.9, u_star * factors))
    return out


def _reference(p_i, p_j, liq, gas, bed, beta, e, u0, u0_j, mode, body, slip):
    u_i, u_j, w = _lab_speeds(p_i, p_j, u0, u0_j)
    state = prepare_pair(p_i, p_j, liq, gas, bed, beta, e, body, slip, u_i=u_i, u_j=u_j)
    e_w, stage, path, _, shape = _evaluate(state, w, mode, False)
    return e_w, stage, path, np.broadcast_to(w, shape), state


def _check(p_i, p_j, liq, gas, bed, beta, e, u0, u0_j=None, mode="paper", body=True,
           slip="emulsion"):
    e_ref, st_ref, pa_ref, w_ref, state = _reference(p_i, p_j, liq, gas, bed, beta, e, u0,
                                                     u0_j, mode, body, slip)
    r = at.collide(p_i, p_j, liquid=liq, gas=gas, bed=bed, u0=u0, u0_j=u0_j, beta_deg=beta,
                   e=e, mode=mode, body_forces=body, drag_slip=slip, details=False)
    np.testing.assert_array_equal(r.stage, st_ref)
    np.testing.assert_array_equal(r.path, pa_ref)
    np.testing.assert_array_equal(r.agglomerated, e_ref == 0.0)
    np.testing.assert_array_equal(r.w, w_ref)
    np.testing.assert_allclose(r.e_w, e_ref, rtol=1e-12, atol=1e-10)

    # The compiled preparation against the numpy one.
    shape, ins, steps, n = _fused_inputs(p_i, p_j, liq, gas, bed, beta, e, u0, u0_j)
    k = fused.prepare_flat(ins, steps, n, body, slip == "particle")
    for q, name in enumerate(ROWS):
        if name == "w":
            ref = w_ref
        else:
            ref = getattr(state, name)
        ref = np.broadcast_to(ref, shape).ravel()
        if name in EXACT:
            np.testing.assert_array_equal(k[q], ref, err_msg=name)
        elif name in ("fn_i", "fn_j"):
            # The net body force is weight less buoyancy less drag: where the drag nearly
            # balances the rest (voidage above Gidaspow's switch, angle 180 deg) it cancels,
            # and the powers' last-place differences (re**0.687, eps**-1.65) are relative
            # to the terms, not to their small sum. Bound: 1e-12 of |fn| plus the weight.
            m = np.broadcast_to(state.m_i if name == "fn_i" else state.m_j, shape).ravel()
            scale = np.abs(ref) + np.where(np.isfinite(m), m * GRAVITY, 0.0)
            err = np.abs(k[q] - ref)
            assert np.all(err <= 1e-12 * scale), (name, float(np.max(err / scale)))
        else:
            np.testing.assert_allclose(k[q], ref, rtol=1e-12, atol=0.0, err_msg=name)
    # Same prepared numbers, same kernel: bitwise, serial and parallel alike.
    runner = run_paper if mode == "paper" else run_relative
    e_k, st_k, pa_k, _ = runner(k[:13])
    tier = fused.TIER_PAPER if mode == "paper" else fused.TIER_RELATIVE
    for n_serial in (0, n + 1):
        old = fused.SERIAL_BELOW
        fused.SERIAL_BELOW = n_serial
        try:
            e_f, st_f, pa_f, w_f, _ = fused.fused_batch(ins, steps, n, tier, body=body,
                                                        particle_slip=slip == "particle")
        finally:
            fused.SERIAL_BELOW = old
        np.testing.assert_array_equal(e_f, e_k)
        np.testing.assert_array_equal(st_f, st_k)
        np.testing.assert_array_equal(pa_f, pa_k)
        np.testing.assert_array_equal(w_f, k[9])
    return r


@pytest.mark.parametrize("mode", ["paper", "relative"])
@pytest.mark.parametrize("slip", ["emulsion", "particle"])
@pytest.mark.parametrize("body", [True, False])
def test_random_scenes(mode, slip, body):
    rng = np.random.default_rng(20240611)
    p_i, p_j, liq, gas, bed, beta, e, u0 = _random_scene(rng, 3000)
    u_i, u_j = _plate_speeds(p_i, p_j, u0)
    r = _check(p_i, p_j, liq, gas, bed, beta, e, u_i, u_j, mode=mode, body=body, slip=slip)
    assert 0.05 < r.agglomerated.mean() < 0.95  # both outcomes are exercised
    # Head-on (u0_j None) without plates in slot i, and a given emulsion velocity.
    p_i, p_j, liq, gas, bed, beta, e, u0 = _random_scene(rng, 2000, plates=False)
    _check(p_i, p_j, liq, gas, bed, beta, e, u0, mode=mode, body=body, slip=slip)
    bed_u = at.Bed(eps=bed.eps, U=rng.uniform(0.0, 2.0, 2000))
    _check(p_i, p_j, liq, gas, bed_u, beta, e, u0, mode=mode, body=body, slip=slip)


@pytest.mark.parametrize("mode", ["paper", "relative"])
def test_near_threshold_special_paths(checks, mode):
    special = 0
    for p_i, p_j, liq, gas, bed, beta, e, u0 in _near_threshold(checks):
        r = _check(p_i, p_j, liq, gas, bed, beta, e, u0, mode=mode)
        special += int(np.count_nonzero(r.path & 0b1111))
        assert 0 < r.agglomerated.sum() < r.agglomerated.size
    if mode == "paper":
        assert special > 20  # the one-particle-stops paths are exercised


def test_broadcast_shapes_and_scalars():
    """2-D broadcasting, scalars everywhere, and a batch of one."""
    water = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    p = at.Particle(d=1e-3, rho=2650.0, h0=5e-6, ha=0.1e-6)
    pj = at.Particle(d=np.geomspace(3e-4, 3e-3, 7)[:, None], rho=2650.0, h0=5e-6, ha=0.1e-6)
    u0 = np.geomspace(0.01, 1.0, 11)[None, :]
    r = _check(p, pj, water, AIR, at.Bed(), 60.0, 0.9, u0)
    assert r.e_w.shape == (7, 11)
    r = _check(p, p, water, AIR, at.Bed(), 60.0, 0.9, 0.3)
    assert r.e_w.shape == ()


@pytest.mark.parametrize("body", [True, False])
@pytest.mark.parametrize("slip", [False, True])
def test_repeated_angles(body, slip):
    """The loops reuse the previous collision's cosine and sine where its angle repeats
    (``fused._angles``): with angles in runs of random lengths, changing within and across
    the parallel loops' blocks, the loops' numbers are bitwise those of ``prepare_one``
    called on each collision alone, and so are the kernels' outcomes."""
    rng = np.random.default_rng(7)
    n = 2 * fused.BLOCK + 37
    p_i, p_j, liq, gas, bed, beta, e, u0 = _random_scene(rng, n, plates=False)

    def runs(values):
        return np.resize(np.repeat(values, rng.integers(1, 80, values.size)), n)

    liq = at.Liquid(mu=liq.mu, gamma=liq.gamma, rho=liq.rho,
                    theta_deg=runs(rng.choice([0.0, 10.0, 40.0, 85.0], 200)))
    beta = runs(rng.choice([0.0, 45.0, 90.0, 180.0, 300.0, -90.0], 200))
    assert (np.diff(liq.theta_deg) != 0).sum() > 40 and (np.diff(beta) != 0).sum() > 40
    _, ins, steps, n = _fused_inputs(p_i, p_j, liq, gas, bed, beta, e, u0, None)
    raw = [[a[q * s] for a, s in zip(ins, steps, strict=True)] for q in range(n)]
    alone = np.array([fused.prepare_one(RawPair(*x[:18]), x[18], x[19], body, slip)
                      for x in raw]).T
    m_i, m_j, r, H0, Ha, cos_t, theta, fn_i, fn_j, w, wpu = alone
    alone = np.array([m_i, m_j, r, H0, Ha, np.broadcast_to(ins[8], (n,)),  # prepare_flat's
                      np.broadcast_to(ins[9], (n,)), cos_t, theta, w, fn_i, fn_j,  # rows
                      np.broadcast_to(ins[17], (n,)), wpu])
    idx = rng.permutation(n)[: n // 2]
    for n_serial in (0, n + 1):
        old = fused.SERIAL_BELOW
        fused.SERIAL_BELOW = n_serial
        try:
            np.testing.assert_array_equal(fused.prepare_flat(ins, steps, n, body, slip), alone)
            for tier, runner in ((fused.TIER_PAPER, run_paper),
                                 (fused.TIER_RELATIVE, run_relative)):
                e_f, st_f, pa_f, _, _ = fused.fused_batch(ins, steps, n, tier, body=body,
                                                          particle_slip=slip)
                e_k, st_k, pa_k, _ = runner(alone[:13])
                np.testing.assert_array_equal(e_f, e_k)
                np.testing.assert_array_equal(st_f, st_k)
                np.testing.assert_array_equal(pa_f, pa_k)
        finally:
            fused.SERIAL_BELOW = old
    np.testing.assert_array_equal(fused.prepare_at(ins, steps, idx, body, slip), alone[:, idx])


@settings(max_examples=60, deadline=None)
@given(
    d_i=st.floats(1e-5, 1e-2), ratio=st.floats(1e-2, 1e2), rho=st.floats(500.0, 8000.0),
    h0=st.floats(1e-8, 1e-4), ha=st.floats(1e-9, 1e-6), mu=st.floats(1e-4, 1e4),
    gamma=st.floats(1e-3, 1.0), eps=st.floats(0.35, 0.95), beta=st.floats(0.0, 360.0),
    e=st.floats(0.0, 1.0), mode=st.sampled_from(["paper", "relative"]),
)
def test_hypothesis_scenes(d_i, ratio, rho, h0, ha, mu, gamma, eps, beta, e, mode):
    p_i = at.Particle(d=d_i, rho=rho, h0=h0, ha=ha)
    p_j = at.Particle(d=d_i * ratio, rho=rho, h0=h0, ha=ha)
    liq = at.Liquid(mu=mu, gamma=gamma, rho=1000.0, theta_deg=20.0)
    _check(p_i, p_j, liq, HOT, at.Bed(eps=eps), beta, e, np.geomspace(1e-4, 30.0, 64),
           mode=mode)


@pytest.mark.parametrize("tol", [None, 1e-3])
def test_auto_fused_equals_auto_batch_bitwise(checks, tol):
    """Mode "auto" without details: the fused choice (no details rows) then "ode" on the
    chosen collisions equals ``auto_batch`` on the compiled preparation, bitwise; both tiers
    are used."""
    from agglomtool.collision.auto import DEFAULT_TOL, TIER_ODE, auto_batch

    rng = np.random.default_rng(99)
    p_i, p_j, liq, gas, bed, beta, e, u0 = _random_scene(rng, 1500)
    u_i, u_j = _plate_speeds(p_i, p_j, u0)
    cases = [(p_i, p_j, liq, gas, bed, beta, e, u_i, u_j)]
    cases += [(a, b, c, d, f, g, h, u, None) for a, b, c, d, f, g, h, u in _near_threshold(checks)]
    used = set()
    for p_i, p_j, liq, gas, bed, beta, e, u0, u0_j in cases:
        r = at.collide(p_i, p_j, liquid=liq, gas=gas, bed=bed, u0=u0, u0_j=u0_j, beta_deg=beta,
                       e=e, mode="auto", details=False, tol=tol)
        shape, ins, steps, n = _fused_inputs(p_i, p_j, liq, gas, bed, beta, e, u0, u0_j)
        k = fused.prepare_flat(ins, steps, n, True, False)
        e_w, stage, path, _, tier, _ = auto_batch(k[:13], tol=DEFAULT_TOL if tol is None
                                                  else tol)
        np.testing.assert_array_equal(r.e_w.ravel(), e_w)
        np.testing.assert_array_equal(r.stage.ravel(), stage)
        np.testing.assert_array_equal(r.path.ravel(), path)
        np.testing.assert_array_equal(r.w.ravel(), k[9])
        used |= set(np.unique(tier).tolist())
    assert TIER_ODE in used and len(used) == 2


def test_lean_indicator_equals_the_indicator_bitwise(checks):
    """``closed_form_indicator_lean`` (one pass, no details row) against
    ``closed_form_indicator`` (the closed forms with details, then the indicator)."""
    from agglomtool.collision.auto import closed_form_indicator, closed_form_indicator_lean
    from agglomtool.collision.outcome import DETAIL_NAMES

    rng = np.random.default_rng(5)
    p_i, p_j, liq, gas, bed, beta, e, u0 = _random_scene(rng, 3000)
    u_i, u_j = _plate_speeds(p_i, p_j, u0)
    _, ins, steps, n = _fused_inputs(p_i, p_j, liq, gas, bed, beta, e, u_i, u_j)
    k = fused.prepare_flat(ins, steps, n, True, False)
    det = np.empty(len(DETAIL_NAMES))
    outcomes = set()
    for q in range(n):
        x = [float(k[j][q]) for j in range(13)]
        pair, w = Pair(*x[:9], *x[10:]), x[9]  # the tier order has w after theta
        a = closed_form_indicator(pair, w, det)
        b = closed_form_indicator_lean(pair, w)
        assert a == b, (q, a, b)
        outcomes.add(a[1])
    assert len(outcomes) >= 5  # rebounds and sticks at several stages
