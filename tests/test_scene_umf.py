"""The Scene's compiled ``U_mf`` (:func:`agglomtool.properties.fluidization.umf_coated`)
against its numpy route (:func:`agglomtool.pair.wet_mass` and
:func:`agglomtool.properties.umf`, :meth:`Resolved._umf_reference`).

The compiled pass takes the same operations in the same order, so the two must agree
bitwise (not within a tolerance): on grid blocks of diameter x coating x temperature, on
scalar scenes (numpy's power of a scalar can differ in the last bit from its power of an
array; the compiled route takes each power as the numpy route does), for every correlation
of the Wen-Yu family, water and a slag, three gases, one solid or two different ones. Where
the compiled pass does not apply it says so (``None``) and the Scene takes the numpy route.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import agglomtool as at
from agglomtool.plausibility import PlausibilityWarning
from agglomtool.properties.fluidization import UMF_C1_C2, umf_coated
from agglomtool.scene import Resolved

pytestmark = pytest.mark.filterwarnings("ignore", category=PlausibilityWarning)


def _resolved(scene, **grid):
    values = scene.values()
    shape = [1] * len(grid)
    for k, (name, vals) in enumerate(grid.items()):
        s = list(shape)
        s[k] = -1
        values[name] = np.asarray(vals, dtype=float).reshape(s)
    return Resolved(values)


def _check_bitwise(r):
    p_i, p_j = r.particles
    for p in (p_i, p_j):
        fast = umf_coated(p.d, p.rho, p.h0, r.liquid.rho, r.gas.mu, r.gas.rho,
                          r.v["umf_method"])
        assert fast is not None  # the compiled pass ran (no silent fallback)
        ref = r._umf_reference(p)
        assert np.shape(fast) == np.shape(ref)
        np.testing.assert_array_equal(fast, ref)
    ref = np.maximum(r._umf_reference(p_i), r._umf_reference(p_j))
    np.testing.assert_array_equal(r.Umf, ref)


@pytest.mark.parametrize("method", list(UMF_C1_C2))
def test_umf_bitwise_on_a_block(method):
    rng = np.random.default_rng(list(UMF_C1_C2).index(method))
    scene = at.Scene(solid_i="glass-beads", liquid="water", gas="air", T=300.0, h0=5e-6,
                     d_i=500e-6, umf_method=method)
    r = _resolved(scene, d_i=np.sort(10 ** rng.uniform(-4.3, -2.5, 23)),
                  h0=np.sort(10 ** rng.uniform(-7.0, -4.5, 31)),
                  T=np.sort(rng.uniform(275.0, 370.0, 17)))
    _check_bitwise(r)


@pytest.mark.parametrize(("solid_i", "solid_j", "liquid", "gas", "T"), [
    ("glass-beads", None, "water", "air", 300.0),
    ("silica-sand", "olivine", "water", "nitrogen", 330.0),
    ("silica-sand", None, "blast-furnace-slag", "biomass-flue-gas", 1500.0),
    ("dense-alumina", "ilmenite", "wood-ash-melt", "carbon-dioxide", 1300.0),
])
def test_umf_bitwise_scalar_and_pairs(solid_i, solid_j, liquid, gas, T):
    rng = np.random.default_rng(3)
    for d_i, h0 in zip(10 ** rng.uniform(-4.3, -2.5, 20), 10 ** rng.uniform(-7.0, -4.5, 20),
                       strict=True):
        scene = at.Scene(solid_i=solid_i, solid_j=solid_j, liquid=liquid, gas=gas, T=T,
                         d_i=float(d_i), d_j=float(d_i) * 1.7 if solid_j else None,
                         h0=float(h0))
        _check_bitwise(Resolved(scene.values()))
    scene = at.Scene(solid_i=solid_i, solid_j=solid_j, liquid=liquid, gas=gas, T=T)
    r = _resolved(scene, d_i=10 ** rng.uniform(-4.3, -2.5, 40),
                  d_j=10 ** rng.uniform(-4.3, -2.5, 7), h0_j=10 ** rng.uniform(-7, -4.5, 5))
    _check_bitwise(r)


def test_umf_coated_declines_where_it_does_not_apply():
    """A plate, a method outside the family, a wet density not above the gas's: ``None``
    (the Scene's numpy route then answers or raises, as before)."""
    args = (500e-6, 2500.0, 5e-6, 1000.0, 1.8e-5, 1.2)
    assert umf_coated(*args) is not None
    assert umf_coated(math.inf, *args[1:]) is None
    assert umf_coated(*args, method="ergun") is None
    assert umf_coated(500e-6, 1.0, 5e-6, 1.0, 1.8e-5, 1.2) is None  # lighter than the gas
    with pytest.raises(ValueError, match="rho_p must exceed"):
        at.properties.umf(500e-6, 1.0, at.Gas(mu=1.8e-5, rho=1.2))
