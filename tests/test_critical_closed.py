"""The near-closed-form u0* (mode "relative", and the bracket of mode "paper").

- against the plain search (``closed_form=False``, the solver used before the closed form):
  the same special values, finite answers within ``rtol`` of each other, across the input
  space (sizes and plates, densities, coatings H0/Ha from 1.0001 to 500, viscosities
  1e-3..1e6, contact and collision angles, restitution, body forces on and off, both drag
  slips), by hypothesis and on a seeded batch;
- the answer keeps the search's contract, checked through ``collide``: it rebounds at u0*
  and sticks at ``u0* (1 - rtol)``;
- where the closed form is refused (Newton given too few steps) every element falls back
  to the search and returns its numbers bitwise;
- the pieces of the derivation: the approach-limited threshold (the bridge breaks at
  contact) and a body force pulling the pair apart (``F_b < 0``, the kinked piece).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import agglomtool as at
from agglomtool.api import _FUSED, _fused_inputs
from agglomtool.collision._codes import P_BROKEN
from agglomtool.collision.critical import (
    HOW_CLOSED,
    HOW_SEARCH,
    HOW_TRIVIAL,
    critical_speeds,
)
from agglomtool.collision.critical_relative import FAILED, OK, relative_threshold
from agglomtool.collision.fused import prepare_flat
from agglomtool.collision.records import Pair
from agglomtool.collision.relative import relative_kernel

RTOL = 1e-6
AIR = at.Gas(mu=18.48e-6, rho=1.168)


def _solve(kw, mode="relative", slip=False, body=True, rtol=RTOL, u_max=math.inf, **opts):
    shape, ins, steps, n = _fused_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"],
                                         kw["bed"], kw["beta_deg"], kw["e"], None, None,
                                         speeds=False)
    return critical_speeds(ins, steps, n, _FUSED[mode], body=body, particle_slip=slip,
                           rtol=rtol, u_max=u_max, **opts)


def _agree(a, b, rtol=RTOL):
    """Same special values; finite values within ``rtol`` (both lie within ``rtol`` above
    the same switch)."""
    a, b = np.atleast_1d(a), np.atleast_1d(b)
    special = ~np.isfinite(a) | (a == 0.0) | ~np.isfinite(b) | (b == 0.0)
    np.testing.assert_array_equal(a[special], b[special])
    fin = ~special
    gap = np.abs(a[fin] - b[fin]) / np.maximum(a[fin], b[fin])
    assert np.all(gap <= rtol * (1 + 1e-9)), (np.flatnonzero(fin)[gap > rtol], gap.max())
    return int(fin.sum())


def _agree_or_earlier(a, b, rtol=RTOL):
    """:func:`_agree`, except that the closed form ``a`` may find an earlier switch than the
    search ``b``: the search steps up in speed and can step over a rebound window narrower
    than its steps (its documented limit), the closed form solves for the first crossing.
    Such an ``a`` must be finite, positive and below ``b``; the caller then checks it with
    the kernel (:func:`_contract`), so it is a real switch from stick to rebound."""
    a, b = np.atleast_1d(a), np.atleast_1d(b)
    both = np.isfinite(a) & (a > 0.0) & np.isfinite(b) & (b > 0.0)
    gap = np.zeros(a.shape)
    gap[both] = np.abs(a[both] - b[both]) / np.maximum(a[both], b[both])
    earlier = np.isfinite(a) & (a > 0.0) & (a < b) & ~(both & (gap <= rtol * (1 + 1e-9)))
    keep = ~earlier
    return _agree(a[keep], b[keep], rtol), int(earlier.sum())


def _contract(kw, u, mode="relative", slip=False, body=True, rtol=RTOL):
    """collide rebounds at u0* and sticks at u0* (1 - rtol) (finite positive u0* only)."""
    u = np.atleast_1d(u)
    fin = np.flatnonzero(np.isfinite(u) & (u > 0.0))
    if fin.size == 0:
        return 0

    def take(x):
        return x[fin] if np.ndim(x) else x

    sub = {}
    for name in ("p_i", "p_j", "liquid", "gas", "bed"):
        obj = kw[name]
        fields = {f: take(getattr(obj, f)) for f in obj.__dataclass_fields__
                  if getattr(obj, f) is not None and f not in ("name", "source")}
        sub[name] = type(obj)(**fields)
    common = dict(**sub, beta_deg=take(kw["beta_deg"]), e=take(kw["e"]), mode=mode,
                  body_forces=body, drag_slip="particle" if slip else "emulsion",
                  details=False)
    up = at.collide(u0=u[fin], **common)
    down = at.collide(u0=u[fin] * (1.0 - rtol), **common)
    assert np.all(up.e_w > 0.0), fin[up.e_w == 0.0]
    assert np.all(down.e_w == 0.0), fin[down.e_w > 0.0]
    return fin.size


def _batch(n, seed, plates=True):
    """``n`` scenes spread over the input space (log-uniform where the range is wide)."""
    rng = np.random.default_rng(seed)

    def lu(lo, hi, size=n):
        return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), size)

    ha = lu(0.01e-6, 2e-6)
    h0 = ha * (1.0 + lu(1e-4, 499.0))  # H0/Ha from 1.0001 to 500
    d_i, d_j = lu(50e-6, 5e-3), lu(50e-6, 5e-3)
    rho_i, rho_j = rng.uniform(900.0, 8000.0, n), rng.uniform(900.0, 8000.0, n)
    if plates:
        k = rng.random(n)
        d_j = np.where(k < 0.1, np.inf, d_j)
        rho_j = np.where(k < 0.1, np.inf, rho_j)
        d_i = np.where(k > 0.95, np.inf, d_i)
        rho_i = np.where(k > 0.95, np.inf, rho_i)
    return dict(
        p_i=at.Particle(d=d_i, rho=rho_i, h0=h0, ha=ha),
        p_j=at.Particle(d=d_j, rho=rho_j, h0=h0 * rng.uniform(0.5, 1.5, n), ha=ha),
        liquid=at.Liquid(mu=lu(1e-3, 1e6), gamma=rng.uniform(0.02, 0.6, n),
                         rho=rng.uniform(700.0, 3000.0, n),
                         theta_deg=rng.uniform(0.0, 85.0, n)),
        gas=at.Gas(mu=lu(1.5e-5, 6e-5), rho=lu(0.2, 2.0)),
        bed=at.Bed(eps=rng.uniform(0.4, 0.95, n)),
        beta_deg=rng.uniform(0.0, 360.0, n), e=rng.uniform(0.05, 1.0, n),
    )


@pytest.mark.parametrize("slip", [False, True])
@pytest.mark.parametrize("body", [True, False])
def test_closed_form_equals_the_search_on_a_wide_batch(slip, body):
    kw = _batch(4000, 20240601 + 2 * slip + body)
    got, how = _solve(kw, slip=slip, body=body, return_how=True)
    ref = _solve(kw, slip=slip, body=body, closed_form=False)
    assert _agree(got, ref) > 3000
    # The closed form carries (nearly) every element with a bridge; the rest went to the
    # search.
    bridged = how != HOW_TRIVIAL
    assert bridged.sum() > 2500
    assert np.mean(how[bridged] == HOW_CLOSED) > 0.95
    assert np.all(np.isin(how, (HOW_TRIVIAL, HOW_CLOSED, HOW_SEARCH)))
    assert _contract(kw, got, slip=slip, body=body) > 3000


@pytest.mark.parametrize("mode", ["paper", "relative"])
def test_closed_form_and_bracket_equal_the_search_with_plates_and_angles(mode):
    kw = _batch(1500, 77)
    got = _solve(kw, mode=mode)
    ref = _solve(kw, mode=mode, closed_form=False)
    assert _agree(got, ref) > 1000
    _contract(kw, got, mode=mode)


_pos = dict(allow_nan=False, allow_infinity=False)


@settings(max_examples=120, deadline=None)
@given(
    d_i=st.floats(50e-6, 5e-3, **_pos), d_j=st.one_of(st.floats(50e-6, 5e-3, **_pos),
                                                       st.just(math.inf)),
    rho_i=st.floats(900.0, 8000.0, **_pos), rho_j=st.floats(900.0, 8000.0, **_pos),
    ha=st.floats(0.01e-6, 2e-6, **_pos), ratio=st.floats(1.0001, 500.0, **_pos),
    log_mu=st.floats(-3.0, 6.0, **_pos), gamma=st.floats(0.02, 0.6, **_pos),
    theta=st.floats(0.0, 85.0, **_pos), beta=st.floats(0.0, 360.0, **_pos),
    e=st.floats(0.05, 1.0, **_pos), body=st.booleans(), slip=st.booleans(),
)
# Found by hypothesis: a 3.9 mm bead on a plate through a 1e6 Pa s film barely thicker than
# the asperities, at 3 deg with body forces. The kernel rebounds in a window 1e-5 wide
# (relative) from 1.68e-5 m/s, sticks above it again and rebounds for good only from
# 4.9e-3 m/s; the search steps over the window, the closed form finds it.
@example(d_i=0.00390625, d_j=math.inf, rho_i=1162.0, rho_j=900.0, ha=1.5855946375724058e-06,
         ratio=1.0001000000000002, log_mu=6.0, gamma=0.5, theta=0.0, beta=3.0, e=1.0,
         body=True, slip=False)
def test_closed_form_equals_the_search_hypothesis(d_i, d_j, rho_i, rho_j, ha, ratio, log_mu,
                                                  gamma, theta, beta, e, body, slip):
    kw = dict(
        p_i=at.Particle(d=d_i, rho=rho_i, h0=ha * ratio, ha=ha),
        p_j=at.Particle(d=d_j, rho=math.inf if math.isinf(d_j) else rho_j, h0=ha * ratio,
                        ha=ha),
        liquid=at.Liquid(mu=10.0**log_mu, gamma=gamma, rho=1500.0, theta_deg=theta),
        gas=AIR, bed=at.Bed(), beta_deg=beta, e=e,
    )
    got = _solve(kw, slip=slip, body=body)
    ref = _solve(kw, slip=slip, body=body, closed_form=False)
    _agree_or_earlier(got, ref)
    _contract(kw, got, slip=slip, body=body)


def test_existing_hard_cases(checks):
    """The published cases (water, slag), plates, a thick film on a plate, a size ratio of
    10 at odd angles, and coatings barely thicker than the asperities."""
    p_w, liq_w, gas_w = checks.case_water()
    p_s, liq_s, gas_s = checks.case_slag()
    wet = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
    big = at.Particle(d=10e-3, rho=2650.0, h0=20e-6, ha=1e-6)
    plate = at.Particle.plate(h0=5e-6, ha=0.1e-6)
    film = at.Particle.plate(h0=100e-6, ha=0.5e-6)
    glass = at.Particle(d=1.74e-3, rho=2500.0, h0=0.0, ha=1e-6)
    thin = [at.Particle(d=1000e-6, rho=2650.0, h0=0.1e-6 * (1 + x), ha=0.1e-6)
            for x in (1e-12, 1e-9, 1e-6, 1e-3)]
    beta = np.array([0.0, 45.0, 90.0, 135.0, 225.0, 270.0, 315.0])
    cases = [(p_w, p_w, liq_w, gas_w), (p_s, p_s, liq_s, gas_s), (plate, wet, liq_w, gas_w),
             (wet, plate, liq_w, gas_w), (film, glass, liq_w, gas_w), (wet, big, liq_w, gas_w),
             (big, wet, liq_w, gas_w)] + [(p, p, liq_w, gas_w) for p in thin]
    n = 0
    for p_i, p_j, liq, gas in cases:
        for mode in ("relative", "paper"):
            for slip in (False, True):
                kw = dict(p_i=p_i, p_j=p_j, liquid=liq, gas=gas, bed=at.Bed(), beta_deg=beta,
                          e=0.9)
                got = _solve(kw, mode=mode, slip=slip)
                n += _agree(got, _solve(kw, mode=mode, slip=slip, closed_form=False))
                _contract(kw, got, mode=mode, slip=slip)
    assert n > 250


def test_fallback_when_newton_is_refused():
    """``max_iter=0``: the closed form gives up on every element that needs the Newton
    iteration; each one then runs the search and returns its numbers bitwise. (Elements
    whose threshold is the approach's own, the bridge broken at contact, need no iteration
    and keep the closed form.)"""
    kw = _batch(500, 3)
    ref = _solve(kw, closed_form=False)
    got, how = _solve(kw, max_iter=0, return_how=True)
    searched = how == HOW_SEARCH
    np.testing.assert_array_equal(got[searched], ref[searched])
    assert searched.sum() > 300
    _agree(got, ref)
    # With Newton allowed, the same elements take the closed form.
    _, how_ok = _solve(kw, return_how=True)
    assert np.mean(how_ok[searched] == HOW_CLOSED) > 0.95


def test_fallback_when_verification_fails():
    """An ``rtol`` below the kernel's own rounding (1e-15): the candidate's bracket cannot
    be verified by the kernel, and the search answers instead (same numbers)."""
    p = at.Particle(d=800e-6, rho=2650.0, h0=3e-6, ha=0.1e-6)
    liq = at.Liquid(mu=5e4, gamma=0.3, rho=2500.0, theta_deg=20.0)  # viscous: K cancels
    kw = dict(p_i=p, p_j=p, liquid=liq, gas=AIR, bed=at.Bed(), beta_deg=30.0, e=0.9)
    got, how = _solve(kw, rtol=1e-15, return_how=True)
    ref = _solve(kw, rtol=1e-15, closed_form=False)
    assert how[0] == HOW_SEARCH
    np.testing.assert_array_equal(got, ref)


def test_ceiling_unchanged():
    """``u_max``: every answer at or below it bitwise the uncapped one, the rest inf, with
    the closed form as with the search."""
    kw = _batch(800, 9)
    full = _solve(kw)
    u_max = float(np.median(full[np.isfinite(full) & (full > 0)]))
    capped = _solve(kw, u_max=u_max)
    below = full <= u_max
    np.testing.assert_array_equal(capped[below], full[below])
    assert np.all(capped[~below] == math.inf)
    _agree(capped, _solve(kw, u_max=u_max, closed_form=False))


def _threshold(p_i, p_j, liq, e=0.9, fn_i=0.0, fn_j=0.0, max_iter=60):
    kw = dict(p_i=p_i, p_j=p_j, liquid=liq, gas=AIR, bed=at.Bed(), beta_deg=0.0, e=e)
    _, ins, steps, n = _fused_inputs(p_i, p_j, liq, AIR, kw["bed"], 0.0, e, None, None,
                                     speeds=False)
    k = prepare_flat(ins, steps, n, False, False)[:, 0]
    m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta = k[:9]
    w, status = relative_threshold(Pair(m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta, fn_i,
                                        fn_j, e), max_iter)
    return w, status, (m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta)


def _outcome(args, w, fn_i=0.0, fn_j=0.0, e=0.9):
    m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta = args
    return relative_kernel(Pair(m_i, m_j, r, H0, Ha, mu, gamma, cos_t, theta, fn_i, fn_j, e),
                           w, np.empty(0))


def test_approach_limited_threshold():
    """A bridge so thin that it is broken at contact: the first rebound is the first speed
    that passes the approach, ``w_v`` (viscosity alone stops the approach at or below it;
    the capillary pull only helps)."""
    p = at.Particle(d=1000e-6, rho=2650.0, h0=0.1e-6 * (1 + 1e-4), ha=0.1e-6)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0, theta_deg=0.0)
    w, status, args = _threshold(p, p, liq)
    assert status == OK
    assert _outcome(args, w)[0] == 0.0  # exactly w_v: approach_viscous
    ew, _, path, _ = _outcome(args, w * (1 + 1e-12))
    assert ew > 0.0 and path & P_BROKEN  # the bridge was gone at contact


def test_body_force_pulling_apart():
    """``F_b < 0`` (a plate held above a heavy particle: gravity pulls it off): the pieces
    on both sides of the gap where the body work overtakes the capillary one; the kernel
    switches at the answer."""
    p = at.Particle(d=3e-3, rho=7000.0, h0=2e-6, ha=0.5e-6)
    plate = at.Particle.plate(h0=2e-6, ha=0.5e-6)
    for mu in (1e-3, 1.0, 100.0):
        liq = at.Liquid(mu=mu, gamma=0.07, rho=1000.0, theta_deg=30.0)
        for fn_i in (-1e-6, -1e-4, -1e-2):
            w, status, args = _threshold(p, plate, liq, fn_i=fn_i)
            assert status == OK, (mu, fn_i)
            assert _outcome(args, w * (1 - 1e-9), fn_i=fn_i)[0] == 0.0, (mu, fn_i)
            assert _outcome(args, w * (1 + 1e-9), fn_i=fn_i)[0] > 0.0, (mu, fn_i)


def test_refused_newton_reports_failure():
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0, theta_deg=10.0)
    assert _threshold(p, p, liq, max_iter=0)[1] == FAILED
    assert _threshold(p, p, liq)[1] == OK
