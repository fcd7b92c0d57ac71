"""Sweeps over names in any order and combination, and water maps over valid temperatures
(each of these crashed in an earlier version)."""

import itertools
import json

import numpy as np
import pytest

import agglomtool as at
from agglomtool.scene import Scene

BASE = Scene(u0=0.5, liquid="hypothetical-slag", h0=0.5e-6, d_i=300e-6)
AXES = {
    "solid_j": ["silica-sand", "ilmenite"],
    "mode": ["paper", "relative"],
    "gas": ["air", "nitrogen"],
    "T": [1000.0, 1100.0],
}


@pytest.mark.parametrize("order", [p for k in (1, 2, 3) for p in
                                   itertools.permutations(AXES, k)
                                   if not (k == 3 and "T" not in p)],
                         ids=lambda p: "-".join(p))
def test_any_order_of_names_and_numbers(order):
    ds = at.sweep(BASE, **{k: AXES[k] for k in order})
    assert ds.propensity.dims == tuple(order)
    # Every point equals the scene evaluated alone with the same values.
    idx = {k: len(AXES[k]) - 1 for k in order}
    pt = ds.isel(idx)
    one = BASE.replace(**{k: (str(pt[k].values) if isinstance(AXES[k][0], str)
                              else float(pt[k])) for k in order}).evaluate()
    for name in ("u_star", "e_w", "propensity"):
        assert float(pt[name]) == pytest.approx(float(one[name]), rel=1e-12), name


def test_material_first_and_only_dimension():
    """The designer's question 1: compare bed materials (material as the first dim)."""
    s = Scene(liquid="water", T=298.15, h0=5e-6)
    ds = at.sweep(s, solid_j=["silica-sand", "ilmenite", "olivine"], U_Umf=[2.0, 4.0])
    assert ds.propensity.dims == ("solid_j", "U_Umf")
    assert list(ds.solid_j.values) == ["silica-sand", "ilmenite", "olivine"]
    only = at.sweep(s, solid_i=["silica-sand", "ilmenite"])
    assert only.u_star.dims == ("solid_i",)
    # ilmenite pairs differ from silica pairs: the material really is swept
    assert float(only.u_star[0]) != float(only.u_star[1])


def test_water_map_over_valid_temperatures():
    """The designer's question 2 for water: 20-80 degC, never the unused default T."""
    T = np.linspace(293.15, 353.15, 4)
    ds = at.sweep(Scene(liquid="water", h0=5e-6), T=T, U_Umf=[2.0, 4.0])
    assert ds.propensity.dims == ("T", "U_Umf")
    mu = ds.mu_l.values
    assert np.all(np.diff(mu) < 0.0)  # water thins as it warms
    assert np.all(np.isfinite(ds.u_star.values))
    assert "liquid water" in json.loads(ds.attrs["material_sources"])


def test_water_outside_its_range_names_the_liquid():
    with pytest.raises(ValueError, match=r"water.*T = 1073.15.*273.16"):
        at.sweep(Scene(liquid="water", h0=5e-6), U_Umf=[2.0, 4.0])
    with pytest.raises(ValueError, match=r"water.*T = 700"):
        at.sweep(Scene(liquid="water", h0=5e-6), T=[300.0, 700.0])


def test_default_temperature_is_named_as_the_default():
    with pytest.raises(ValueError, match=r"default"):
        Scene(liquid="water", h0=5e-6).evaluate()
