"""Robust operating maps: the propensity's spread at every grid point under uncertain
inputs, with common random numbers across the grid."""

import numpy as np
import pytest

import agglomtool as at
from agglomtool.maps.robust import UNDECIDED

SAND = at.Scene(liquid="water", T=298.15, solid_i="silica-sand", d_i=300e-6)
GRID = dict(solid_j=["silica-sand", "ilmenite"], U_Umf=[1.5, 3.0, 6.0], h0=[2e-6, 8e-6])


@pytest.fixture(scope="module")
def robust():
    return at.sweep(SAND, uncertain="assumed", samples=64, seed=7, **GRID)


def test_each_point_is_the_scene_monte_carlo_of_that_point_with_the_same_draws(robust):
    """Draw k is the same world at every point: the robust map's point equals the Scene
    Monte Carlo of that point with the same seed and count (the same named streams)."""
    for solid_j, u, h0 in (("ilmenite", 3.0, 8e-6), ("silica-sand", 1.5, 2e-6)):
        mc = at.monte_carlo(SAND.replace(solid_j=solid_j, U_Umf=u, h0=h0),
                            uncertain="assumed", n=64, seed=7)
        pt = robust.sel(solid_j=solid_j, U_Umf=u, h0=h0)
        np.testing.assert_allclose(float(pt.propensity_mean), float(mc.propensity_mean),
                                   rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(float(pt.p_unsafe), np.mean(mc.propensity.values > 0.5),
                                   rtol=0, atol=0)
        # and the nominal map is the plain sweep's
        assert float(pt.propensity) == float(at.sweep(
            SAND.replace(solid_j=solid_j), U_Umf=[u], h0=[h0]).propensity.squeeze())


def test_summaries_are_consistent(robust):
    qs = robust.propensity_quantile
    assert (qs.diff("quantile") >= 0).all()
    assert ((robust.p_unsafe >= 0) & (robust.p_unsafe <= 1)).all()
    lo, hi = UNDECIDED
    expect = (robust.p_unsafe > lo) & (robust.p_unsafe < hi)
    np.testing.assert_array_equal(robust.undecided.values, expect.values.astype(np.int8))
    assert robust.attrs["robust_samples"] == 64 and "asperity_height" in robust.attrs[
        "robust_uncertain_inputs"]


def test_a_degenerate_law_gives_the_nominal_map():
    ds = at.sweep(SAND, uncertain={"ha_i": at.Uniform(0.1e-6, 0.1e-6 * (1 + 1e-12))},
                      samples=4, solid_j=["silica-sand"], U_Umf=[1.5, 3.0], h0=[2e-6, 8e-6])
    np.testing.assert_allclose(ds.propensity_mean.values, ds.propensity.values, atol=1e-9)


@pytest.mark.parametrize("kw, match", [
    (dict(uncertain={"h0": at.Normal(5e-6, 1e-6)}, h0=[1e-6, 2e-6]),
     "h0 is both swept and uncertain"),
    (dict(uncertain="assumed", samples=1, h0=[1e-6, 2e-6]), "samples = 1 must be"),
    (dict(uncertain="assumed", threshold=1.5, h0=[1e-6, 2e-6]), "threshold = 1.5 must be"),
    (dict(uncertain="assumed", quantiles=[0.5, 2.0], h0=[1e-6, 2e-6]), "quantiles"),
    (dict(uncertain="assumd", h0=[1e-6, 2e-6]), "the one word allowed is 'assumed'"),
])
def test_bad_requests_are_refused_naming_the_field(kw, match):
    with pytest.raises(ValueError, match=match):
        at.sweep(SAND, **kw)


def test_a_robust_map_is_not_for_a_store():
    with pytest.raises(ValueError, match="computed in memory"):
        at.sweep(SAND, uncertain="assumed", store="somewhere", **GRID)


ROBUST_TOML = """
[scene]
liquid = "water"
T = "25 degC"
solid_i = "silica-sand"
d_i = "300 um"

[grid]
U_Umf = [1.5, 3.0]
h0 = [2e-6, 8e-6]

[uncertain]
assumed = true

[options]
samples = 16
seed = 7
"""


def test_a_robust_map_from_a_file(tmp_path, capsys):
    import xarray as xr

    from agglomtool.cli import main

    cfg = tmp_path / "r.toml"
    cfg.write_text(ROBUST_TOML)
    out = tmp_path / "r.nc"
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 0
    assert "robust map: 16 draws per point" in capsys.readouterr().out
    ds = xr.open_dataset(out)
    api = at.sweep(SAND, uncertain="assumed", samples=16, seed=7, U_Umf=[1.5, 3.0],
                   h0=[2e-6, 8e-6])
    np.testing.assert_array_equal(ds.p_unsafe.values, api.p_unsafe.values)
    ds.close()


@pytest.mark.parametrize("edit, match", [
    (("[uncertain]\nassumed = true\n", ""), r"\[options\] samples: unknown.*add an \[uncertain\]"),
    (("samples = 16", "samples = 1"), r"\[options\] samples: must be an integer >= 2"),
    (("assumed = true", 'h0 = { law = "normal", mean = 5e-6, sd = 1e-6 }'),
     r"\[uncertain\] h0: it is swept in \[grid\]"),
])
def test_bad_robust_files_are_refused_naming_the_key(tmp_path, capsys, edit, match):
    import re

    from agglomtool.cli import main

    cfg = tmp_path / "r.toml"
    cfg.write_text(ROBUST_TOML.replace(*edit))
    assert main(["map", str(cfg), "-o", str(tmp_path / "r.nc")]) == 2
    assert re.search(match, capsys.readouterr().err)


def test_implausible_draws_of_a_robust_map_are_said():
    # a lognormal given a log-space spread as its standard deviation: 1e-20 m asperities
    with pytest.warns(at.PlausibilityWarning, match=r"^ha_i = .* outside the plausible"):
        at.sweep(SAND, uncertain={"ha_i": at.LogNormal(0.1e-6, 0.5)}, samples=64,
                 U_Umf=[1.5, 3.0], h0=[2e-6, 8e-6])
