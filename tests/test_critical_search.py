"""The u0* search, written once (:mod:`agglomtool.collision.critical`).

- Each collision converges on its own: a pair's u0* is the same, bitwise, alone and inside
  a batch whose other pairs need more bisection steps, in the modes searched over numpy
  batches ("stokes", "auto") as in the compiled ones. The tolerance is chosen at a step
  boundary: the search bisects ``ln w`` from a bracket of ``2^(1/16)``, so after ``k``
  halvings ``1 - lo/hi`` is ``1 - 2^(-1/(16 2^k))`` up to rounding; with ``rtol`` exactly
  that for ``k = 10``, about half of the pairs stop after 10 halvings and the rest need an
  11th (rounding decides), so a batch mixes fast and slow partners.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import agglomtool as at

AIR = at.Gas(mu=18.48e-6, rho=1.168)
#: ``1 - lo/hi`` after 10 halvings of the scan's last step: the boundary between 10 and 11.
RTOL_AT_A_STEP = -math.expm1(-math.log(2.0) / (16 * 2**10))


def _pairs(n, seed):
    rng = np.random.default_rng(seed)

    def lu(lo, hi):
        return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), n)

    ha = lu(0.02e-6, 1e-6)
    h0 = ha * lu(1.5, 100.0)
    return dict(
        p_i=at.Particle(d=lu(100e-6, 3e-3), rho=rng.uniform(1000.0, 5000.0, n), h0=h0, ha=ha),
        p_j=at.Particle(d=lu(100e-6, 3e-3), rho=rng.uniform(1000.0, 5000.0, n), h0=h0, ha=ha),
        liquid=at.Liquid(mu=lu(1e-3, 30.0), gamma=rng.uniform(0.02, 0.5, n),
                         rho=rng.uniform(800.0, 3000.0, n),
                         theta_deg=rng.uniform(0.0, 80.0, n)),
        gas=AIR, bed=at.Bed(eps=rng.uniform(0.4, 0.95, n)),
        beta_deg=rng.uniform(0.0, 360.0, n), e=rng.uniform(0.2, 1.0, n),
    )


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
