"""The propensity from the compiled sticking set against the node quadrature.

:func:`agglomtool.bed.speeds.sticking_probability` with ``pair`` integrates the speed law's
CDF over the set of speeds above ``u0*`` at which the pair sticks again
(:mod:`agglomtool.collision.sticking`). The reference is the same function without
``pair``: the node quadrature with 4096 nodes, whose error is bounded: each end of a
sticking window above ``u0*`` moves it by at most half a node, ``(1 - F(u0*)) / (2 N)``.
So ``|P - P_ref| <= 1e-9 + ends (1 - F(u0*)) / (2 N)``, with ``ends`` the window ends that
lie above ``u0*``; where the pair never sticks again the two agree to 1e-9. The windows
themselves are checked against the kernel on a dense grid of speeds (they must hold every
sticking speed found there, and only those), so that a missed window cannot hide in the
bound.

The hard set: the paper's Table 2 cases with the Table 3 partners (denser, smaller) at
every collision angle (its Figs. 6b, 8, 9: body forces move the threshold), in modes
"relative" and "paper"; pairs that stick again above ``u0*`` (a plate under a very viscous
film, the case the closed-form u0* test found, and a seeded random set of pairs that
holds such windows); knife-edge pairs (coatings barely thicker than the asperities, laws
concentrated at ``u0*``, fixed speeds next to a window's ends); every speed family.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import agglomtool as at
from agglomtool.api import _FUSED, _fused_inputs
from agglomtool.bed.speeds import SpeedModel, sticking_probability
from agglomtool.collision.sticking import sticking_windows

N_REF = 4096
AIR = at.Gas(mu=1.8e-5, rho=1.2)
BED = at.Bed(eps=0.55)


def _water():
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5.00e-6, ha=0.10e-6)
    return p, at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0), \
        at.Gas(mu=18.48e-6, rho=1.168)


def _slag():
    p = at.Particle(d=1000e-6, rho=2650.0, h0=0.15e-6, ha=0.10e-6)
    return p, at.Liquid(mu=10.0, gamma=0.400, rho=2500.0, theta_deg=10.0), \
        at.Gas(mu=45.48e-6, rho=0.324)


class Pairs:
    """A batch of collisions (arrays broadcasting to one shape) with what the propensity
    needs: ``u0*``, ``collide(u0)`` and the compiled set's ``pair``."""

    def __init__(self, p_i, p_j, liquid, gas, beta, e, mode="relative", body=True,
                 slip=False, bed=BED):
        self.kw = dict(p_i=p_i, p_j=p_j, liquid=liquid, gas=gas, bed=bed, beta_deg=beta, e=e,
                       mode=mode, body_forces=body,
                       drag_slip="particle" if slip else "emulsion")
        self.u_star = np.asarray(at.critical_impact_speed(**self.kw), dtype=float)
        self.shape = self.u_star.shape
        self.mode, self.body, self.slip = mode, body, slip

    def collide(self, u0):
        return at.collide(u0=u0, details=False, **self.kw)

    def pair(self, u_star):
        k = self.kw
        shape, ins, steps, _ = _fused_inputs(k["p_i"], k["p_j"], k["liquid"], k["gas"],
                                             k["bed"], k["beta_deg"], k["e"],
                                             np.zeros(np.shape(u_star)), None, check=False)
        return ins, steps, shape, _FUSED.get(self.mode, self.mode), self.body, self.slip

    def windows(self):
        fused = self.pair(self.u_star)
        ins, steps, shape, tier, body, slip = fused
        n = int(np.prod(shape))
        us = np.broadcast_to(self.u_star, shape).ravel()
        return sticking_windows(ins, steps, n, tier, us, body=body, particle_slip=slip)


def _random_pairs(seed, n_pairs, angles=13):
    """A seeded random set of collisions (sizes, plates, densities, coatings, viscosities
    over nine decades, angles): the ranges of tests/test_critical_closed.py's search."""
    rng = np.random.default_rng(seed)
    out = []
    beta = np.linspace(0.0, 360.0, angles)
    for _ in range(n_pairs):
        d_i = 10 ** rng.uniform(-4.3, -2.3)
        plate = rng.random() < 0.3
        d_j = math.inf if plate else 10 ** rng.uniform(-4.3, -2.3)
        ha = 10 ** rng.uniform(-8.0, -5.7)
        h0 = ha * (1.0 + 10 ** rng.uniform(-4.0, 2.7))
        p_i = at.Particle(d=d_i, rho=rng.uniform(900.0, 8000.0), h0=h0, ha=ha)
        p_j = at.Particle(d=d_j, rho=math.inf if plate else rng.uniform(900.0, 8000.0), h0=h0,
                          ha=ha)
        liquid = at.Liquid(mu=10 ** rng.uniform(-3.0, 6.0), gamma=rng.uniform(0.02, 0.6),
                           rho=1500.0, theta_deg=rng.uniform(0.0, 85.0))
        out.append(Pairs(p_i, p_j, liquid, AIR, beta, rng.uniform(0.05, 1.0)))
    return out


def _laws(u_star, rng):
    """One law of each family per element, with probability on both sides of u0* and
    well above it (medians from 0.3 to 300 u0*)."""
    finite = np.where(np.isfinite(u_star) & (u_star > 0.0), u_star, 1.0)
    med = finite * 10 ** rng.uniform(-0.5, 2.5, u_star.shape)
    return [
        SpeedModel("lognormal", u0=med, sigma_ln=rng.uniform(0.05, 1.5, u_star.shape)),
        SpeedModel("maxwellian", granular_temperature=med**2 / math.log(2.0)),
        SpeedModel("fixed", u0=finite * 10 ** rng.uniform(-0.3, 3.0, u_star.shape)),
    ]


def _ends_above(lo, hi, count, u_star):
    """Window ends above u0* per element (what the quadrature can misplace)."""
    k = np.arange(lo.shape[1])[None, :] < count[:, None]
    us = u_star.reshape(-1, 1)
    ends = (k & (lo > us)).sum(axis=1) + (k & (hi > us) & np.isfinite(hi)).sum(axis=1)
    return ends.reshape(u_star.shape)


def _check_against_reference(pairs, laws, expect_exact=True):
    lo, hi, count, status = pairs.windows()
    ends = _ends_above(lo, hi, count, np.broadcast_to(pairs.u_star, pairs.shape).ravel())
    for law in laws:
        report = {}
        got = sticking_probability(law, pairs.u_star, pairs.collide, nodes=N_REF,
                                   pair=pairs.pair, report=report)
        ref = sticking_probability(law, pairs.u_star, pairs.collide, nodes=N_REF)
        f_star = np.broadcast_to(law.cdf(pairs.u_star), got.shape)
        nodes = 1 if law.family == "fixed" else N_REF
        bound = 1e-9 + ends * (1.0 - f_star) / (2.0 * nodes)
        if law.family == "fixed":
            bound = np.full(got.shape, 1e-9)  # one node: the indicator at u0 itself
        err = np.abs(got - ref)
        worst = np.unravel_index(np.argmax(err - bound), got.shape)
        assert np.all(err <= bound), (law.family, worst, got[worst], ref[worst], ends[worst])
        assert np.all((got >= 0.0) & (got <= 1.0))
        if expect_exact:
            assert report["quadrature"] == 0, report
    return count, status


def _check_windows_on_a_grid(pairs, points=4001):
    """The kernel on a geometric grid from u0* to 1e4 u0*: it sticks exactly inside the
    windows (beyond 1e-8 of their ends). Returns the number of elements with windows."""
    lo, hi, count, status = pairs.windows()
    us = np.broadcast_to(pairs.u_star, pairs.shape).ravel()
    ok = np.isfinite(us) & (us > 0.0) & (status == 0)
    grid = np.geomspace(1.0, 1e4, points)[1:]
    u = np.where(ok, us, 1.0)[:, None] * grid[None, :]
    kw = dict(pairs.kw, beta_deg=np.asarray(pairs.kw["beta_deg"], dtype=float)[..., None])
    stick = np.broadcast_to(at.collide(u0=u, details=False, **kw).agglomerated, u.shape)
    inside = np.zeros(u.shape, dtype=bool)
    near = np.zeros(u.shape, dtype=bool)
    for j in range(lo.shape[1]):
        has = (count > j)[:, None]
        a = np.where(has, lo[:, j:j + 1], 1.0)
        b = np.where(has, hi[:, j:j + 1], 1.0)
        inside |= has & (u >= a) & (u <= b)
        near |= has & ((np.abs(u / a - 1.0) < 1e-8) | (np.abs(u / b - 1.0) < 1e-8))
    bad = ok[:, None] & (stick != inside) & ~near
    assert not bad.any(), np.argwhere(bad)[:5]
    return int(np.count_nonzero(count[ok] > 0))


@pytest.mark.parametrize("make", [_water, _slag])
@pytest.mark.parametrize("mode", ["relative", "paper"])
def test_paper_cases_and_partners_every_angle(make, mode):
    """Table 2 cases against themselves and the Table 3 partners (ilmenite, 4330 kg/m3; a
    600 um grain) at 24 angles: mode "relative" exact everywhere (no element left to the
    quadrature), its windows checked on a dense grid; mode "paper" exact where no body
    force acts on the axis (beta = 0, 180) and by the same quadrature elsewhere."""
    p, liquid, gas = make()
    ilmenite = at.Particle(d=p.d, rho=4330.0, h0=p.h0, ha=p.ha)
    small = at.Particle(d=600e-6, rho=p.rho, h0=p.h0, ha=p.ha)
    beta = np.linspace(0.0, 345.0, 24)
    rng = np.random.default_rng(26)
    for partner in (p, ilmenite, small):
        pairs = Pairs(p, partner, liquid, gas, beta, 0.9, mode=mode)
        _check_against_reference(pairs, _laws(pairs.u_star, rng),
                                 expect_exact=mode == "relative")
        if mode == "relative":
            _check_windows_on_a_grid(pairs)


def test_pairs_that_stick_again_above_u_star():
    """A seeded random set in which pairs stick again above u0* (the test fails if none
    does): every law against the 4096-node reference within its bound, and the windows
    against the kernel on a dense grid."""
    with_windows = 0
    rng = np.random.default_rng(7)
    for k, pairs in enumerate(_random_pairs(11, 100, angles=25)):
        count = pairs.windows()[2]
        if not (count > 0).any() and k % 10:
            continue  # every tenth pair without a window, each pair with one
        count, status = _check_against_reference(pairs, _laws(pairs.u_star, rng),
                                                  expect_exact=False)
        assert np.all(status == 0)
        with_windows += _check_windows_on_a_grid(pairs, points=1001)
    assert with_windows >= 10


def test_plate_under_a_viscous_film_sticks_again():
    """The case tests/test_critical_closed.py records: a 3.9 mm bead on a plate through a
    1e6 Pa s film barely thicker than the asperities, at 3 deg. The kernel rebounds in a
    narrow window from u0* and sticks again above it; the propensity counts that mass."""
    ha = 1.5855946375724058e-06
    p_i = at.Particle(d=0.00390625, rho=1162.0, h0=ha * 1.0001000000000002, ha=ha)
    p_j = at.Particle.plate(h0=ha * 1.0001000000000002, ha=ha)
    liquid = at.Liquid(mu=1e6, gamma=0.5, rho=1500.0, theta_deg=0.0)
    pairs = Pairs(p_i, p_j, liquid, AIR, np.array([3.0]), 1.0, bed=at.Bed())
    lo, hi, count, _ = pairs.windows()
    assert count[0] >= 1 and lo[0, 0] > pairs.u_star[0]  # a window above u0*
    law = SpeedModel("lognormal", u0=np.sqrt(lo[0, 0] * hi[0, 0]), sigma_ln=1.0)
    p = sticking_probability(law, pairs.u_star, pairs.collide, pair=pairs.pair)
    assert float(p[0]) > float(law.cdf(pairs.u_star)[0]) + 0.1  # the window's mass counts
    _check_against_reference(pairs, [law, SpeedModel("maxwellian",
                                                     granular_temperature=hi[0, 0] ** 2)])
    _check_windows_on_a_grid(pairs)


def test_knife_edges():
    """Coatings barely thicker than the asperities (1e-12 to 1e-3 above them), laws
    concentrated at u0* (sigma_ln 1e-3, fixed speeds at u0* (1 + 1e-6)), and fixed speeds
    just inside a window's ends."""
    water = _water()
    rng = np.random.default_rng(5)
    beta = np.array([0.0, 60.0, 135.0, 270.0])
    for x in (1e-12, 1e-9, 1e-6, 1e-3):
        p = at.Particle(d=1000e-6, rho=2650.0, h0=0.1e-6 * (1 + x), ha=0.1e-6)
        q = at.Particle(d=300e-6, rho=4330.0, h0=0.1e-6 * (1 + x), ha=0.1e-6)
        pairs = Pairs(p, q, water[1], water[2], beta, 0.9)
        us = np.where(np.isfinite(pairs.u_star), pairs.u_star, 1.0)
        laws = _laws(pairs.u_star, rng) + [
            SpeedModel("lognormal", u0=us, sigma_ln=1e-3),
            SpeedModel("fixed", u0=us * (1.0 + 1e-6)),
            SpeedModel("maxwellian", granular_temperature=us**2 * 1e-3),
        ]
        _check_against_reference(pairs, laws)
    # fixed speeds 1e-6 inside and outside the ends of windows above u0*
    for pairs in _random_pairs(11, 40):
        lo, hi, count, _ = pairs.windows()
        rows = np.flatnonzero(count > 0)
        if rows.size == 0:
            continue
        k = rows[0]
        sub = Pairs(pairs.kw["p_i"], pairs.kw["p_j"], pairs.kw["liquid"], AIR,
                    np.atleast_1d(pairs.kw["beta_deg"])[k:k + 1], pairs.kw["e"])
        speeds = np.array([lo[k, 0] * (1 + 1e-6), hi[k, 0] * (1 - 1e-6),
                           hi[k, 0] * (1 + 1e-6)])
        speeds = speeds[np.isfinite(speeds)]
        for u in speeds:
            law = SpeedModel("fixed", u0=u)
            got = sticking_probability(law, sub.u_star, sub.collide, pair=sub.pair)
            assert float(got[0]) == float(bool(sub.collide(u).agglomerated[0]))
        return
    pytest.fail("no window above u0* in the random set")


@pytest.mark.parametrize("mode", ["stokes", "auto", "ode", "ode_selfconsistent"])
def test_other_tiers_take_their_own_sets(mode):
    """Tiers without a compiled sticking set: "stokes" takes ``F(u0*)`` (counted exact),
    the others the bracketing of :mod:`agglomtool.collision.sticking_numeric` (counted
    bracketed); none is left to the quadrature, and where no window lies above u0* the
    numbers are bitwise the quadrature's (tests/test_sticking_numeric.py: the hard set)."""
    p, liquid, gas = _water()
    pairs = Pairs(p, at.Particle(d=600e-6, rho=2650.0, h0=p.h0, ha=p.ha), liquid, gas,
                  np.array([0.0, 90.0]), 0.9, mode=mode)
    law = SpeedModel("lognormal", u0=2.0 * pairs.u_star, sigma_ln=0.8)
    report = {}
    got = sticking_probability(law, pairs.u_star, pairs.collide, nodes=16,
                               pair=pairs.pair, report=report)
    ref = sticking_probability(law, pairs.u_star, pairs.collide, nodes=16)
    np.testing.assert_array_equal(got, ref)
    done = "exact" if mode == "stokes" else "bracketed"
    assert report[done] == got.size and report["quadrature"] == 0, report


def test_fallbacks_are_bracketed():
    """Mode "paper" with body forces off the axis and a drag that depends on the particles'
    speed have no compiled set: those elements are bracketed with the tier's own kernel
    (bitwise the quadrature where no window lies above u0*) and counted; the axis' element
    of mode "paper" keeps the compiled set."""
    p, liquid, gas = _water()
    q = at.Particle(d=600e-6, rho=4330.0, h0=p.h0, ha=p.ha)
    for mode, slip in (("paper", False), ("relative", True)):
        pairs = Pairs(p, q, liquid, gas, np.array([30.0, 90.0, 200.0]), 0.9, mode=mode,
                      slip=slip)
        law = SpeedModel("maxwellian", granular_temperature=(3.0 * pairs.u_star) ** 2)
        report = {}
        got = sticking_probability(law, pairs.u_star, pairs.collide, nodes=16,
                                   pair=pairs.pair, report=report)
        ref = sticking_probability(law, pairs.u_star, pairs.collide, nodes=16)
        np.testing.assert_array_equal(got, ref)
        assert report == {"exact": 0, "bracketed": got.size, "quadrature": 0}, report


def test_a_map_takes_the_compiled_set():
    """A sweep's propensity equals the 4096-node reference of the same points within the
    bound (no window here: 1e-9), and a scene in mode "relative" integrates none by nodes."""
    from agglomtool.scene import Resolved, Scene

    s = Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
    values = {**s.values(), "U_Umf": np.linspace(1.2, 8.0, 5).reshape(5, 1, 1),
              "h0": np.geomspace(1e-6, 30e-6, 4).reshape(1, 4, 1),
              "beta_deg": np.array([-60.0, 0.0, 45.0]).reshape(1, 1, 3)}
    r = Resolved(values)
    shape = np.broadcast_shapes(np.shape(r.u_star), np.shape(r.U))
    report = {}
    got = sticking_probability(r.speeds, r.u_star, r.collide, shape=shape,
                               collide_on=r.collide_on, pair=r.sticking_pair, report=report)
    ref = sticking_probability(r.speeds, r.u_star, r.collide, nodes=N_REF, shape=shape,
                               collide_on=r.collide_on)
    assert report == {"exact": got.size, "bracketed": 0, "quadrature": 0}
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=1e-9)
    ds = at.sweep(s, U_Umf=values["U_Umf"].ravel(), h0=values["h0"].ravel(),
                  beta_deg=values["beta_deg"].ravel())
    np.testing.assert_allclose(ds.propensity.values, got, rtol=0.0, atol=1e-12)
