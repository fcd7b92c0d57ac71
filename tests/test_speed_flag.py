"""A map partly outside an impact-speed model's domain: the points where the model has no
answer are flagged (``speed_flag``), their propensity is NaN with that flag and a warning
says how many and why; the rest of the map is computed. A single point still raises."""

import warnings

import numpy as np
import pytest
import xarray as xr

import agglomtool as at
from agglomtool.bed.speed_models import SPEED_FLAGS, NoImpactSpeedWarning

#: 1 mm sand (Geldart D: the bubble models warn of it) up to 8 U_mf: at the top bubbles
#: and their wakes fill the bed, for Darton's bubbles (Mori and Wen's stay bubbling there)
SAND = at.Scene(d_i=1e-3, speed="bubble-darton")
U_UMF = np.linspace(1.5, 8.0, 14)
#: the words of each flag's reason in the single point's ValueError
REASON = {1: "does not exceed", 2: "bubble fraction", 3: "fill the bed"}


def _point_error(scene):
    """The ValueError text of one point's collision, or None where it answers."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            scene.collide()
    except ValueError as exc:
        return str(exc)
    return None


def _sweep(scene, **grid):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = at.sweep(scene, **grid)
    return ds, [w for w in rec if issubclass(w.category, NoImpactSpeedWarning)]


@pytest.fixture(scope="module")
def darton():
    return _sweep(SAND, U_Umf=U_UMF)


def test_a_map_partly_outside_the_bubble_model_is_computed_where_it_answers(darton):
    ds, said = darton
    flag = ds.speed_flag.values
    errors = [_point_error(SAND.replace(U_Umf=float(u))) for u in U_UMF]
    # flagged exactly where the single point refuses, with the flag of its reason
    assert [f != 0 for f in flag] == [e is not None for e in errors]
    assert flag.any() and not flag.all()
    for f, e in zip(flag, errors, strict=True):
        if f:
            assert REASON[int(f)] in e
    bad = flag != 0
    for name in ("propensity", "u_typical", "margin", "e_w", "St"):
        assert np.isnan(ds[name].values[bad]).all(), name
        assert np.isfinite(ds[name].values[~bad]).all(), name
    # the rest is the map the points give on their own
    for u in U_UMF[~bad][:: 4]:
        one = at.sweep(SAND, U_Umf=[float(u)]).propensity.values[0]
        assert ds.propensity.sel(U_Umf=u).item() == one
    # the warning counts the flagged points and says why
    assert len(said) == 1
    text = str(said[0].message)
    assert f"{int(bad.sum())} of {flag.size} points" in text
    for f in np.unique(flag[bad]):
        assert SPEED_FLAGS[int(f)][0] in text


def test_the_flag_is_a_cf_flag_variable(darton):
    ds, _ = darton
    attrs = ds.speed_flag.attrs
    assert ds.speed_flag.dtype == np.int8
    np.testing.assert_array_equal(attrs["flag_values"], sorted(SPEED_FLAGS))
    assert attrs["flag_meanings"].split() == [v[0] for _, v in sorted(SPEED_FLAGS.items())]
    assert "speed_flag" in ds.propensity.attrs["ancillary_variables"]


def test_a_single_point_outside_still_raises():
    with pytest.raises(ValueError, match="fill the bed"):
        SAND.replace(U_Umf=8.0).collide()
    with pytest.raises(ValueError, match="fill the bed"):
        SAND.replace(U_Umf=8.0).evaluate()


def test_not_fluidized_points_of_the_excess_gas_estimate_are_flagged():
    s = at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
    ds, said = _sweep(s, U_Umf=[0.8, 1.0, 2.0, 3.0])
    np.testing.assert_array_equal(ds.speed_flag.values, [1, 1, 0, 0])
    assert np.isnan(ds.propensity.values[:2]).all()
    assert np.isfinite(ds.propensity.values[2:]).all()
    assert len(said) == 1 and "not_fluidized" in str(said[0].message)
    # the remedy fits the reason: a bed below U_mf needs more gas, not less
    text = str(said[0].message)
    assert "a U above U_mf" in text and "lower U" not in text


def test_every_flag_has_its_remedy():
    from agglomtool.maps.speed_flag import flag_text

    for code in SPEED_FLAGS:
        if code:  # a code added without its remedy raises a KeyError here
            text = flag_text(np.array([0, code], dtype=np.int8))
            assert text.startswith("the impact-speed model has no answer at 1 of 2 points")
            assert SPEED_FLAGS[code][0] in text
            assert ("a U above U_mf" if code == 1 else "another speed model") in text


def test_a_map_that_answers_everywhere_says_nothing():
    s = at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
    ds, said = _sweep(s, U_Umf=[2.0, 3.0])
    assert not said and (ds.speed_flag.values == 0).all()


def test_cli_map_of_a_partly_outside_map(tmp_path, capsys):
    from agglomtool.cli import main

    cfg = tmp_path / "c.toml"
    cfg.write_text('[scene]\nd_i = 1e-3\nspeed = "bubble-darton"\n'
                   '[grid]\nU_Umf = { start = 1.5, stop = 8.0, num = 14 }\n'
                   'h0 = [0.2e-6, 1e-6]\n')
    out = tmp_path / "m.nc"
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 0
    err = capsys.readouterr().err
    assert "points" in err and "no_emulsion" in err
    with xr.open_dataset(out) as ds:
        flag = ds.speed_flag.values
        assert flag.any() and not flag.all()
        assert np.isnan(ds.propensity.values[flag != 0]).all()
        assert np.isfinite(ds.propensity.values[flag == 0]).all()
    png = tmp_path / "w.png"
    assert main(["plot", str(out), "-o", str(png)]) == 0
    assert png.stat().st_size > 10_000


def _legend_texts(fig):
    return [t.get_text() for leg in fig.legends for t in leg.get_texts()]


def test_the_plot_marks_the_flagged_region(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from agglomtool.plots import operating_window

    ds, _ = _sweep(SAND, U_Umf=U_UMF, h0=[0.2e-6, 1e-6, 5e-6])
    fig = operating_window(ds, x="U_Umf", y="h0")
    assert any("no impact speed" in t and "no emulsion" in t for t in _legend_texts(fig))
    fig1 = operating_window(ds.isel(h0=[0]), x="U_Umf")
    assert any("no impact speed" in t for t in _legend_texts(fig1))
    fig2 = operating_window(ds, "speed_flag", x="U_Umf", y="h0")
    assert "no emulsion" in _legend_texts(fig2)


def test_a_robust_map_partly_outside(tmp_path):
    ds = at.sweep(SAND, uncertain={"ha_i": at.Uniform(0.1e-6, 0.3e-6)}, samples=4,
                  U_Umf=U_UMF[[0, 6, 13]])
    bad = ds.speed_flag.values != 0
    assert bad.any() and not bad.all()
    for name in ("propensity_mean", "p_unsafe"):
        assert np.isnan(ds[name].values[bad]).all()
        assert np.isfinite(ds[name].values[~bad]).all()
    assert np.isnan(ds.propensity_quantile.values[bad]).all()
    # the undecided flag says the point has no answer, rather than "decided"
    und = ds.undecided
    meanings = dict(zip(np.atleast_1d(und.attrs["flag_values"]).tolist(),
                        und.attrs["flag_meanings"].split(), strict=True))
    assert {meanings[int(v)] for v in und.values[bad]} == {"no_impact_speed"}


def test_a_bed_map_partly_outside():
    """bed_sweep: the operating points where the bed's speed model has no answer are
    flagged and NaN, the others are the single bed's answers; one bed point raises."""
    from agglomtool.bed import Component, bed_propensity, bed_sweep

    comps = [Component("silica-sand", 1.0, d=[0.9e-3, 1.1e-3])]
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = bed_sweep(SAND, comps, directions=2, U_Umf=U_UMF[[0, 6, 13]])
    flag = ds.speed_flag.values
    assert list(flag != 0) == [False, False, True]
    assert REASON[int(flag[2])] in _point_error(SAND.replace(U_Umf=float(U_UMF[13])))
    assert np.isnan(ds.propensity.values[2]) and np.isfinite(ds.propensity.values[:2]).all()
    assert np.isnan(ds.propensity_by_class.values[2]).all()
    said = [w for w in rec if issubclass(w.category, NoImpactSpeedWarning)]
    assert len(said) == 1 and "1 of 3 points" in str(said[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        one = bed_propensity(SAND.replace(U_Umf=float(U_UMF[6])), comps, directions=2)
        assert float(one.propensity) == pytest.approx(float(ds.propensity.values[1]),
                                                      rel=1e-12)
        with pytest.raises(ValueError, match=REASON[int(flag[2])]):
            bed_propensity(SAND.replace(U_Umf=float(U_UMF[13])), comps, directions=2)


@pytest.mark.parametrize("speed", ["collisional-balance", "excess-gas"])
def test_a_bed_map_below_u_mf(speed):
    """Below U_mf no model has an answer: flagged and NaN in a bed map, whether the
    model's temperature is the bed's mean particle's (the collisional balance) or each
    pair's."""
    from agglomtool.bed import Component, bed_sweep

    scene = at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6, speed=speed)
    comps = [Component("silica-sand", 1.0, d=[250e-6, 350e-6])]
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = bed_sweep(scene, comps, directions=2, U_Umf=[0.8, 2.0])
    np.testing.assert_array_equal(ds.speed_flag.values, [1, 0])
    assert np.isnan(ds.propensity.values[0]) and np.isfinite(ds.propensity.values[1])
    assert [w for w in rec if issubclass(w.category, NoImpactSpeedWarning)]
