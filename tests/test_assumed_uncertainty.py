"""The database's assumed values as uncertain inputs, and the Scene Monte Carlo that
answers the map's question (propensity, u0*) per draw."""

import math
import textwrap

import numpy as np
import pytest
from scipy import stats

import agglomtool as at
from agglomtool import materials
from agglomtool.materials import MaterialsError, load
from agglomtool.uncertainty.assumed import assumed_draws, law_distribution, scene_fields

GLASS = at.Scene(liquid="water", T=323.15, h0=5e-6, d_i=400e-6, solid_i="glass-beads",
                 U_Umf=2.0)


def test_every_assumed_number_of_the_database_states_a_law_that_holds_its_value():
    numeric = {"density", "asperity_height", "restitution_dry", "theta_deg", "mu", "gamma",
               "rho"}
    seen = 0
    for kind, lookup in (("solid", materials.solid), ("liquid", materials.liquid_entry)):
        for name in materials.names(kind):
            entry = lookup(name)
            laws = {law.field: law for law in entry.uncertainty}
            assert set(laws) == set(entry.assumed) & (numeric | {"composition_wt"}), (kind,
                                                                                      name)
            for field, law in laws.items():
                if field == "composition_wt":  # factors on the shares: the band holds 1
                    assert law.law == "logratio"
                    assert law.params[0] < 1.0 < law.params[1], name
                    assert len(law.reason) > 40, name
                    seen += 1
                    continue
                lo, hi = law.params
                assert lo <= getattr(entry, field) <= hi, (name, field)
                assert len(law.reason) > 40, (name, field)
                seen += 1
    # 5 asperities, 2 restitutions, 4 contact angles, 2 compositions at the time of writing
    assert seen >= 13


def test_a_lognormal_law_has_its_stated_5_and_95_percent_quantiles():
    law = materials.solid("ilmenite").uncertainty[0]
    assert law.law == "lognormal"
    d = law_distribution(law)
    m, s = d.log_params
    ref = stats.lognorm(s=s, scale=math.exp(m))  # an independent implementation
    np.testing.assert_allclose(ref.ppf([0.05, 0.95]), law.params, rtol=1e-12)
    np.testing.assert_allclose(d.ppf(np.array([0.05, 0.95])), law.params, rtol=1e-12)


def _user_file(tmp_path, body):
    p = tmp_path / "mine.toml"
    p.write_text(textwrap.dedent(body))
    return tmp_path


SOLID = """
[solid.my-sand]
assumed = ["asperity_height"]
density = 2650.0
asperity_height = 1e-6
restitution_dry = 0.9
size_range = [100e-6, 1000e-6]
source = "test"
confidence = "test"
"""


def test_a_user_entry_with_an_assumed_number_and_no_law_is_refused_naming_the_field(
        tmp_path):
    with pytest.raises(MaterialsError, match=r"my-sand.*uncertainty\.asperity_height.*"
                                             r"is missing"):
        load(extra_dirs=(str(_user_file(tmp_path, SOLID)),))


@pytest.mark.parametrize("law, match", [
    ('law = "lognormal"\np05 = 2e-6\np95 = 1e-5\nreason = "r"', "outside"),
    ('law = "uniform"\nlo = 0.5e-6\nhi = 0.1e-6\nreason = "r"', "must be greater"),
    ('law = "normal"\np05 = 0.5e-6\np95 = 2e-6\nreason = "r"', "is not one of"),
    ('law = "lognormal"\np05 = 0.5e-6\np95 = 2e-6', "reason.*is missing"),
    ('law = "lognormal"\np05 = 0.0\np95 = 2e-6\nreason = "r"', "p05.*outside the allowed"),
])
def test_a_bad_law_is_refused_naming_it(tmp_path, law, match):
    body = SOLID + "\n[solid.my-sand.uncertainty.asperity_height]\n" + law + "\n"
    with pytest.raises(MaterialsError, match=match):
        load(extra_dirs=(str(_user_file(tmp_path, body)),))


def test_a_law_for_a_value_not_marked_assumed_is_refused(tmp_path):
    body = (SOLID + '\n[solid.my-sand.uncertainty.asperity_height]\nlaw = "uniform"\n'
            'lo = 0.5e-6\nhi = 2e-6\nreason = "r"\n'
            '\n[solid.my-sand.uncertainty.density]\nlaw = "uniform"\nlo = 2600.0\n'
            'hi = 2700.0\nreason = "r"\n')
    with pytest.raises(MaterialsError, match="only a field listed in assumed"):
        load(extra_dirs=(str(_user_file(tmp_path, body)),))


def test_assumed_draws_follow_the_scene():
    base = at.Scene(liquid="k-silicate-ash-melt", T=1123.15, solid_i="silica-sand",
                    solid_j="ilmenite", d_i=300e-6).values()
    inputs, not_drawn = assumed_draws(base)
    assert list(inputs) == ["solid silica-sand asperity_height",
                            "solid ilmenite asperity_height",
                            "solid ilmenite restitution_dry",
                            "liquid k-silicate-ash-melt theta_deg",
                            "liquid k-silicate-ash-melt composition_wt SiO2",
                            "liquid k-silicate-ash-melt composition_wt K2O",
                            "liquid k-silicate-ash-melt composition_wt CaO",
                            "model excess-gas fluctuation_ratio",
                            "model speed choice",
                            "model bubble wake_fraction"]
    assert not_drawn == []
    # values the scene sets, or the caller makes uncertain, are not drawn
    inputs, _ = assumed_draws({**base, "ha_i": 1e-6, "fluctuation_ratio": 2.0},
                              given=("theta_deg",))
    assert list(inputs) == ["solid ilmenite asperity_height", "solid ilmenite restitution_dry",
                            "liquid k-silicate-ash-melt composition_wt SiO2",
                            "liquid k-silicate-ash-melt composition_wt K2O",
                            "liquid k-silicate-ash-melt composition_wt CaO"]
    # the speed estimate's coefficient only where the scene uses that estimate
    inputs, _ = assumed_draws({**base, "speed": "lognormal", "u0": 0.1})
    assert "model excess-gas fluctuation_ratio" not in inputs
    # e is the mean of the two solids' values, drawn or from the database (sand: 0.9)
    out = scene_fields(base, {"solid ilmenite restitution_dry": np.array([0.7, 0.95])})
    np.testing.assert_allclose(out["e"], [0.8, 0.925])


def test_a_solid_is_one_draw_for_both_particles_and_options_share_their_draws():
    same = at.monte_carlo(GLASS, uncertain="assumed", n=300, seed=5)
    np.testing.assert_array_equal(same.ha_i.values, same.ha_j.values)
    sand = at.Scene(liquid="water", T=323.15, h0=5e-6, solid_i="silica-sand", d_i=300e-6,
                    U_Umf=2.0)
    a = at.monte_carlo(sand.replace(solid_j="ilmenite"), uncertain="assumed", n=300, seed=5)
    b = at.monte_carlo(sand.replace(solid_j="olivine"), uncertain="assumed", n=300, seed=5)
    np.testing.assert_array_equal(a.ha_i.values, b.ha_i.values)  # the sand's own draws
    assert not np.array_equal(a.ha_j.values, b.ha_j.values)  # two ores, two streams


def test_the_scene_monte_carlo_answers_the_maps_question():
    """Degenerate inputs: the mean propensity over the draws is the map's propensity at the
    point (within 3 standard errors; here the draws are all alike, so the error is ~0 and
    the bound is the floating-point noise of h0's 1e-12 m spread)."""
    m = at.sweep(GLASS, h0=[5e-6])
    p_map = float(m.propensity.values.ravel()[0])
    assert 0.05 < p_map < 0.95  # a point inside the window, not a trivial 0 or 1
    ds = at.monte_carlo(GLASS, uncertain={"h0": at.Normal(5e-6, 1e-12)}, n=2000, seed=1)
    assert float(ds.propensity_nominal) == p_map
    assert float(ds.u_star_nominal) == float(m.u_star.values.ravel()[0])
    assert abs(float(ds.propensity_mean) - p_map) <= 3 * float(ds.propensity_se) + 1e-8
    # a real spread: the mean lies within 3 standard errors of the mean of the samples
    wide = at.monte_carlo(GLASS, uncertain={"h0": at.Uniform(2e-6, 8e-6)}, n=4000, seed=2)
    assert float(wide.propensity_quantile.sel(quantile=0.05)) < float(
        wide.propensity_quantile.sel(quantile=0.95))
    np.testing.assert_allclose(float(wide.propensity_mean), wide.propensity.values.mean())


@pytest.mark.parametrize("uncertain, match", [
    ("assume", "the one word allowed is 'assumed'"),
    ({"assumed": "yes"}, "must be True or False"),
    ({"assumed": False}, "names no uncertain input"),
    ({"ha": at.Uniform(0.1e-6, 1e-6)}, "'ha' is not a numeric Scene field"),
])
def test_bad_uncertain_is_refused_naming_it(uncertain, match):
    with pytest.raises(ValueError, match=match):
        at.monte_carlo(GLASS, uncertain=uncertain, n=10)


def test_assumed_with_nothing_to_draw_is_refused():
    scene = GLASS.replace(ha_i=0.5e-6, ha_j=0.5e-6, theta_deg=10.0, fluctuation_ratio=1.5)
    with pytest.raises(ValueError, match="uses no assumed database value"):
        at.monte_carlo(scene, uncertain="assumed", n=10)


BIOMASS = at.Scene(liquid="k-silicate-ash-melt", T=1123.15, solid_i="silica-sand",
                   d_i=300e-6, h0=0.2e-6, U_Umf=3.0)


def test_compare_pairs_the_draws_and_names_the_deciding_input():
    ds = at.compare(BIOMASS, solid_j=["silica-sand", "ilmenite", "olivine"], n=2048, seed=0)
    assert list(ds.option.values) == ["silica-sand", "ilmenite", "olivine"]
    p_lower, p_equal = ds.p_lower.values, ds.p_equal.values
    # a probability law over the three outcomes of each pair, and symmetric ties
    np.testing.assert_allclose(p_lower + p_lower.T + p_equal, 1.0)
    np.testing.assert_array_equal(p_equal, p_equal.T)
    # the mean propensities agree with the Scene Monte Carlo of each option, same seed
    ilm = at.monte_carlo(BIOMASS.replace(solid_j="ilmenite"), uncertain="assumed", n=2048,
                         seed=0)
    assert float(ds.propensity_mean.sel(option="ilmenite")) == float(ilm.propensity_mean)
    # p_lower recomputed from the paired samples themselves
    sand = at.monte_carlo(BIOMASS.replace(solid_j="silica-sand"), uncertain="assumed",
                          n=2048, seed=0)
    expect = np.mean(ilm.propensity.values < sand.propensity.values)
    assert float(ds.p_lower.sel(option="ilmenite", other="silica-sand")) == expect
    assert ds.deciding_input.sel(option="ilmenite", other="silica-sand").item().startswith(
        "solid_")
    assert len(ds.attrs["verdicts"].splitlines()) == 3


def test_the_sensitivity_of_a_difference_finds_the_input_that_drives_it():
    from agglomtool.uncertainty.compare import _first_order

    rng = np.random.default_rng(0)
    x1, x2 = rng.uniform(size=20000), rng.uniform(size=20000)
    d = x1  # d depends on x1 only: S1 = 1, S2 = 0. Binning loses the within-bin variance:
    # bins of width 1/16 of a uniform hold (1/16)^2/12 of its 1/12, so the estimate is
    # 1 - 1/256 (to sampling noise)
    assert abs(_first_order(x1, d, 16) - (1.0 - 1.0 / 256)) < 2e-3
    assert _first_order(x2, d, 16) < 0.01
    d = x1 + x2  # additive, equal variances: S = 1/2 each
    assert abs(_first_order(x1, d, 32) - 0.5) < 0.02


def test_a_verdict_is_decided_only_past_the_threshold():
    from agglomtool.uncertainty.compare import verdicts

    def fake(p_ab, p_ba):
        import xarray as xr
        lo = np.array([[0.0, p_ab], [p_ba, 0.0]])
        eq = 1.0 - lo - lo.T
        np.fill_diagonal(eq, 1.0)
        return xr.Dataset({
            "p_lower": (("option", "other"), lo), "p_equal": (("option", "other"), eq),
            "deciding_input": (("option", "other"), np.array([["", "h0"], ["h0", ""]])),
            "deciding_index": (("option", "other"), np.array([[0.0, 0.8], [0.8, 0.0]]))},
            coords={"option": ["a", "b"], "other": ["a", "b"]})

    assert fake(0.97, 0.01).pipe(verdicts) == [
        "decided: a sticks less than b in 97 % of plausible inputs, as much in 2 %, more "
        "in 1 %."]
    assert fake(0.03, 0.6).pipe(verdicts)[0].startswith(
        "not decided (a decision needs 90 %): b sticks less than a in 60 %")
    # a share just below the threshold is not printed as the threshold, and a verdict
    # within Monte Carlo error of it says so (n = 4096: standard error 0.48 %)
    near = fake(0.896, 0.05).assign_attrs(n_samples_per_option=4096)
    assert "in 89.6 % of plausible" in verdicts(near)[0]
    assert "within 3 Monte Carlo standard errors, 0.5 %, of 90 %" in verdicts(near)[0]
    far = fake(0.70, 0.05).assign_attrs(n_samples_per_option=4096)
    assert "Monte Carlo" not in verdicts(far)[0]
    assert "depends on h0 (first-order index 0.80)" in fake(0.03, 0.6).pipe(verdicts)[0]


@pytest.mark.parametrize("kw, match", [
    ({}, "exactly one field"),
    ({"solid_j": ["ilmenite"]}, "at least two options"),
    ({"solid_j": ["ilmenite", "ilmenite"]}, "options repeat"),
    ({"solid_j": ["ilmenite", "granite"]}, "option 'granite'"),
    ({"solid": ["ilmenite", "olivine"]}, "'solid' is not a Scene field"),
    ({"solid_j": ["ilmenite", "olivine"], "h0": [1e-6, 2e-6]}, "exactly one field"),
])
def test_compare_refuses_bad_options_naming_them(kw, match):
    with pytest.raises(ValueError, match=match):
        at.compare(BIOMASS, n=16, **kw)


def test_compare_refuses_bad_counts():
    with pytest.raises(ValueError, match="n = 0 must be a positive integer"):
        at.compare(BIOMASS, solid_j=["ilmenite", "olivine"], n=0)
    with pytest.raises(ValueError, match="bins = 1 must be"):
        at.compare(BIOMASS, solid_j=["ilmenite", "olivine"], n=16, bins=1)


def test_the_docs_table_of_assumed_laws_is_the_database():
    """docs/confidence.md lists every law of the database with its numbers (and no other)."""
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "confidence.md").read_text()
    rows = {line for line in page.splitlines() if line.startswith(("| solid `",
                                                                   "| liquid `"))}
    scale = {"asperity_height": (1e6, " um"), "restitution_dry": (1.0, ""),
             "theta_deg": (1.0, " deg")}
    expect = set()
    for kind, look in (("solid", materials.solid), ("liquid", materials.liquid_entry)):
        for name in materials.names(kind):
            entry = look(name)
            for law in entry.uncertainty:
                if law.law == "logratio":  # a composition: its factors, no unit
                    a, b = law.params
                    expect.add(f"| {kind} `{name}` | `{law.field}` | "
                               + ", ".join(f"{k} {w:g}" for k, w in
                                           entry.composition_wt.items())
                               + f" wt % | each oxide's share times a lognormal factor, "
                               f"5-95 %: {a:g}-{b:g}; rescaled to 100 wt % |")
                    continue
                f, u = scale[law.field]
                a, b = law.params
                text = (f"lognormal, 5-95 %: {a * f:g}-{b * f:g}{u}" if law.law == "lognormal"
                        else f"uniform on [{a * f:g}, {b * f:g}]{u}")
                expect.add(f"| {kind} `{name}` | `{law.field}` | "
                           f"{getattr(entry, law.field) * f:g}{u} | {text} |")
    assert rows == expect


def test_sobol_refuses_assumed_with_the_way_out():
    with pytest.raises(ValueError, match="'assumed' is for monte_carlo, compare"):
        at.sobol_indices(GLASS, uncertain="assumed", n_base=8)


def test_a_field_left_at_its_default_and_drawn_takes_its_laws_nominal():
    """A water scene whose T the user never set (the Scene's 1073.15 K default, outside
    water's range) with T drawn: every draw is a water temperature, and the nominal answer
    is the map's value at the law's nominal T, not at the default (which raised)."""
    scene = at.Scene(liquid="water", h0=5e-6, d_i=300e-6, U_Umf=2.0)
    ds = at.monte_carlo(scene, uncertain={"T": at.Normal(320.0, 5.0)}, n=400, seed=3)
    m = at.sweep(scene.replace(T=320.0), h0=[5e-6])
    assert float(ds.propensity_nominal) == float(m.propensity.values.ravel()[0])
    assert float(ds.u_star_nominal) == float(m.u_star.values.ravel()[0])
    # a T the user set stays the nominal, whatever the law's centre
    set_t = at.monte_carlo(scene.replace(T=330.0), uncertain={"T": at.Normal(320.0, 5.0)},
                           n=400, seed=3)
    m330 = at.sweep(scene.replace(T=330.0), h0=[5e-6])
    assert float(set_t.u_star_nominal) == float(m330.u_star.values.ravel()[0])


def test_no_valid_speed_model_to_draw_says_why():
    """U below U_mf with the model choice drawn: 'no impact-speed model of the registry is
    valid at this scene' said nothing of the bed not being fluidized."""
    scene = at.Scene(liquid="water", T=298.15, h0=5e-6, U_Umf=0.8, solid_i="silica-sand",
                     d_i=300e-6)
    with pytest.raises(ValueError, match=r"no impact-speed model .* valid.*the scene's own "
                                         r"\(excess-gas\): U = .* does not exceed U_mf"):
        at.monte_carlo(scene, uncertain="assumed", n=16, seed=0)
