"""The u0* search, written once (:mod:`agglomtool.collision.critical`).

- Each collision converges on its own: a pair's u0* is the same, bitwise, alone and inside
  a batch whose other pairs need more bisection steps, in the modes searched over numpy
  batches ("stokes", "auto") as in the compiled ones. The tolerance is chosen at a step
  boundary: the search bisects ``ln w`` from a bracket of ``2^(1/16)``, so after ``k``
  halvings ``1 - lo/hi`` is ``1 - 2^(-1/(16 2^k))`` up to rounding; with ``rtol`` exactly
  that for ``k = 10``, about half of the pairs stop after 10 halvings and the rest need an
  11th (rounding decides), so a batch mixes fast and slow partners.
- One machine, two drivers: the batch driver (:func:`first_rebound_speed` over the numpy
  preparation, ``api._critical_vectorised``) and the compiled per-collision solver
  (``critical_speeds(closed_form=False)``) give the same u0*, bitwise, in the tiers both
  can run, with plates, both drag slips, body forces on and off, and a ceiling.
- The machine's contract on a known switch (a kernel stand-in that sticks below a chosen
  threshold): the answer rebounds and lies within ``rtol`` above the last sticking speed,
  from the viscous bound and from candidates above and below (mode "paper"'s bracket); the
  ceiling ends the search with ``inf``; a candidate whose bracket cannot close above the
  viscous bound still finds the switch.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _random_pairs import AIR, as_inputs, random_arrays

import agglomtool as at
from agglomtool.api import _FUSED, _critical_vectorised, _fused_inputs
from agglomtool.collision.critical import (
    BISECT,
    DONE,
    HOW_BRACKET,
    HOW_SEARCH,
    SCAN,
    SearchLimits,
    critical_speeds,
    search_from_bound,
    search_from_candidate,
    search_update,
)

#: ``1 - lo/hi`` after 10 halvings of the scan's last step: the boundary between 10 and 11.
RTOL_AT_A_STEP = -math.expm1(-math.log(2.0) / (16 * 2**10))


def _pairs(n, seed, plates=False):
    a = random_arrays(n, seed)
    if plates:
        a["d_j"][: n // 10] = np.inf
    return as_inputs(a)


def _element(kw, i):
    """The inputs of pair ``i`` alone (scalars)."""
    out = {}
    for name in ("p_i", "p_j", "liquid", "bed"):
        obj = kw[name]
        fields = {f: getattr(obj, f)[i] if np.ndim(getattr(obj, f)) else getattr(obj, f)
                  for f in obj.__dataclass_fields__
                  if getattr(obj, f) is not None and f not in ("name", "source")}
        out[name] = type(obj)(**fields)
    return dict(out, gas=kw["gas"], beta_deg=kw["beta_deg"][i], e=kw["e"][i])


@pytest.mark.parametrize("mode", ["stokes", "auto", "relative", "paper"])
@pytest.mark.parametrize("drag_slip", ["emulsion", "particle"])
def test_a_pairs_u_star_does_not_depend_on_its_batch(mode, drag_slip):
    kw = _pairs(24, 5)
    opts = dict(mode=mode, drag_slip=drag_slip, rtol=RTOL_AT_A_STEP)
    batch = at.critical_impact_speed(**kw, **opts)
    assert np.all(np.isfinite(batch) & (batch > 0.0))
    alone = np.array([at.critical_impact_speed(**_element(kw, i), **opts)
                      for i in range(batch.size)])
    np.testing.assert_array_equal(alone, batch)
    # ... and inside a batch of two, with each other pair as its partner in turn.
    for i in (0, 7):
        pair = _element(kw, i)
        for j in range(batch.size):
            both = {k: v for k, v in _element(kw, j).items()}
            two = {}
            for name in ("p_i", "p_j", "liquid", "bed"):
                a, b = pair[name], both[name]
                fields = {f: np.array([getattr(a, f), getattr(b, f)])
                          for f in a.__dataclass_fields__
                          if getattr(a, f) is not None and f not in ("name", "source")}
                two[name] = type(a)(**fields)
            got = at.critical_impact_speed(
                **two, gas=AIR, beta_deg=np.array([pair["beta_deg"], both["beta_deg"]]),
                e=np.array([pair["e"], both["e"]]), **opts)
            assert got[0] == alone[i] and got[1] == alone[j], (mode, i, j)


@pytest.mark.parametrize("mode", ["relative", "paper"])
@pytest.mark.parametrize("rtol", [1e-6, RTOL_AT_A_STEP])
def test_batch_driver_equals_the_compiled_solver(mode, rtol):
    kw = _pairs(400, 17, plates=True)
    _, ins, steps, n = _fused_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                                     kw["beta_deg"], kw["e"], None, None, speeds=False)
    finite = 0
    for body in (True, False):
        for slip in ("emulsion", "particle"):
            for ceiling in (math.inf, 0.2):
                batch = _critical_vectorised(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"],
                                             kw["bed"], kw["beta_deg"], kw["e"], mode, body,
                                             slip, rtol, None, ceiling)
                one = critical_speeds(ins, steps, n, _FUSED[mode], body=body,
                                      particle_slip=slip == "particle", rtol=rtol,
                                      u_max=ceiling, closed_form=False)
                np.testing.assert_array_equal(batch, one)
                finite += int(np.isfinite(one).sum())
    assert finite > 1500  # of 3200: the ceiling of 0.2 m/s cuts some


def _drive(s, lim, threshold):
    """Run search ``s`` against a kernel stand-in that sticks below ``threshold``; the
    answer and the speeds tried."""
    tried = []
    while s.phase != DONE:
        tried.append(s.w)
        s = search_update(s, s.w < threshold, lim)
    return s, tried


def _holds(s, tried, threshold, rtol):
    """The answer rebounds, and a speed within ``rtol`` below it was tried and stuck."""
    assert s.w >= threshold
    assert any(w < threshold and s.w - w <= rtol * s.w for w in tried) or s.w == tried[0]


@pytest.mark.parametrize("rtol", [1e-6, 1e-3, RTOL_AT_A_STEP])
def test_the_machine_finds_a_known_switch(rtol):
    rng = np.random.default_rng(4)
    for threshold in 10.0 ** rng.uniform(-8.0, 3.0, 60):
        w_vis = threshold * 10.0 ** rng.uniform(-6.0, -0.01)
        lim = SearchLimits(w_vis=w_vis, w_max=math.inf, rtol=rtol)
        s, tried = _drive(search_from_bound(lim), lim, threshold)
        assert s.origin == HOW_SEARCH
        _holds(s, tried, threshold, rtol)
        assert tried[0] == 2.0 * w_vis  # the first doubling of the bound
        # mode "paper": a bracket around candidates below, at and above the switch
        for c in threshold * np.array([0.3, 0.97, 1.0, 1.01, 1.5, 40.0]):
            s, tried = _drive(search_from_candidate(c), lim, threshold)
            assert s.origin == HOW_BRACKET and tried[0] == c
            _holds(s, tried, threshold, rtol)


def test_the_machine_phases_and_ceiling():
    lim = SearchLimits(w_vis=1e-3, w_max=math.inf, rtol=1e-6)
    s = search_from_bound(lim)
    phases = []
    while s.phase != DONE:
        phases.append(s.phase)
        s = search_update(s, s.w < 0.05, lim)
    # doublings from 2e-3 up to 6.4e-2 (the first above 0.05), then the scan of
    # (3.2e-2, 6.4e-2], then the bisection
    assert phases[:6] == [0] * 6 and SCAN in phases and phases[-1] == BISECT
    assert phases.index(BISECT) > phases.index(SCAN)
    assert 0.05 <= s.w <= 0.05 * (1 + 1e-6)
    # a ceiling below the switch: inf once every speed up to it is known to stick
    capped = SearchLimits(w_vis=1e-3, w_max=0.02, rtol=1e-6)
    s, tried = _drive(search_from_bound(capped), capped, 0.05)
    assert s.w == math.inf and max(tried) <= 2 * 0.02
    s, tried = _drive(search_from_candidate(0.03), capped, 0.05)
    assert s.w == math.inf
    # a candidate far above a switch close to the viscous bound: the bracket's bottom
    # stops at the bound (which sticks in every tier) and the bisection finds the switch
    s, tried = _drive(search_from_candidate(1e3), lim, 1.5e-3)
    assert min(tried) >= 1e-3 and 1.5e-3 <= s.w <= 1.5e-3 * (1 + 1e-6)
