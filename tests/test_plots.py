"""Pictures that never hide a dimension (a facet or an axis for each, or an error)."""

import matplotlib
import numpy as np
import pytest

import agglomtool as at
from agglomtool.plots import operating_window, plan_layout

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def ds4():
    s = at.Scene(liquid="water", T=298.15, h0=5e-6)
    return at.sweep(s, solid_j=["silica-sand", "ilmenite"], U_Umf=[2.0, 3.0, 5.0],
                    h0=np.geomspace(1e-6, 100e-6, 5), d_i=[300e-6, 550e-6, 800e-6])


def _titles(fig):
    return sorted(ax.get_title() for ax in fig.axes if ax.get_title() and ax.get_visible())


def test_four_dims_one_panel_per_facet_with_readable_titles(ds4):
    fig = operating_window(ds4)
    titles = _titles(fig)
    assert len(titles) == 2 * 3
    assert "d_i = 550 um, solid_j = ilmenite" in titles
    assert "d_i = 300 um, solid_j = silica-sand" in titles
    assert fig.layout.x == "h0" and fig.layout.y == "U_Umf"
    assert {fig.layout.col, fig.layout.row} == {"solid_j", "d_i"}
    # u0* contours on every panel (u0* does not depend on U_Umf: it is broadcast)
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert all(ax.collections for ax in panels)


def test_comparison_panels_are_titled_by_their_own_material(ds4):
    fig = operating_window(ds4, col="solid_j", sel={"d_i": 550e-6})
    assert _titles(fig) == ["solid_j = ilmenite", "solid_j = silica-sand"]
    assert "d_i = 550 um" in fig._suptitle.get_text()


def test_a_dimension_that_cannot_be_shown_is_refused_not_hidden():
    s = at.Scene(liquid="water", T=298.15, u0=0.1)
    ds = at.sweep(s, h0=np.geomspace(1e-6, 50e-6, 4), U_Umf=[2.0, 3.0],
                  d_i=np.linspace(200e-6, 900e-6, 11), T=np.linspace(293.15, 353.15, 12))
    with pytest.raises(ValueError, match=r"would be hidden.*sel"):
        plan_layout(ds)
    lay = plan_layout(ds, sel={"T": float(ds.T[3])}, col="d_i", x="h0", y="U_Umf")
    assert lay.col == "d_i" and "T" in lay.sel
    with pytest.raises(ValueError, match="not a grid value"):
        operating_window(ds, sel={"T": 300.0}, col="d_i", x="h0", y="U_Umf")


def test_categorical_variable_gets_discrete_colours_and_a_legend(ds4):
    fig = operating_window(ds4, "stage", sel={"d_i": 300e-6})
    labels = [t.get_text() for lg in fig.legends for t in lg.get_texts()]
    assert "rebound" in labels
    assert not any(ax.get_label() == "<colorbar>" for ax in fig.axes)


def test_region_above_the_ceiling_is_labelled():
    s = at.Scene(liquid="k-silicate-ash-melt", gas="biomass-flue-gas")
    ds = at.sweep(s, T=[1173.15, 1473.15, 1673.15], h0=[0.11e-6, 0.3e-6, 1e-6])
    fig = operating_window(ds)
    labels = [t.get_text() for lg in fig.legends for t in lg.get_texts()]
    assert any("up to the u0* ceiling (10 m/s)" in t for t in labels)


def test_missing_map_file_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        operating_window(tmp_path / "nothere.nc")
    bad = tmp_path / "bad.nc"
    bad.write_text("not a netcdf")
    with pytest.raises(ValueError, match="not a readable netCDF map"):
        operating_window(bad)
