"""Monte Carlo of a Scene, in the Scene's own names (one vocabulary for every entry point)."""

import numpy as np
import pytest

import agglomtool as at
from agglomtool.plausibility import PlausibilityWarning
from agglomtool.scene import Resolved

SCENE = at.Scene(liquid="water", T=298.15, h0=5e-6, h0_j=5e-6, u0=0.1, d_i=300e-6)


def test_scene_path_equals_the_low_level_call_with_the_same_draws():
    ds = at.monte_carlo(SCENE, uncertain={"h0": at.Normal(5e-6, 2e-6)}, n=5000, seed=3)
    r = Resolved(SCENE.values())
    p_i, p_j = r.particles
    low = at.monte_carlo(p_i, p_j, liquid=r.liquid, gas=r.gas, bed=at.Bed(eps=0.55, U=None),
                         u0=0.1, e=float(r.e), uncertain={"h0_i": at.Normal(5e-6, 2e-6)},
                         n=5000, seed=3)
    np.testing.assert_array_equal(ds.h0.values, low.h0_i.values)  # same stream
    np.testing.assert_array_equal(ds.e_w.values, low.e_w.values)
    assert 0.05 < float(ds.p_agglomeration) < 0.95  # a real spread, not all one outcome
    assert ds.h0.attrs["units"] == "m" and "provenance: T" in ds.attrs


def test_the_record_names_the_uncertain_fields_without_the_samples():
    kw = dict(uncertain={"h0": at.Normal(5e-6, 2e-6)}, n=2000, seed=3)
    kept = at.monte_carlo(SCENE, **kw)
    lean = at.monte_carlo(SCENE, **kw, keep_samples=False)
    for key in ("uncertain_inputs", "distributions", "n_resampled_total"):
        assert lean.attrs[key] == kept.attrs[key], key
    assert lean.attrs["uncertain_inputs"] == "h0" and "provenance: h0" not in lean.attrs
    assert float(lean.e_w_mean) == float(kept.e_w_mean)


def test_scene_fields_that_need_properties_can_be_uncertain():
    ds = at.monte_carlo(SCENE, uncertain={"T": at.Normal(318.15, 10.0)}, n=400, seed=1)
    assert ds.T.attrs["units"] == "K" and np.isfinite(ds.e_w.values).all()


def test_errors_and_warnings_name_the_field():
    with pytest.raises(ValueError, match="'h0_i' is not a numeric Scene field"):
        at.monte_carlo(SCENE, uncertain={"h0_i": at.Normal(5e-6, 1e-6)}, n=10)
    with pytest.raises(ValueError, match="liquid is given with a Scene"):
        at.monte_carlo(SCENE, liquid=at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0),
                       uncertain={"h0": at.Normal(5e-6, 1e-6)}, n=10)
    with pytest.raises(ValueError, match="p_j is required"):
        at.monte_carlo(at.Particle(d=1e-3, rho=2650.0, h0=1e-6, ha=1e-7),
                       uncertain={"h0_i": at.Normal(5e-6, 1e-6)}, n=10)
    # a standard deviation meant as a log-space spread: draws of 1e-20 m asperities
    with pytest.warns(PlausibilityWarning, match=r"^ha_i = .* outside the plausible"):
        at.monte_carlo(SCENE, uncertain={"ha_i": at.LogNormal(0.1e-6, 0.5)}, n=1000, seed=1)


def test_sobol_of_a_scene_in_its_own_names():
    ds = at.sobol_indices(SCENE, uncertain={"h0": at.Normal(5e-6, 1e-6),
                                            "u0": at.Normal(0.1, 0.02),
                                            "theta_deg": at.Uniform(0.0, 1.0)},
                          n_base=2**8, seed=2)
    assert list(ds.factor.values) == ["h0", "u0", "theta_deg"]
    st = dict(zip(ds.factor.values, ds.ST.values, strict=True))
    assert np.all(np.isfinite(ds.ST.values))
    assert st["u0"] > st["theta_deg"]  # impact speed matters; a 1-degree angle does not
    with pytest.raises(ValueError, match="gas is given with a Scene"):
        at.sobol_indices(SCENE, gas=at.Gas(mu=1.8e-5, rho=1.2),
                         uncertain={"h0": at.Normal(5e-6, 1e-6)}, n_base=4)


def test_one_draw_is_refused_it_has_no_spread():
    """n = 1 gave propensity_se = 0: a standard error of none, read as certainty."""
    from agglomtool.uncertainty import monte_carlo, table4_case

    with pytest.raises(ValueError, match=r"n = 1 .*allowed: n >= 2"):
        at.monte_carlo(SCENE, uncertain={"h0": at.Normal(5e-6, 1e-6)}, n=1, seed=0)
    with pytest.raises(ValueError, match=r"n = 1 .*allowed: n >= 2"):
        monte_carlo(**table4_case("water", 0.52), n=1, seed=0)
    ds = at.monte_carlo(SCENE, uncertain={"h0": at.Normal(5e-6, 1e-6)}, n=2, seed=0)
    p = ds.propensity.values
    assert float(ds.propensity_se) == pytest.approx(abs(p[0] - p[1]) / 2, rel=1e-12)


def test_a_draw_a_property_model_refuses_names_the_uncertain_field():
    """T = Normal(25, 5) meant in degC: the water model refused a draw at 15 K with its own
    message, which named neither the uncertain input nor the unit it was read in."""
    with pytest.raises(ValueError, match=r"^uncertain T: a draw is refused: liquid 'water'.*"
                                         r"T given without a unit, so in SI \(K\)"):
        at.monte_carlo(SCENE, uncertain={"T": at.Normal(25, 5)}, n=16, seed=0)
    # a law with its units: no unit hint, the law still named
    with pytest.raises(ValueError, match=r"^uncertain T: a draw is refused") as info:
        at.monte_carlo(SCENE, uncertain={"T": at.Normal("300 degC", "100 degC")}, n=64,
                       seed=0)
    assert "without a unit" not in str(info.value)
