"""The compiled u0* solver (modes "paper" and "relative") and the ``u_max`` ceiling.

- against the vectorised search over the numpy preparation (``api._critical_vectorised``,
  the path every other mode takes): the same search, so both answers lie within ``rtol``
  above the same threshold, on a wide random set and near the paper's special paths, with
  both drag-slip rules (with ``"particle"`` the drag is re-evaluated at every trial speed);
- the answer is where ``collide`` switches from sticking to rebounding;
- ``u_max``: every finite answer at or below the ceiling is bitwise the uncapped one, every
  answer above it is ``inf``, in every mode; bad ceilings are refused.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _random_pairs import as_inputs, random_arrays

import agglomtool as at
from agglomtool.api import _critical_vectorised

RTOL = 1e-6


def _random_set(n, seed):
    a = random_arrays(n, seed)
    a["h0"][:10] = 0.5 * a["ha"][:10]  # no bridge: 0
    a["e"][10:20] = 0.0  # never rebounds: inf
    a["d_j"][20:60] = np.inf  # plates
    return as_inputs(a)


def _reference(kw, mode, drag_slip="emulsion", body_forces=True):
    return _critical_vectorised(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                                kw["beta_deg"], kw["e"], mode, body_forces, drag_slip, RTOL,
                                None, math.inf)


def _agree(a, b):
    a, b = np.asarray(a), np.asarray(b)
    special = ~np.isfinite(a) | (a == 0.0) | ~np.isfinite(b) | (b == 0.0)
    np.testing.assert_array_equal(a[special], b[special])
    fin = ~special
    assert np.all(np.abs(a[fin] - b[fin]) <= RTOL * np.maximum(a[fin], b[fin]) * (1 + 1e-9))
    return int(fin.sum())


@pytest.mark.parametrize("mode", ["paper", "relative"])
@pytest.mark.parametrize("drag_slip", ["emulsion", "particle"])
def test_compiled_solver_equals_the_vectorised_search(mode, drag_slip):
    kw = _random_set(600, 11)
    got = at.critical_impact_speed(**kw, mode=mode, drag_slip=drag_slip, rtol=RTOL)
    ref = _reference(kw, mode, drag_slip)
    assert np.all(got[:10] == 0.0) and np.all(got[10:20] == math.inf)
    assert _agree(got, ref) > 500


@pytest.mark.parametrize("mode", ["paper", "relative"])
def test_compiled_solver_near_the_special_paths(checks, mode):
    for p, liq, gas in (checks.case_water(), checks.case_slag()):
        kw = dict(p_i=p, p_j=p, liquid=liq, gas=gas, bed=at.Bed(),
                  beta_deg=np.array([0.0, 45.0, 90.0, 135.0, 225.0, 270.0, 315.0]), e=0.9)
        got = at.critical_impact_speed(**kw, mode=mode)
        assert _agree(got, _reference(kw, mode)) == 7
        # collide switches there.
        u = got[:, None] * np.array([1.0 - 1e-5, 1.0 + 1e-5])
        r = at.collide(p, p, liquid=liq, gas=gas, beta_deg=kw["beta_deg"][:, None], e=0.9,
                       u0=u, mode=mode, details=False)
        assert np.all(r.e_w[:, 0] == 0.0) and np.all(r.e_w[:, 1] > 0.0)


def test_particle_slip_threshold_is_where_collide_switches(checks):
    p, liq, gas = checks.case_water()
    beta = np.array([30.0, 90.0, 200.0])
    u = at.critical_impact_speed(p, p, liquid=liq, gas=gas, beta_deg=beta,
                                 drag_slip="particle")
    r = at.collide(p, p, liquid=liq, gas=gas, beta_deg=beta[:, None], drag_slip="particle",
                   u0=u[:, None] * np.array([1.0 - 1e-5, 1.0 + 1e-5]), details=False)
    assert np.all(r.e_w[:, 0] == 0.0) and np.all(r.e_w[:, 1] > 0.0)


@pytest.mark.parametrize("mode", ["paper", "relative", "ode"])
def test_u_max_caps_exactly(mode):
    kw = _random_set(300 if mode != "ode" else 60, 5)
    full = at.critical_impact_speed(**kw, mode=mode)
    finite = full[np.isfinite(full) & (full > 0.0)]
    u_max = float(np.median(finite))
    capped = at.critical_impact_speed(**kw, mode=mode, u_max=u_max)
    below = full <= u_max
    np.testing.assert_array_equal(capped[below], full[below])
    assert np.all(capped[~below] == math.inf)
    assert 0 < below.sum() < below.size


def test_u_max_stops_early_where_nothing_rebounds(checks):
    """A very viscous pair whose u0* lies far above the ceiling comes back inf (and a
    scalar); without the ceiling its u0* is finite and above it."""
    p, liq, gas = checks.case_slag()
    thick = at.Liquid(mu=1e6, gamma=0.4, rho=2500.0, theta_deg=10.0)
    u = at.critical_impact_speed(p, p, liquid=thick, gas=gas, u_max=10.0)
    assert u == math.inf
    assert 10.0 < at.critical_impact_speed(p, p, liquid=thick, gas=gas) < math.inf
    assert np.shape(u) == ()


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, "fast"])
def test_u_max_must_be_a_positive_speed(bad, checks):
    p, liq, gas = checks.case_water()
    with pytest.raises(ValueError, match="u_max"):
        at.critical_impact_speed(p, p, liquid=liq, gas=gas, u_max=bad)


def test_tol_is_refused_by_the_compiled_modes(checks):
    """The compiled solver must not silently drop ``tol`` (only mode "auto" takes it)."""
    p, liq, gas = checks.case_water()
    for mode in ("paper", "relative"):
        with pytest.raises(ValueError, match="tol"):
            at.critical_impact_speed(p, p, liquid=liq, gas=gas, mode=mode, tol=0.01)
        with pytest.raises(ValueError, match="tol"):
            at.collide(p, p, liquid=liq, gas=gas, u0=0.1, mode=mode, tol=0.01)
