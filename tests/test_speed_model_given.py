"""A speed model the user names is given, not assumed: ``uncertain="assumed"`` draws the
model only where the scene leaves ``speed`` at its default (None), and still draws the
chosen model's own coefficient where the user left that at its default."""

import warnings

import numpy as np
import pytest

import agglomtool as at

SAND = dict(T=300.0, gas="air", liquid="water", h0=10e-6, d_i=400e-6, U_Umf=3.0)
CHOICE = "model speed choice"
K = "model excess-gas fluctuation_ratio"
WAKE = "model bubble wake_fraction"


def _mc(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        return at.monte_carlo(scene, uncertain="assumed", n=16, seed=3)


def _drawn(ds):
    return [part.split(":")[0] for part in ds.attrs["assumed_drawn"].split("; ")]


def test_the_default_estimate_draws_the_model():
    ds = _mc(at.Scene(**SAND))
    assert CHOICE in _drawn(ds) and K in _drawn(ds)


def test_a_named_excess_gas_estimate_is_given_its_coefficient_drawn():
    ds = _mc(at.Scene(**SAND, speed="excess-gas"))
    assert CHOICE not in _drawn(ds) and K in _drawn(ds)
    assert (ds.attrs["assumed_not_drawn"].count("speed = 'excess-gas'") == 1
            and "given" in ds.attrs["assumed_not_drawn"])
    # every draw used the named model: no draw has another model's propensity
    assert "speed" not in ds.attrs["uncertain_inputs"].split()


def test_a_named_bubble_model_is_given_its_wake_fraction_drawn():
    ds = _mc(at.Scene(**SAND, speed="bubble-darton"))
    assert CHOICE not in _drawn(ds) and WAKE in _drawn(ds) and K not in _drawn(ds)
    assert "speed = 'bubble-darton'" in ds.attrs["assumed_not_drawn"]


def test_coefficients_the_user_gives_are_not_drawn_either():
    ds = _mc(at.Scene(**SAND, speed="excess-gas", fluctuation_ratio=0.5))
    assert CHOICE not in _drawn(ds) and K not in _drawn(ds)


def test_replace_keeps_whether_the_model_was_named():
    named = at.Scene(**SAND, speed="excess-gas").replace(h0=5e-6)
    assert CHOICE not in _drawn(_mc(named))
    default = at.Scene(**SAND).replace(h0=5e-6)
    assert CHOICE in _drawn(_mc(default))
    # naming it in replace names it
    assert CHOICE not in _drawn(_mc(at.Scene(**SAND).replace(speed="excess-gas")))


def test_compare_and_robust_maps_keep_a_named_model():
    scene = at.Scene(**SAND, speed="excess-gas")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        cmp = at.compare(scene, n=16, solid_j=["silica-sand", "ilmenite"])
        assert CHOICE not in cmp.attrs.get("assumed_drawn", "")
        ds = at.sweep(scene, uncertain="assumed", samples=4, h0=[5e-6, 10e-6])
    assert CHOICE not in [p.split(" = ")[0] for p in
                          ds.attrs["robust_uncertain_inputs"].split("; ")]
    assert "speed = 'excess-gas'" in ds.attrs["robust_assumed_not_drawn"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        dflt = at.sweep(at.Scene(**SAND), uncertain="assumed", samples=4, h0=[5e-6, 10e-6])
    assert CHOICE in [p.split(" = ")[0] for p in
                      dflt.attrs["robust_uncertain_inputs"].split("; ")]


def test_the_cli_assumed_list_says_the_model_is_given(capsys):
    from agglomtool.cli import main

    args = ["collide", "--liquid", "water", "--T", "300", "--h0", "10e-6", "--d-i",
            "400e-6"]
    assert main([*args, "--speed", "excess-gas"]) == 0
    out = capsys.readouterr().out
    assert "speed = 'excess-gas'" in out and "given" in out
    assert main(args) == 0
    assert "speed = 'excess-gas'" not in capsys.readouterr().out


@pytest.mark.parametrize("speed", [None, "excess-gas"])
def test_the_scene_is_otherwise_the_same(speed):
    """Naming the default model changes nothing but the draw: the same values, equal."""
    a, b = at.Scene(**SAND), at.Scene(**SAND, speed=speed)
    assert a == b and a.values() == b.values()
    np.testing.assert_array_equal(a.evaluate()["propensity"], b.evaluate()["propensity"])
