"""The propensity of the tiers without a compiled sticking set, against the node quadrature.

Mode "stokes" takes ``P = F(u0*)`` (nothing above a rebounding ``u0*`` sticks by Ennis'
criterion); modes "ode", "ode_selfconsistent", "auto", "paper" with body forces off the
axis and every mode with the particle's own slip take the bracketing of
:mod:`agglomtool.collision.sticking_numeric`. The reference is the 4096-node quadrature
(tests/test_sticking_exact.py's bound: each window end above ``u0*`` may move it by
``(1 - F(u0*)) / (2 N)``), and the sets found are checked against a dense scan of the
tier's own kernel (no window missed, none invented).

The hard set: the random pairs of tests/test_sticking_exact.py that stick again above
``u0*`` in mode "relative" (three of its first hundred, every one of which sticks again in
"ode", "auto" and "paper" too), the Table 2 water case against its Table 3 partners at
angles off the axis, and coatings barely thicker than the asperities; every speed family.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_sticking_exact import AIR, N_REF, Pairs, _random_pairs, _water

import agglomtool as at
from agglomtool.bed.speeds import SpeedModel, bracket_elements, sticking_probability
from agglomtool.collision.sticking_numeric import U_RTOL, stick_indicator

#: (mode, particle slip): the tiers and flags that take the bracketing.
NUMERIC = [("ode", False), ("ode_selfconsistent", False), ("auto", False), ("paper", False),
           ("relative", True), ("paper", True)]
#: Where mode "ode_selfconsistent"'s verdict flickers above its u0* (relative to it):
#: test_ode_selfconsistent_flickers_above_u_star.
FLICKER = 3e-4
#: The random pairs (tests/test_sticking_exact.py's draw) with windows above u0*.
WITH_WINDOWS = (10, 61, 92)


def _hard_set(mode, slip):
    water = _water()
    p, liquid, gas = water
    out = []
    rand = _random_pairs(11, 100, angles=7)
    for k in WITH_WINDOWS:
        kw = rand[k].kw
        out.append(Pairs(kw["p_i"], kw["p_j"], kw["liquid"], AIR, kw["beta_deg"], kw["e"],
                         mode=mode, slip=slip))
    beta = np.array([30.0, 90.0, 200.0, 315.0])
    for partner in (at.Particle(d=p.d, rho=4330.0, h0=p.h0, ha=p.ha),
                    at.Particle(d=600e-6, rho=p.rho, h0=p.h0, ha=p.ha)):
        out.append(Pairs(p, partner, liquid, gas, beta, 0.9, mode=mode, slip=slip))
    for x in (1e-9, 1e-3):  # knife edges: coatings barely thicker than the asperities
        q = at.Particle(d=1000e-6, rho=2650.0, h0=0.1e-6 * (1 + x), ha=0.1e-6)
        r = at.Particle(d=300e-6, rho=4330.0, h0=0.1e-6 * (1 + x), ha=0.1e-6)
        out.append(Pairs(q, r, liquid, gas, beta, 0.9, mode=mode, slip=slip))
    return out


def _laws(u_star, rng):
    finite = np.where(np.isfinite(u_star) & (u_star > 0.0), u_star, 1.0)
    med = finite * 10 ** rng.uniform(-0.5, 2.5, u_star.shape)
    return [
        SpeedModel("lognormal", u0=med, sigma_ln=rng.uniform(0.05, 1.5, u_star.shape)),
        SpeedModel("maxwellian", granular_temperature=med**2 / math.log(2.0)),
        SpeedModel("lognormal", u0=finite, sigma_ln=1e-3),  # concentrated at u0*
        SpeedModel("fixed", u0=finite * 10 ** rng.uniform(-0.3, 3.0, u_star.shape)),
    ]


def _reference(pairs, law, n=N_REF):
    """The node quadrature of :func:`sticking_probability` without ``pair`` (its formula,
    the nodes' verdicts summed as counts) with every node in one call of the kernel
    instead of one call per node (4096 calls of a non-fused tier cost minutes in Python);
    bitwise the same (test_reference_is_the_quadrature)."""
    f_star = np.broadcast_to(law.cdf(pairs.u_star), pairs.shape)
    rest = 1.0 - f_star
    open_ = rest > 1e-12
    n = 1 if law.family == "fixed" else n
    q = f_star[..., None] + rest[..., None] * ((np.arange(n) + 0.5) / n)

    def col(a):
        return None if a is None else np.asarray(a)[..., None]

    nodes = SpeedModel(law.family, u0=col(law.u0), sigma_ln=col(law.sigma_ln),
                       granular_temperature=col(law.theta))
    u = np.broadcast_to(nodes.quantile(np.where(open_[..., None], q, 0.5)), q.shape)
    positive = u > 0.0
    kw = dict(pairs.kw)
    for name in ("beta_deg", "e"):
        kw[name] = np.asarray(kw[name], dtype=float)[..., None]
    stuck = np.broadcast_to(at.collide(u0=np.where(positive, u, 1.0), details=False,
                                       **kw).agglomerated, q.shape) | ~positive
    return np.where(open_, f_star + rest * np.count_nonzero(stuck, axis=-1) / n, 1.0)


def _sets(pairs, law, nodes=16):
    """The bracketed sets of the elements with probability above u0* (as the propensity
    finds them with ``nodes``): ``(within, cand, stuck, cross, ok)``."""
    within = (1.0 - np.broadcast_to(law.cdf(pairs.u_star), pairs.shape)) > 1e-12
    _, cand, stuck, cross, ok = bracket_elements(law, pairs.u_star, pairs.pair(pairs.u_star),
                                                 pairs.shape, within, nodes)
    return within, cand, stuck, cross, ok


def _check(pairs, laws, band=0.0, nodes=16):
    """Every law against the 4096-node reference within its bound (plus the probability
    between u0* and ``u0* (1 + band)``), nothing left to the quadrature; returns the
    number of elements with a window above u0*."""
    windows = 0
    for law in laws:
        report = {}
        got = sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair,
                                   report=report, nodes=nodes)
        ref = _reference(pairs, law)
        f_star = np.broadcast_to(law.cdf(pairs.u_star), got.shape)
        ends = np.zeros(got.shape)
        if law.family != "fixed":
            within, _, stuck, _, ok = _sets(pairs, law, nodes)
            assert ok.all()
            ends[within] = np.count_nonzero(stuck[:, 1:] != stuck[:, :-1], axis=1)
            windows += int(np.count_nonzero(ends))
        n_ref = 1 if law.family == "fixed" else N_REF
        bound = 1e-9 + ends * (1.0 - f_star) / (2.0 * n_ref)
        if band:
            bound = bound + law.cdf(pairs.u_star * (1.0 + band)) - f_star
        err = np.abs(got - ref)
        worst = np.unravel_index(np.argmax(err - bound), got.shape)
        assert np.all(err <= bound), (law.family, worst, got[worst], ref[worst], ends[worst])
        assert np.all((got >= 0.0) & (got <= 1.0))
        assert report["quadrature"] == 0, report
        assert report["exact"] + report["bracketed"] == got.size, report
    return windows


def _scan(pairs, law, points=300):
    """The tier's kernel on a geometric grid from u0* to the top candidate: it sticks
    exactly where the bracketed sets say (beyond 1e-8 of a crossing)."""
    within, cand, stuck, cross, ok = _sets(pairs, law)
    if not within.any():
        return 0
    coll = np.broadcast_to(np.arange(int(np.prod(pairs.shape))).reshape(pairs.shape),
                           pairs.shape)[within]
    lo, hi = cand[:, 0], cand[:, -1]
    frac = np.linspace(0.0, 1.0, points)[None, 1:-1]
    u = np.exp(np.log(lo)[:, None] * (1.0 - frac) + np.log(hi)[:, None] * frac)
    fused = pairs.pair(pairs.u_star)
    s, known = stick_indicator(fused[0], fused[1], fused[3], fused[4], fused[5])(
        np.repeat(coll, u.shape[1]), u.ravel())
    s, known = s.reshape(u.shape), known.reshape(u.shape)
    assert known.all()
    # the piecewise indicator the integral takes
    said = np.zeros(u.shape, dtype=bool)
    near = np.zeros(u.shape, dtype=bool)
    for j in range(cand.shape[1] - 1):
        a, x, b = cand[:, j:j + 1], cross[:, j:j + 1], cand[:, j + 1:j + 2]
        said |= ((u >= a) & (u < x) & stuck[:, j:j + 1]) | ((u >= x) & (u < b)
                                                             & stuck[:, j + 1:j + 2])
        near |= np.abs(u / x - 1.0) < 1e-8
    said |= (u >= cand[:, -1:]) & stuck[:, -1:]
    bad = (s != said) & ~near
    assert not bad.any(), (np.argwhere(bad)[:5], u[bad][:5])
    return int(np.count_nonzero(np.any(stuck[:, 1:] != stuck[:, :-1], axis=1)))


@pytest.mark.parametrize("mode", ["ode", "paper"])
def test_reference_is_the_quadrature(mode):
    """The one-call reference is bitwise :func:`sticking_probability`'s quadrature."""
    rng = np.random.default_rng(1)
    pairs = _hard_set(mode, False)[0]
    for law in _laws(pairs.u_star, rng):
        np.testing.assert_array_equal(
            _reference(pairs, law, 64),
            sticking_probability(law, pairs.u_star, pairs.collide, nodes=64))


@pytest.mark.parametrize("mode, slip", [
    pytest.param(*x, marks=pytest.mark.xfail(
        strict=True, reason="ode_selfconsistent's verdict flickers just above u0* "
        "(test_ode_selfconsistent_flickers_above_u_star)"))
    if x[0] == "ode_selfconsistent" else x for x in NUMERIC])
def test_numeric_tiers_against_the_reference(mode, slip):
    """Each numeric tier on the hard set: every law within the bound of the 4096-node
    reference, nothing left to the quadrature, and the sets against a dense kernel scan.
    The 16-node quadrature these elements took before misses the reference by up to
    1/32 of the probability above u0* at a window's end (the test then fails)."""
    rng = np.random.default_rng(26)
    windows = 0
    for pairs in _hard_set(mode, slip):
        laws = _laws(pairs.u_star, rng)
        windows += _check(pairs, laws)
        _scan(pairs, laws[0])
    if mode != "ode_selfconsistent":  # its rupture leaves no window in this set
        assert windows >= 10


@pytest.mark.parametrize("mode, slip", [("ode", False), ("auto", False), ("paper", False),
                                        ("relative", True), ("paper", True)])
def test_no_window_missed_on_a_random_set(mode, slip):
    """A seeded random set (other draws than the hard set's): the bracketed sets against a
    dense scan of the tier's kernel."""
    rng = np.random.default_rng(3)
    windows = 0
    for k, base in enumerate(_random_pairs(12, 60, angles=5)):
        kw = base.kw
        pairs = Pairs(kw["p_i"], kw["p_j"], kw["liquid"], AIR, kw["beta_deg"], kw["e"],
                      mode=mode, slip=slip)
        windows += _scan(pairs, _laws(pairs.u_star, rng)[k % 2], points=120)
    assert windows >= 2  # the set holds windows above u0* (2 to 16 per tier)


def test_bisection_tolerance_is_the_stated_one():
    """Each crossing found lies within U_RTOL of a change of the tier's verdict: the
    kernel's verdicts just below and just above it differ."""
    pairs = _hard_set("ode", False)[0]
    law = SpeedModel("lognormal", u0=30.0 * pairs.u_star, sigma_ln=1.5)
    within, cand, stuck, cross, ok = _sets(pairs, law)
    rows, cols = np.nonzero(stuck[:, 1:] != stuck[:, :-1])
    assert rows.size >= 2
    fused = pairs.pair(pairs.u_star)
    coll = np.flatnonzero(within.ravel())[rows]
    x = cross[rows, cols]
    sticks = stick_indicator(fused[0], fused[1], fused[3], fused[4], fused[5])
    below, _ = sticks(coll, x * (1.0 - U_RTOL))
    above, _ = sticks(coll, x * (1.0 + U_RTOL))
    assert np.all(below != above)


def test_stokes_takes_the_cdf_at_u_star():
    """Mode "stokes": ``u0*`` is the tier's exact threshold (Ennis: ``St_v = (1 + 1/e)
    ln(H0 / Ha)``, to the search's rtol above it), nothing above it sticks on a dense scan,
    and the propensity is ``F(u0*)`` with no kernel evaluation, every family, within 1e-9
    of the 4096-node reference."""
    from agglomtool.collision.bridge import viscous_constant
    from agglomtool.collision.fused import prepare_flat
    from agglomtool.collision.physics import reduced_mass

    p, liquid, gas = _water()
    rng = np.random.default_rng(4)
    for partner in (p, at.Particle(d=600e-6, rho=4330.0, h0=p.h0, ha=p.ha),
                    at.Particle.plate(h0=p.h0, ha=p.ha)):
        pairs = Pairs(p, partner, liquid, gas, np.array([0.0, 90.0, 200.0]),
                      np.array([0.3, 0.9, 1.0]), mode="stokes")
        fused = pairs.pair(pairs.u_star)
        k = prepare_flat(fused[0], fused[1], 3, False, False)
        m_r = np.array([reduced_mass(a, b)[0] for a, b in zip(k[0], k[1], strict=True)])
        c = np.array([viscous_constant(mu, r) for mu, r in zip(k[5], k[2], strict=True)])
        e = k[12]
        w_star = (1.0 + 1.0 / e) * np.log(k[3] / k[4]) * c / m_r
        u_exact = w_star / k[13]
        assert np.all(pairs.u_star >= u_exact * (1.0 - 1e-12))
        assert np.all(pairs.u_star <= u_exact * (1.0 + 2e-6))
        u = pairs.u_star[:, None] * np.geomspace(1.0, 1e6, 400)[None, :]
        assert not np.any(at.collide(p_i=pairs.kw["p_i"], p_j=pairs.kw["p_j"], **{
            **{x: pairs.kw[x] for x in ("liquid", "gas", "bed", "mode")},
            "beta_deg": pairs.kw["beta_deg"][:, None], "e": e[:, None]}, u0=u,
            details=False).agglomerated)

        def no_kernel(u0):
            raise AssertionError("the kernel was called")

        for law in _laws(pairs.u_star, rng):
            report = {}
            got = sticking_probability(law, pairs.u_star, no_kernel, pair=pairs.pair,
                                       report=report)
            ref = _reference(pairs, law)
            f_star = law.cdf(pairs.u_star)
            np.testing.assert_array_equal(got, np.where(1.0 - f_star > 1e-12, f_star, 1.0))
            np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-9)
            assert report == {"exact": 3, "bracketed": 0, "quadrature": 0}


def test_ode_selfconsistent_flickers_above_u_star():
    """Mode "ode_selfconsistent"'s verdict is no union of a few intervals just above its
    ``u0*``: on the Table 2 water case against ilmenite it changes at more than ten speeds
    within ``FLICKER`` of ``u0*`` (its integration's resolution; mode "ode" does not). A law
    concentrated there (``sigma_ln = 1e-3``) puts percents of probability on that flicker,
    which no bracketing from a few candidates resolves (:mod:`.sticking_numeric`: what is
    not proven); the 4096-node reference samples it. Measured here, and the comparison
    marked as the known failure below."""
    pairs = _hard_set("ode_selfconsistent", False)[3]
    fused = pairs.pair(pairs.u_star)
    sticks = stick_indicator(fused[0], fused[1], fused[3], fused[4], fused[5])
    x = np.linspace(0.0, 3.0 * FLICKER, 601)
    stuck, known = sticks(np.zeros(x.size, dtype=np.int64), pairs.u_star[0] * (1.0 + x))
    assert known.all()
    changes = np.flatnonzero(stuck[1:] != stuck[:-1])
    assert changes.size > 10
    assert x[changes[-1] + 1] <= FLICKER  # and none beyond the band


def test_ode_selfconsistent_within_its_flicker_band():
    """Mode "ode_selfconsistent" on the hard set: within the bound plus the law's
    probability in the band where its verdict flickers (``FLICKER`` above ``u0*``, the
    bound the bed page states for this tier), nothing left to the quadrature."""
    rng = np.random.default_rng(26)
    for pairs in _hard_set("ode_selfconsistent", False):
        _check(pairs, _laws(pairs.u_star, rng), band=FLICKER)


def test_the_nodes_are_candidates():
    """``nodes`` reaches the bracketing: with the reference's 4096 nodes among the
    candidates, mode "ode_selfconsistent"'s flicker is seen node by node and the law
    concentrated on it agrees with the reference within the bound (it does not with 16)."""
    pairs = _hard_set("ode_selfconsistent", False)[3]
    law = [SpeedModel("lognormal", u0=pairs.u_star, sigma_ln=1e-3)]
    _check(pairs, law, nodes=N_REF)
    with pytest.raises(AssertionError):
        _check(pairs, law, nodes=16)


def _numpy_method(monkeypatch, law, pairs, **kw):
    """The propensity by the numpy batches of the method (:mod:`.sticking_numeric`), the
    compiled pass switched off: the reference the compiled pass is held to."""
    import agglomtool.collision.sticking_bracketed as compiled

    with monkeypatch.context() as m:
        m.setattr(compiled, "kind_of", lambda tier: None)
        return sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair, **kw)


@pytest.mark.parametrize("mode, slip", [("auto", False), ("paper", False), ("relative", True),
                                        ("paper", True), ("ode", False),
                                        ("ode_selfconsistent", False)])
def test_compiled_pass_is_the_numpy_method(mode, slip, monkeypatch):
    """The compiled pass of :mod:`agglomtool.collision.sticking_bracketed` against the
    numpy batches of the same method (:func:`bracket_elements` and its integral) on the
    hard set, every law: the same elements proven and the same propensity within 1e-15
    (the compiled sum runs in candidate order, numpy's pairwise; the lognormal CDF is
    ``erfc``'s form there, scipy's ``ndtr`` here: a few units in the last place). Mode
    "ode_selfconsistent" within its stated bound instead: the law's probability in the
    band ``FLICKER`` above ``u0*`` where its verdict flickers, since a node a unit in the
    last place apart (the compiled ``log1p`` against numpy's) can let a bisection settle on
    another of the band's crossings (measured: 1.2e-9 on one of
    ``benchmarks/bench_bracketing.py``'s maps, 0 on this set)."""

    rng = np.random.default_rng(7)
    for pairs in _hard_set(mode, slip):
        for law in _laws(pairs.u_star, rng):
            rep_c, rep_n = {}, {}
            got = sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair,
                                       report=rep_c)
            ref = _numpy_method(monkeypatch, law, pairs, report=rep_n)
            assert rep_c == rep_n
            band = 0.0
            if mode == "ode_selfconsistent":
                band = law.cdf(pairs.u_star * (1.0 + FLICKER)) - law.cdf(pairs.u_star)
            assert np.all(np.abs(got - ref) <= 1e-15 + band)


def _alternating(mode, slip):
    """Two of the random pairs in turn along one axis, 8 collisions: one (``u0*`` near
    9.6e-8 m/s) that rebounds at every speed above it, and one (7.5e-7 m/s) that sticks
    again from about 300 times its ``u0*``, a speed where the first is proven to rebound
    (shape ``(8, 1)``). What is proven for one collision must not carry over to the
    next."""
    rand = _random_pairs(11, 100, angles=7)
    a, b = rand[WITH_WINDOWS[1]].kw, rand[WITH_WINDOWS[2]].kw

    def both(get):
        return np.array([get(a), get(b)] * 4, dtype=float).reshape(8, 1)

    def particle(name):
        return at.Particle(*(both(lambda kw, f=f: getattr(kw[name], f))
                             for f in ("d", "rho", "h0", "ha")))

    liquid = at.Liquid(*(both(lambda kw, f=f: getattr(kw["liquid"], f))
                         for f in ("mu", "gamma", "rho", "theta_deg")))
    return Pairs(particle("p_i"), particle("p_j"), liquid, AIR, 0.0,
                 both(lambda kw: kw["e"]), mode=mode, slip=slip)


@pytest.mark.parametrize("mode, slip", [("paper", False), ("relative", True)])
def test_proof_shared_by_a_collisions_elements(mode, slip, monkeypatch):
    """Modes "paper" and "relative", where a proof of rebound spares evaluations: each
    collision of the hard set (its angles along the first axis) has a run of 12 elements
    whose laws (Maxwellian, lognormal) reach tops above and below one another in a shuffled
    order, so that the interval proven for the collision is taken as it is, extended, and
    made anew. The propensity is bitwise the same as with each element alone (its own
    run, its own proof), and within 1e-15 of the numpy batches, which evaluate every
    candidate: the proof decides which candidates are evaluated, never the result."""

    rng = np.random.default_rng(23)
    runs = 0
    for base in _hard_set(mode, slip) + [_alternating(mode, slip)]:
        k = base.kw
        beta = np.asarray(k["beta_deg"], dtype=float).reshape(-1, 1)
        pairs = Pairs(k["p_i"], k["p_j"], k["liquid"], k["gas"], beta, k["e"], mode=mode,
                      slip=slip, bed=k["bed"])
        us = np.where(np.isfinite(pairs.u_star) & (pairs.u_star > 0.0), pairs.u_star, 1.0)
        scale = us * rng.permutation(np.geomspace(1.02, 300.0, 12))[None, :]
        if base.shape == (8, 1):  # the alternating pairs: one set of speeds for both
            scale = np.broadcast_to(rng.permutation(np.geomspace(1e-6, 3e-2, 12)), (8, 12))
        for law in (SpeedModel("maxwellian", granular_temperature=scale**2 / math.log(2.0)),
                    SpeedModel("lognormal", u0=scale, sigma_ln=rng.uniform(0.05, 1.0, 12))):
            rep = {}
            got = sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair,
                                       report=rep)
            runs += rep["bracketed"] // 12
            for j in range(12):  # each element alone: one element per collision and call
                one = SpeedModel(law.family, u0=None if law.u0 is None else law.u0[:, j:j + 1],
                                 sigma_ln=None if law.sigma_ln is None
                                 else np.broadcast_to(law.sigma_ln, scale.shape)[:, j:j + 1],
                                 granular_temperature=None if law.theta is None
                                 else law.theta[:, j:j + 1])
                alone = sticking_probability(one, pairs.u_star, pairs.collide,
                                             pair=pairs.pair)
                np.testing.assert_array_equal(got[:, j:j + 1], alone)
            ref = _numpy_method(monkeypatch, law, pairs)
            np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-15)
    assert runs >= 20  # runs of one collision reached the compiled pass


#: A random pair (tests/test_sticking_exact.py's draw, seed 11) whose mode "paper" sticks
#: again in a narrow window far above its u0* (about 1400 times it) at the angles 60 and
#: 120 degrees, where mode "relative" has no window: none of the pair's own candidates
#: (u0*, the speeds just above it, mode "relative"'s seeds) lies in it, only the law's
#: nodes can.
UNSEEDED = 39


@pytest.mark.parametrize("slip", [False, True])
def test_a_window_only_the_nodes_reach(slip, monkeypatch):
    """The compiled pass takes ``P = F(u0*)`` without making an element's row where every
    candidate below the proven speed rebounds; a law node that sticks must stop that. On
    :data:`UNSEEDED` (mode "paper"), with laws concentrated on the window a dense scan of
    the kernel finds, the window is seen (P well above F(u0*) where it exists) and the
    pass equals the numpy method within 1e-15 (as
    test_compiled_pass_is_the_numpy_method)."""

    kw = _random_pairs(11, 100, angles=7)[UNSEEDED].kw
    pairs = Pairs(kw["p_i"], kw["p_j"], kw["liquid"], AIR, kw["beta_deg"], kw["e"],
                  mode="paper", slip=slip)
    # the window: the speeds between 2 u0* and 1 m/s at which the kernel sticks (scan)
    beta = np.asarray(kw["beta_deg"])
    at_60 = int(np.flatnonzero(beta == 60.0)[0])
    one = dict(pairs.kw, beta_deg=60.0)
    u = np.geomspace(2.0 * pairs.u_star[at_60], 1.0, 20000)
    stuck = u[np.asarray(at.collide(u0=u, details=False, **one).agglomerated)]
    assert stuck.size
    lo, hi = stuck.min(), stuck.max()
    assert hi / lo < 1.05 and lo > 1000.0 * pairs.u_star[at_60]  # narrow, far above u0*
    _, _, count, _ = Pairs(kw["p_i"], kw["p_j"], kw["liquid"], AIR, kw["beta_deg"], kw["e"],
                           mode="relative").windows()
    assert not count.any()  # no seed from mode "relative"
    middle = math.sqrt(lo * hi)
    laws = [SpeedModel("lognormal", u0=np.full(beta.shape, middle), sigma_ln=0.004),
            SpeedModel("maxwellian", granular_temperature=np.full(beta.shape, middle**2))]
    for law in laws:
        got = sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair)
        ref = _numpy_method(monkeypatch, law, pairs)
        np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-15)
        if law.family == "lognormal":
            seen = got - law.cdf(pairs.u_star)
            assert np.all(seen[np.isin(beta, (60.0, 120.0))] > 0.5), seen


def test_compiled_pass_in_parallel_over_chunks(monkeypatch):
    """The compiled pass's parallel entry and its lognormal chunks, which the hard set's
    few elements per call (under ``SERIAL_BELOW``) never reach: a water-case batch of 104
    elements whose collision changes at every element (the law varies along the first
    axis, the collisions along the last: the pass groups them by collision, and the
    lognormal nodes are asked for by index), the lognormal nodes made by scipy in chunks
    of 66 (``LOGNORMAL_CHUNK`` shrunk from 65536: one parallel launch, then 38 elements on
    the calling thread, the second chunk starting inside a collision's group). Against
    the numpy batches within 1e-15 (as test_compiled_pass_is_the_numpy_method), the same
    elements proven, and bitwise the same on one thread as on two."""
    import numba

    import agglomtool.collision.sticking_bracketed as compiled

    pairs = _hard_set("relative", True)[3]  # Table 2 water against ilmenite, 4 angles
    rng = np.random.default_rng(11)
    med = pairs.u_star[None, :] * 10 ** rng.uniform(-0.3, 2.0, (26, pairs.u_star.size))
    law = SpeedModel("lognormal", u0=med, sigma_ln=rng.uniform(0.1, 1.5, (26, 1)))
    launches = []
    launch = compiled.parallel_launch

    def counted(f, *args):
        launches.append(args[2][0].size)  # the elements of the launch
        return launch(f, *args)

    monkeypatch.setattr(compiled, "LOGNORMAL_CHUNK", 66)
    monkeypatch.setattr(compiled, "parallel_launch", counted)
    before = numba.get_num_threads()
    got, reps = [], []
    try:
        for threads in (1, min(2, numba.config.NUMBA_NUM_THREADS)):
            numba.set_num_threads(threads)
            reps.append({})
            got.append(sticking_probability(law, pairs.u_star, pairs.collide,
                                            pair=pairs.pair, report=reps[-1]))
    finally:
        numba.set_num_threads(before)
    assert launches == [66, 66]
    rep = {}
    ref = _numpy_method(monkeypatch, law, pairs, report=rep)
    assert reps[0] == reps[1] == rep and rep["bracketed"] == got[0].size == 104
    np.testing.assert_array_equal(got[0], got[1])
    np.testing.assert_allclose(got[0], ref, rtol=0.0, atol=1e-15)


def test_compiled_pass_groups_the_elements_of_a_collision(monkeypatch):
    """A map whose speed law varies along an axis before the pairs' gives each collision's
    elements far apart (here 26 Maxwellian laws x the 4 angles of a water pair in mode
    "paper" with gravity: the collision changes at every element). The pass takes them
    grouped by collision (one proof and one set of own candidates per collision, not per
    element) and returns them in the caller's order: bitwise the same as the pass run in
    the caller's order (a run per element), with the same elements proven."""
    import agglomtool.collision.sticking_bracketed as compiled
    from agglomtool.collision.sticking import MAXWELLIAN

    pairs = _hard_set("paper", False)[3]  # Table 2 water against ilmenite, 4 angles
    ins, steps, cshape, tier, body, slip = pairs.pair(pairs.u_star)
    n = int(np.prod(cshape))
    u_star = np.ascontiguousarray(np.broadcast_to(pairs.u_star, cshape), dtype=float).ravel()
    rng = np.random.default_rng(17)
    coll = np.tile(np.arange(n), 26)
    theta = (u_star[coll] * 10 ** rng.uniform(-0.3, 1.0, coll.size)) ** 2 / math.log(2.0)
    assert compiled._grouping(coll) is not None and compiled._grouping(np.sort(coll)) is None

    def run():
        return compiled.bracketed_propensity(ins, steps, compiled.kind_of(tier), u_star, coll,
                                             MAXWELLIAN, theta, np.ones(1), body=body,
                                             particle_slip=slip)

    grouped = run()
    with monkeypatch.context() as m:
        m.setattr(compiled, "_grouping", lambda coll: None)
        as_given = run()
    assert grouped[1].all()
    np.testing.assert_array_equal(grouped[1], as_given[1])
    np.testing.assert_array_equal(grouped[0], as_given[0])
    assert np.ptp(grouped[0]) > 0.1  # the laws differ: the order matters to the result


def test_compiled_pass_leaves_an_element_without_u_star():
    """Called directly with a NaN ``u0*`` (no critical speed), the compiled pass proves
    nothing: P NaN and not ``ok``, every law (the compiled lognormal CDF of NaN is 0, which
    would otherwise give P = 0 as if proven; ``sticking_probability`` closes such elements
    before they reach the pass)."""
    from agglomtool.collision.sticking import FIXED, LOGNORMAL, MAXWELLIAN
    from agglomtool.collision.sticking_bracketed import bracketed_propensity, kind_of

    pairs = _hard_set("paper", False)[3]
    ins, steps, cshape, tier, body, slip = pairs.pair(pairs.u_star)
    n = int(np.prod(cshape))
    u_star = np.full(n, np.nan)
    coll = np.arange(n)
    for family, p1, p2 in ((LOGNORMAL, 0.1, 0.5), (MAXWELLIAN, 0.01, 1.0), (FIXED, 0.1, 1.0)):
        nodes = lambda idx: np.full((idx.size, 18), np.nan)  # noqa: E731
        p, ok = bracketed_propensity(ins, steps, kind_of(tier), u_star, coll, family,
                                     np.array([p1]), np.array([p2]), body=body,
                                     particle_slip=slip, lognormal=nodes)
        assert not ok.any() and np.isnan(p).all(), (family, p, ok)
