"""A melt's assumed composition drawn as an uncertain input (issue: answers with their
confidence): the melt models vectorised over compositions, the database's log-ratio law,
and the Monte Carlo, compare and robust maps drawing it."""

import math
import warnings

import numpy as np
import pytest
from scipy.special import ndtri

import agglomtool as at
from agglomtool import materials
from agglomtool.materials import MaterialsError, load
from agglomtool.properties import melt
from agglomtool.properties.slag_composition import normalise_wt
from agglomtool.properties.slag_surface import density_mills_keene, surface_tension_mills
from agglomtool.properties.slag_viscosity import (
    viscosity_giordano_russell_dingwell,
    viscosity_riboud,
    viscosity_urbain_mills,
)
from agglomtool.scene import COMPOSITION_KEY, Resolved
from agglomtool.uncertainty.assumed import assumed_draws, drawn_composition, scene_fields

MODELS = (viscosity_giordano_russell_dingwell, viscosity_urbain_mills, viscosity_riboud,
          surface_tension_mills)


def _compositions(n, seed=3, caf2=True):
    """``n`` compositions around a K-Ca silicate (with a little CaF2: every model has
    terms for most of it), each rescaled to 100 wt %, and temperatures."""
    base = {"SiO2": 52.0, "CaO": 20.0, "K2O": 14.0, "MgO": 5.0, "Al2O3": 4.0,
            "Na2O": 2.0, "Fe2O3": 2.0, "CaF2": 1.0}
    if not caf2:  # Mills-Keene has no partial molar volume for CaF2
        base["CaO"] += base.pop("CaF2")
    rng = np.random.default_rng(seed)
    f = {k: v * np.exp(0.4 * rng.standard_normal(n)) for k, v in base.items()}
    total = sum(f.values())
    return {k: 100.0 * v / total for k, v in f.items()}, rng.uniform(1300.0, 1800.0, n)


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.parametrize("model", MODELS, ids=lambda f: f.__name__)
def test_array_compositions_give_each_element_its_own_scalar_answer(model):
    """One call over 40 compositions equals 40 calls of one composition each, to the last
    bit or one rounding (the same arithmetic, reduced in the same order)."""
    comp, T = _compositions(40)
    together = model(comp, T)
    one_by_one = [float(model({k: float(v[i]) for k, v in comp.items()}, T[i]))
                  for i in range(T.size)]
    np.testing.assert_allclose(together, one_by_one, rtol=4e-16, atol=0.0)


def test_array_density_and_the_rule_per_element():
    comp, T = _compositions(40, caf2=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rho = density_mills_keene(comp, T)
        chosen = melt.choose_viscosity_model(comp)
    for i in range(T.size):
        one = {k: float(v[i]) for k, v in comp.items()}
        assert rho[i] == pytest.approx(float(density_mills_keene(one, T[i])), rel=4e-16)
        assert chosen[i] == melt.choose_viscosity_model(one)
    assert set(chosen) == {"grd", "urbain-mills"}  # the draws straddle SiO2 = 50 wt %


def test_melt_liquid_at_many_compositions_uses_each_ones_model():
    comp, T = _compositions(30, caf2=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        liq = melt.melt_liquid(comp, T)
        for i in range(T.size):
            one = melt.melt_liquid({k: float(v[i]) for k, v in comp.items()}, T[i])
            assert liq.mu[i] == pytest.approx(float(one.mu), rel=4e-16)
            assert liq.gamma[i] == pytest.approx(float(one.gamma), rel=4e-16)
    assert "compositions" in liq.source  # says how many took each model


def test_a_composition_of_arrays_is_checked_element_by_element():
    with pytest.raises(ValueError, match=r"sums to 60 wt % in 1 of 2 elements"):
        normalise_wt({"SiO2": np.array([60.0, 70.0]), "CaO": np.array([0.0, 30.0])})
    with pytest.raises(ValueError, match=r"composition\['CaO'\] = -1"):
        normalise_wt({"SiO2": np.array([60.0, 70.0]), "CaO": np.array([-1.0, 30.0])})


def test_the_glass_refusal_counts_the_glassy_draws():
    comp = {"SiO2": np.array([75.0, 75.0]), "K2O": np.array([15.0, 15.0]),
            "CaO": np.array([10.0, 10.0])}
    with pytest.raises(ValueError, match=r"VFT temperature .* \(1 of 2 compositions and T\)"):
        viscosity_giordano_russell_dingwell(comp, np.array([200.0, 1200.0]))


# --- the database's law -------------------------------------------------------------------

def _user_file(tmp_path, body):
    d = tmp_path / "db"
    d.mkdir()
    (d / "liquids.toml").write_text(body)
    return d


MELT = ('[liquid.my-melt]\nmodel = "melt"\ntheta_deg = 10.0\nassumed = ["composition_wt"]\n'
        'composition_wt = {SiO2 = 70.0, K2O = 20.0, CaO = 10.0}\nsource = "s"\n'
        'confidence = "c"\n')


@pytest.mark.parametrize("law, match", [
    ("", r"'uncertainty.composition_wt': is missing: .*law = 'logratio'"),
    ('law = "lognormal"\np05 = 0.5\np95 = 2.0\nreason = "r"\n',
     "'lognormal' is not a law of composition_wt .*allowed: logratio"),
    ('law = "logratio"\nfactor_p05 = 1.2\nfactor_p95 = 2.0\nreason = "r"\n', "must hold 1"),
    ('law = "logratio"\nfactor_p05 = 0.0\nfactor_p95 = 2.0\nreason = "r"\n', "factor_p05"),
])
def test_the_loader_refuses_a_composition_law_it_cannot_draw(tmp_path, law, match):
    body = MELT + (f"[liquid.my-melt.uncertainty.composition_wt]\n{law}" if law else "")
    with pytest.raises(MaterialsError, match=match):
        load(extra_dirs=(str(_user_file(tmp_path, body)),))


def test_a_number_cannot_take_the_composition_law(tmp_path):
    body = (MELT.replace('["composition_wt"]', '["theta_deg"]')
            + '[liquid.my-melt.uncertainty.theta_deg]\nlaw = "logratio"\nfactor_p05 = 0.5\n'
              'factor_p95 = 2.0\nreason = "r"\n')
    with pytest.raises(MaterialsError, match="'logratio' is not a law of theta_deg"):
        load(extra_dirs=(str(_user_file(tmp_path, body)),))


# --- the draws ----------------------------------------------------------------------------

SCENE = at.Scene(liquid="k-silicate-ash-melt", T=1123.15, h0=2e-6, solid_i="silica-sand",
                 theta_deg=10.0, ha_i=1e-7)  # only the composition (and speed) left assumed


def test_each_oxide_is_an_input_of_its_own_and_nothing_is_left_undrawn():
    inputs, not_drawn = assumed_draws(SCENE.values())
    oxides = [k.split()[-1] for k in inputs if "composition_wt" in k]
    assert oxides == ["SiO2", "K2O", "CaO"]
    assert not_drawn == []
    law = materials.liquid_entry("k-silicate-ash-melt").uncertainty[0]
    assert law.law == "logratio"
    d = inputs["liquid k-silicate-ash-melt composition_wt K2O"].dist
    np.testing.assert_allclose(d.ppf(np.array([0.05, 0.95])), law.params, rtol=1e-12)


def test_factors_of_one_give_the_database_composition_and_its_properties():
    base = dict(materials.liquid_entry("k-silicate-ash-melt").composition_wt)
    ones = {k: np.ones(3) for k in base}
    comp = drawn_composition(base, ones)
    for k, w in base.items():
        np.testing.assert_array_equal(comp[k], w)  # the database's sums to 100 exactly
    values = SCENE.values()
    T = np.array([1073.15, 1123.15, 1173.15])
    plain = Resolved({**values, "T": T}).liquid
    drawn = Resolved({**values, "T": T, COMPOSITION_KEY: comp}).liquid
    for name in ("mu", "gamma", "rho"):
        np.testing.assert_allclose(getattr(drawn, name), getattr(plain, name), rtol=4e-16)


def test_the_drawn_compositions_follow_the_stated_law():
    """Independent of the drawing code: each pair of oxides' log-ratio is normal with the
    standard deviation sqrt(2) ln(p95) / z95 that the stated factors imply (the rescaling
    cancels in a ratio), and every draw sums to 100 wt %."""
    ds = at.monte_carlo(SCENE, uncertain="assumed", n=20000, seed=5, keep_samples=True)
    si, k = ds["composition_wt_SiO2"].values, ds["composition_wt_K2O"].values
    total = si + k + ds["composition_wt_CaO"].values
    np.testing.assert_allclose(total, 100.0, rtol=1e-12)
    lo, hi = materials.liquid_entry("k-silicate-ash-melt").uncertainty[0].params
    sigma = math.log(hi / lo) / (2.0 * ndtri(0.95))
    r = np.log(si / k)
    # 20000 draws: the sample sd within 3 % of the law's (its standard error is 0.5 %)
    assert np.std(r) == pytest.approx(math.sqrt(2.0) * sigma, rel=0.03)
    assert np.median(r) == pytest.approx(math.log(70.0 / 20.0), abs=0.02)


def test_the_composition_moves_the_answer_and_a_comparison_can_name_an_oxide():
    """With every other assumed value fixed, the composition alone spreads u0* (the melt's
    viscosity spans decades over the law), and compare's sentence names the oxide."""
    ds = at.monte_carlo(SCENE.replace(speed="lognormal", u0=0.3), uncertain="assumed",
                        n=2000, seed=2)
    q = ds["u_star_quantile"].sel(quantile=[0.05, 0.95]).values
    assert q[0] < q[1]
    from agglomtool.uncertainty.compare import _input_text

    assert _input_text("liquid_k-silicate-ash-melt_composition_wt_K2O") == (
        "the K2O content of k-silicate-ash-melt (its composition, which the database "
        "assumes)")


def test_scene_fields_carry_the_composition_and_robust_maps_draw_it():
    comp = scene_fields(SCENE.values(), {
        "liquid k-silicate-ash-melt composition_wt K2O": np.array([1.0, 2.0])})[COMPOSITION_KEY]
    np.testing.assert_allclose(comp["K2O"], [20.0, 100.0 * 40.0 / 120.0])
    ds = at.sweep(SCENE, T=np.array([1073.15, 1173.15]), uncertain="assumed", samples=64,
                  seed=1)
    assert "liquid k-silicate-ash-melt composition_wt K2O" in ds.attrs["robust_uncertain_inputs"]
    assert ds.attrs["robust_assumed_not_drawn"] == "none"
    assert np.all((ds["p_unsafe"].values >= 0.0) & (ds["p_unsafe"].values <= 1.0))
