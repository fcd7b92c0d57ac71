"""The impact-speed model as an uncertain input (``uncertain="assumed"``) and as a swept
dimension of a map."""

import warnings

import numpy as np
import pytest

import agglomtool as at
from agglomtool.bed.speed_models import IMPACT_SPEED_MODELS, choice_weights
from agglomtool.uncertainty.assumed import assumed_draws, scene_fields, speed_model_weights

SAND = dict(T=300.0, gas="air", liquid="water", h0=10e-6, d_i=400e-6, U_Umf=3.0)
ALL = list(IMPACT_SPEED_MODELS)


def test_each_mechanism_weighs_the_same_and_its_correlations_share_it():
    """The stated rule: three mechanisms, a third each; the two bubble-size correlations
    share the bubble-wake third; a mechanism with one valid correlation keeps its share."""
    w = choice_weights(ALL)
    assert w == pytest.approx({"excess-gas": 1 / 3, "bubble-darton": 1 / 6,
                               "bubble-mori-wen": 1 / 6, "collisional-balance": 1 / 3})
    assert choice_weights(["excess-gas", "bubble-darton"]) == pytest.approx(
        {"excess-gas": 0.5, "bubble-darton": 0.5})
    with pytest.raises(ValueError, match="no impact-speed model"):
        choice_weights(["fixed"])


def test_the_models_drawn_are_those_valid_at_the_scene():
    scene = at.Scene(**SAND)
    assert list(speed_model_weights(scene.values())) == at.impact_speed_methods(scene)
    # 0.5 mm sand is outside Mori and Wen's particle sizes: Darton takes the bubbles' share
    coarse = at.Scene(**{**SAND, "d_i": 500e-6})
    w = speed_model_weights(coarse.values())
    assert "bubble-mori-wen" not in w and w["bubble-darton"] == pytest.approx(1 / 3)


def test_the_choice_is_drawn_only_where_the_scene_leaves_the_speed_at_its_default():
    base = at.Scene(**SAND).values()
    assert "model speed choice" in assumed_draws(base)[0]
    for other in ({"speed": "bubble-darton"}, {"fluctuation_ratio": 2.0},
                  {"speed": "lognormal", "u0": 0.1}):
        assert "model speed choice" not in assumed_draws({**base, **other})[0]


def test_a_uniform_draw_picks_the_model_by_the_cumulative_weights():
    base = at.Scene(**SAND).values()  # weights 1/3, 1/6, 1/6, 1/3 in the registry's order
    out = scene_fields(base, {"model speed choice": np.array([0.0, 0.33, 0.34, 0.49, 0.51,
                                                              0.66, 0.67, 0.999])})
    assert list(out["speed"]) == ["excess-gas", "excess-gas", "bubble-darton",
                                  "bubble-darton", "bubble-mori-wen", "bubble-mori-wen",
                                  "collisional-balance", "collisional-balance"]


def test_monte_carlo_draws_the_model_and_each_draw_is_its_scene():
    """Every draw's propensity is that of the Scene with the drawn model and the other
    drawn values (recomputed through Scene.evaluate); the models come up with their
    weights (within 4 binomial standard deviations)."""
    scene = at.Scene(**SAND)
    n = 1200
    ds = at.monte_carlo(scene, uncertain="assumed", n=n, seed=3, keep_samples=True)
    names = ds["speed"].values
    w = speed_model_weights(scene.values())
    for name, p in w.items():
        k = int(np.sum(names == name))
        assert abs(k - n * p) < 4 * np.sqrt(n * p * (1 - p)), name
    fields = [f for f in ("ha_i", "ha_j", "theta_deg", "fluctuation_ratio", "e",
                          "wake_fraction")
              if f in ds]
    for name in w:
        i = int(np.flatnonzero(names == name)[0])
        kw = {f: float(ds[f].values[i]) for f in fields}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", at.PlausibilityWarning)
            one = at.Scene(**SAND, speed=name, **kw).evaluate()
        assert float(ds["propensity"].values[i]) == pytest.approx(
            float(one["propensity"]), rel=1e-9, abs=1e-12), name


def test_a_verdict_names_the_model_choice_in_words():
    from agglomtool.uncertainty.compare import _input_text

    assert _input_text("model_speed_choice") == ("the choice of impact-speed model, which is "
                                                 "assumed")


def test_the_window_under_each_model_is_the_sweep_of_each_model(tmp_path):
    """speed_model_windows: one column per model valid at the scene, each the map of the
    scene swept with that model alone; the picture is written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from agglomtool.plots import speed_model_windows

    scene = at.Scene(**SAND)
    grid = dict(h0=np.array([2e-6, 10e-6]), U_Umf=np.array([1.5, 3.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        fig = speed_model_windows(scene, path=tmp_path / "w.png", **grid)
        assert fig.layout.col == "speed"
        assert list(fig.data.speed.values) == at.impact_speed_methods(scene)
        one = at.sweep(scene.replace(speed="bubble-darton"), **grid)
    plt.close(fig)
    np.testing.assert_array_equal(fig.data.propensity.sel(speed="bubble-darton").values,
                                  one.propensity.values)
    assert (tmp_path / "w.png").stat().st_size > 10_000
    with pytest.raises(ValueError, match="speed is the facet"):
        speed_model_windows(scene, speed=["excess-gas"], **grid)
    with pytest.raises(ValueError, match="models = \\['fixed'\\]"):
        speed_model_windows(scene, models=["fixed"], **grid)


def test_the_bubble_models_wake_fraction_is_drawn_where_a_bubble_model_may_be_used():
    """The bubble models' coefficient (wake_fraction, 0.25 by default) is assumed: drawn
    where the scene uses a bubble model, or where the model itself is drawn, and left at
    its default; each draw's propensity is its Scene's (bubble draws)."""
    base = at.Scene(**SAND).values()
    key = "model bubble wake_fraction"
    assert key in assumed_draws(base)[0]
    assert key in assumed_draws({**base, "speed": "bubble-darton"})[0]
    assert key not in assumed_draws({**base, "speed": "bubble-darton",
                                     "wake_fraction": 0.3})[0]
    assert key not in assumed_draws({**base, "speed": "collisional-balance"})[0]
    out = scene_fields(base, {key: np.array([0.2, 0.3])})
    np.testing.assert_array_equal(out["wake_fraction"], [0.2, 0.3])
    ds = at.monte_carlo(at.Scene(**SAND, speed="bubble-darton"), uncertain="assumed",
                        n=64, seed=2, keep_samples=True)
    wf = ds["wake_fraction"].values
    assert np.ptp(wf) > 0.0
    i = int(np.argmax(wf))
    kw = {f: float(ds[f].values[i]) for f in ("ha_i", "ha_j", "theta_deg", "wake_fraction")}
    one = at.Scene(**SAND, speed="bubble-darton", **kw).evaluate()
    assert float(ds["propensity"].values[i]) == pytest.approx(float(one["propensity"]),
                                                              rel=1e-9, abs=1e-12)


@pytest.mark.parametrize("config", ["granulator_window", "sand_vs_ilmenite",
                                    "biomass_window"])
def test_the_readme_pictures_use_the_default_speed_estimate(config):
    """The README's and gallery's granulator, material-comparison and combustor pictures
    are drawn with the default impact-speed estimate, the one docs/speed_models.md
    chooses: their configurations name no speed model and no coefficient of one."""
    from pathlib import Path

    from agglomtool._fields import DEFAULTS
    from agglomtool.maps.config import load_config

    path = Path(__file__).resolve().parent.parent / "examples" / "configs" / f"{config}.toml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        cfg = load_config(path)
    assert cfg.scene.speed == "excess-gas" and "speed" not in cfg.grid
    for name in ("fluctuation_ratio", "wake_fraction", "bed_height", "column_diameter"):
        assert getattr(cfg.scene, name) == DEFAULTS[name] and name not in cfg.grid
