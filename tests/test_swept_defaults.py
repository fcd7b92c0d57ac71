"""Plausibility warnings are about the values used: a Scene's default that a map sweeps
(or a Monte Carlo draws) is never judged; one that is used is, when it is used."""

import re
import warnings

import numpy as np
import pytest

import agglomtool as at
from agglomtool import PlausibilityWarning

WATER = dict(liquid="water", h0=5e-6, d_i=300e-6)  # T left at its default, 1073.15 K


def _said(func):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        out = func()
    return out, [str(w.message) for w in rec if issubclass(w.category, PlausibilityWarning)]


def test_a_swept_temperature_is_judged_at_its_values_not_at_the_default():
    ds, said = _said(lambda: at.sweep(at.Scene(**WATER), T=np.linspace(300, 350, 3)))
    assert not [m for m in said if "1073.15" in m], said
    assert np.isfinite(ds.propensity.values).all()
    # the swept values themselves are judged
    _, said = _said(lambda: at.sweep(at.Scene(**WATER), d_i=[300e-6, 3e-3], T=[300.0]))
    assert [m for m in said if re.match(r"d_i = 0.003 m is above the typical size", m)]


ILMENITE = dict(solid_i="ilmenite", liquid="water", T=300.0, h0=5e-6)  # d_i 0.5 mm: large
BIG = "d_i = 0.0005 m is above the typical size range of ilmenite"


def test_the_default_is_judged_where_it_is_used():
    _, said = _said(lambda: at.sweep(at.Scene(**ILMENITE), h0=[2e-6, 5e-6]))
    assert [m for m in said if m.startswith(BIG)], said
    for use in ("collide", "evaluate"):
        _, said = _said(getattr(at.Scene(**ILMENITE), use))
        assert [m for m in said if m.startswith(BIG)], said
    # water at the default 1073.15 K is refused where it is used, naming the default
    with pytest.raises(ValueError, match="T = 1073.15 K is the Scene's default: set T"):
        at.sweep(at.Scene(**WATER), h0=[2e-6, 5e-6])


def test_a_value_the_user_types_is_judged_at_once():
    _, said = _said(lambda: at.Scene(**WATER, T=383.15))
    assert [m for m in said if m.startswith("T = 383.15 K")]


@pytest.mark.parametrize("scene, grid, word", [
    (dict(solid_i="ilmenite", liquid="water", T=300.0, h0=5e-6), dict(d_i=[200e-6, 300e-6]),
     "d_i = 0.0005 m"),
    (dict(solid_j="ilmenite", liquid="water", T=300.0, h0=5e-6), dict(d_i=[200e-6, 300e-6]),
     "d_j (= d_i) = 0.0005 m"),
])
def test_every_swept_field_with_a_check(scene, grid, word):
    """The default d_i (0.5 mm) is above ilmenite's sizes: said for a Scene that uses it,
    not for a map that sweeps d_i within them."""
    _, said = _said(lambda: at.sweep(at.Scene(**scene), **grid))
    assert not [m for m in said if word in m], said
    _, said = _said(lambda: at.Scene(**scene).collide())
    assert [m for m in said if word in m], said


def test_a_monte_carlo_drawing_the_default_does_not_judge_it():
    scene = at.Scene(**ILMENITE)
    _, said = _said(lambda: at.monte_carlo(scene, uncertain={"d_i": at.Uniform(2e-4, 3e-4)},
                                           n=8))
    assert not [m for m in said if m.startswith(BIG)], said
    _, said = _said(lambda: at.monte_carlo(scene, uncertain={"h0": at.Uniform(4e-6, 6e-6)},
                                           n=8))
    assert [m for m in said if m.startswith(BIG)], said
