"""Pictures that never hide a dimension (a facet or an axis for each, or an error)."""

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

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
    # three dimensions too long for a facet (more than 8 values) and two axes
    s = at.Scene(liquid="water", T=298.15, u0=0.1)
    ds = at.sweep(s, h0=np.geomspace(1e-6, 50e-6, 9), U_Umf=[2.0, 3.0],
                  d_i=np.linspace(200e-6, 900e-6, 11), T=np.linspace(293.15, 353.15, 12))
    with pytest.raises(ValueError, match=r"would be hidden.*sel"):
        plan_layout(ds)
    lay = plan_layout(ds, sel={"T": float(ds.T[3])}, col="d_i", x="h0", y="U_Umf")
    assert lay.col == "d_i" and "T" in lay.sel
    with pytest.raises(ValueError, match="not a grid value"):
        operating_window(ds, sel={"T": 300.0}, col="d_i", x="h0", y="U_Umf")


@pytest.mark.parametrize("sizes, axes", [
    # a short numeric dimension (T, 2 values) took the y axis before a long one (U_Umf,
    # 15), which then fitted nowhere: 'would be hidden' for a map every slot could show
    ({"T": 2, "solid_j": 2, "U_Umf": 15, "h0": 15}, {"U_Umf", "h0"}),
    ({"T": 3, "U_Umf": 12, "h0": 12}, {"U_Umf", "h0"}),
    ({"T": 2, "d_i": 3, "U_Umf": 3, "h0": 12}, {"h0"}),
    # where every numeric dimension fits an axis or a facet: as before, T against h0
    ({"T": 5, "h0": 35}, {"T", "h0"}),
    ({"T": 3, "U_Umf": 4, "h0": 5}, {"T", "h0"}),
])
def test_dimensions_too_long_for_a_facet_take_the_axes(sizes, axes):
    values = {"T": np.linspace(293.15, 353.15, 12), "U_Umf": np.linspace(1.5, 8.0, 35),
              "h0": np.geomspace(1e-6, 50e-6, 35), "d_i": np.linspace(2e-4, 9e-4, 12)}
    coords = {k: (k, values[k][:n]) if k in values else (k, ["silica-sand", "ilmenite"][:n])
              for k, n in sizes.items()}
    ds = xr.Dataset({"propensity": (tuple(sizes), np.zeros(tuple(sizes.values())))},
                    coords=coords)
    lay = plan_layout(ds)
    placed = [d for d in (lay.x, lay.y, lay.col, lay.row) if d is not None]
    assert sorted(placed) == sorted(sizes)  # every dimension shown, none hidden
    assert axes <= {lay.x, lay.y}
    if axes == {"T", "h0"}:
        assert (lay.y, lay.x) == ("T", "h0")


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


# ---- what a picture shows is what the data hold ----------------------------------------

@pytest.fixture(scope="module")
def cmp3():
    """Three partner materials, a 3-value log axis (1-10 um) and a 3-value linear axis."""
    s = at.Scene(liquid="water", T=298.15, d_i=300e-6)
    return at.sweep(s, solid_j=["silica-sand", "ilmenite", "olivine"], U_Umf=[2.0, 3.0, 5.0],
                    h0=[1e-6, 3e-6, 10e-6])


@pytest.fixture(scope="module")
def slag_maps():
    """Two maps of uniform u0*: infinite everywhere (a melt far too viscous to rebound
    from) and 0 everywhere (coatings thinner than the 0.1 um asperities)."""
    s = at.Scene(liquid="k-silicate-ash-melt", gas="biomass-flue-gas")
    T = [1073.15, 1173.15, 1273.15]
    inf = at.sweep(s, T=T, h0=[0.3e-6, 1e-6, 3e-6])
    zero = at.sweep(s, T=T, h0=[0.02e-6, 0.05e-6, 0.08e-6])
    assert np.isinf(inf.u_star).all() and (zero.u_star == 0.0).all()
    return inf, zero


@pytest.fixture(scope="module")
def bed():
    from agglomtool.bed import Component, bed_sweep

    s = at.Scene(liquid="water", T=298.15, h0=5e-6, U_Umf=2.0)
    comps = [Component("silica-sand", 0.7, d50=1000e-6, gsd=1.3, classes=3, ha=0.1e-6),
             Component("ilmenite", 0.3, d50=1000e-6, ha=0.1e-6)]
    return bed_sweep(s, comps, mix="ilmenite", U_Umf=[1.5, 2.0, 3.0],
                     fraction=[0.0, 0.3, 0.6], directions=2)


def _colorbars(fig):
    return [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]


def _legend_labels(fig):
    return [t.get_text() for lg in fig.legends for t in lg.get_texts()]


def _all_text(fig):
    """Every visible text of the figure: titles, labels, tick labels, legends, notes."""
    import matplotlib.text

    return "\n".join(" ".join(t.get_text().split()) for t in fig.findobj(matplotlib.text.Text)
                     if t.get_visible() and t.get_text())  # lines wrapped: joined again


def _panels(fig):
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.get_visible()]


def test_uniform_u_star_gets_no_colour_range_and_says_what_it_is(slag_maps):
    inf, zero = slag_maps
    for ds, words in ((inf, ("all points", "infinite", "ceiling")),
                      (zero, ("all points", "no bridge"))):
        fig = operating_window(ds, "u_star")
        assert _colorbars(fig) == []
        assert not any("contours" in t for t in _legend_labels(fig))
        text = _all_text(fig)
        assert all(w in text for w in words), text
        plt.close(fig)


def test_uniform_propensity_is_stated_not_given_a_range(slag_maps):
    fig = operating_window(slag_maps[0])  # propensity 1 everywhere (u0* infinite)
    assert _colorbars(fig) == []
    assert "all points: agglomeration propensity = 1" in _all_text(fig)
    assert not any("contours" in t for t in _legend_labels(fig))
    assert any("ceiling" in t for t in _legend_labels(fig))  # the hatching is drawn
    plt.close(fig)


def test_colour_bar_spans_the_shown_data(bed, cmp3):
    fig = operating_window(bed)
    (cb,) = _colorbars(fig)
    p = bed.propensity.values
    np.testing.assert_allclose(sorted(cb.get_ylim()), [p.min(), p.max()], rtol=1e-12)
    plt.close(fig)
    fig = operating_window(cmp3, "St", sel={"solid_j": "ilmenite"})  # a log colour scale
    (cb,) = _colorbars(fig)
    st = cmp3.St.sel(solid_j="ilmenite").values
    np.testing.assert_allclose(sorted(cb.get_ylim()), [st.min(), st.max()], rtol=1e-12)
    plt.close(fig)


def test_contour_legend_entry_only_where_contours_are_drawn(cmp3):
    from matplotlib.contour import ContourSet

    fig = operating_window(cmp3, col="solid_j")
    drawn = [c for ax in _panels(fig) for c in ax.collections if isinstance(c, ContourSet)
             and len(c.levels)]
    assert len(drawn) == 3 and any("u0* contours" in t for t in _legend_labels(fig))
    assert all(_labelled(c) for c in drawn)
    plt.close(fig)


def test_a_selection_is_titled_once(cmp3):
    fig = operating_window(cmp3, sel={"solid_j": "ilmenite"})
    titles = [fig._suptitle.get_text()] + [ax.get_title() for ax in _panels(fig)]
    assert sum(t.count("ilmenite") for t in titles) == 1, titles
    plt.close(fig)


def _overlap(a, b):
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


@pytest.mark.parametrize("kw", [dict(sel={"solid_j": "ilmenite"}), dict(col="solid_j")])
def test_labels_legend_and_notes_do_not_overlap(cmp3, kw):
    fig = operating_window(cmp3, **kw)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    axis_parts = []
    for ax in _panels(fig) + _colorbars(fig):
        axis_parts += [ax.xaxis.label, ax.yaxis.label, ax.title]
        axis_parts += ax.get_xticklabels() + ax.get_yticklabels()
    boxes = [t.get_window_extent(r) for t in axis_parts if t.get_visible() and t.get_text()]
    boxes += [ax.get_window_extent(r) for ax in _panels(fig) + _colorbars(fig)]
    notes = [lg.get_window_extent(r) for lg in fig.legends]
    notes += [t.get_window_extent(r) for t in fig.texts if t.get_text()]  # and the title
    assert fig._suptitle in fig.texts and len(notes) >= 4
    for i, n in enumerate(notes):
        assert not any(_overlap(n, b) for b in boxes)
        assert not any(_overlap(n, m) for m in notes[i + 1:])
    ticks = [[t.get_window_extent(r) for t in ax.get_xticklabels() if t.get_text()]
             for ax in _panels(fig)]  # the end ticks of neighbouring panels stay apart
    for a in range(len(ticks)):
        for b in range(a + 1, len(ticks)):
            assert not any(_overlap(u, v) for u in ticks[a] for v in ticks[b])
    plt.close(fig)


def test_notes_list_only_the_materials_shown(cmp3):
    assert "olivine" in cmp3.attrs["assumed_inputs"]
    fig = operating_window(cmp3, sel={"solid_j": "ilmenite"})
    notes = " ".join(" ".join(t.get_text().split()) for t in fig.texts)
    assert "ilmenite asperity_height = 1 um" in notes
    assert "olivine" not in _all_text(fig)
    plt.close(fig)
    fig = operating_window(cmp3, col="solid_j")
    assert "olivine asperity_height = 1 um" in " ".join(" ".join(t.get_text().split())
                                                       for t in fig.texts)
    plt.close(fig)


def test_bed_picture_names_every_component(bed):
    fig = operating_window(bed)
    title = fig._suptitle.get_text()
    assert "silica-sand" in title and "ilmenite" in title
    text = _all_text(fig)
    assert "d50 = 1000 um" in text and "gsd = 1.3" in text  # the components' sizes
    assert "h0 = 5 um" in text and "T = 25 degC" in text
    plt.close(fig)


def test_cells_span_the_data_only(cmp3, bed):
    fig = operating_window(cmp3, col="solid_j")
    for ax in _panels(fig):
        np.testing.assert_allclose(ax.get_xlim(), (1.0, 10.0), rtol=1e-9)  # h0 [um]
        np.testing.assert_allclose(ax.get_ylim(), (2.0, 5.0), rtol=1e-9)   # U/U_mf
        ticks = [float(t) for t in ax.get_xticks() if 1.0 <= t <= 10.0]
        np.testing.assert_allclose(ticks, [1.0, 3.0, 10.0])  # few values: each marked
    plt.close(fig)
    fig = operating_window(bed)
    (ax,) = _panels(fig)
    np.testing.assert_allclose(ax.get_xlim(), (0.0, 0.6), atol=1e-12)
    np.testing.assert_allclose(ax.get_ylim(), (1.5, 3.0), rtol=1e-12)
    plt.close(fig)


def test_every_fixed_scene_value_is_stated(cmp3):
    fig = operating_window(cmp3, sel={"solid_j": "ilmenite"})
    text = _all_text(fig)
    for item in ("T = 25 degC", "P = 1.013 bar", "gas = air", "d_i = 300 um", "d_j = d_i",
                 "eps = 0.55", "U_e_Umf = 1.1", "beta_deg = 0 deg", "mode = relative",
                 "speed = excess-gas", "fluctuation_ratio = 1", "drag_slip = emulsion",
                 "umf_method = wen-yu", "u_ceiling = 10 m/s", "body_forces = on",
                 "water", "silica-sand"):
        assert item in text, item
    assert "h0 = 0.2 um" not in text  # the scene's h0 is swept: the axis says it
    plt.close(fig)


@pytest.mark.parametrize("units", ["dimensionless", "1"])
def test_one_convention_for_dimensionless_units(cmp3, units):
    ds = cmp3.copy()
    for name in list(ds.variables):
        if ds[name].attrs.get("units") == "dimensionless":
            ds[name].attrs["units"] = units
    fig = operating_window(ds, col="solid_j")
    text = _all_text(fig)
    assert "dimensionless" not in text and "[1]" not in text
    assert "U/U_mf [-]" in text and "propensity [-]" in text
    plt.close(fig)


def test_each_picture_is_a_new_figure(slag_maps):
    first = operating_window(slag_maps[0], "u_star")
    second = operating_window(slag_maps[1], contours=False)
    assert second is not first and len(_colorbars(second)) <= 1
    assert _all_text(first).count("all points") == 1
    plt.close("all")


def test_contour_labels_are_not_clipped_at_a_panel_edge(cmp3):
    ds = cmp3.copy()
    # u0* of 0.05 m/s just inside the left edge (h0 = 1 um): its label would stick out
    ds["u_star"] = ds["u_star"].copy(data=np.broadcast_to(
        np.array([0.0499, 0.2, 0.5]), ds["u_star"].shape).copy())
    fig = operating_window(ds, sel={"solid_j": "ilmenite"})
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    (ax,) = _panels(fig)
    box = ax.get_window_extent(r)
    labels = [t for t in ax.texts if t.get_text().endswith("m/s")]
    assert labels
    for t in labels:
        ext = t.get_window_extent(r)
        assert box.x0 - 0.5 <= ext.x0 and ext.x1 <= box.x1 + 0.5, t.get_text()
        assert box.y0 - 0.5 <= ext.y0 and ext.y1 <= box.y1 + 0.5, t.get_text()
    plt.close(fig)


def test_end_ticks_of_neighbouring_panels_stay_apart(bed):
    fig = operating_window(bed, "propensity_by_component")  # 0 ... 0.6 | 0 ... 0.6
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    left, right = ([t.get_window_extent(r) for t in ax.get_xticklabels() if t.get_text()]
                   for ax in _panels(fig))
    assert left and right
    em = _panels(fig)[0].get_xticklabels()[0].get_fontsize() * fig.dpi / 72.0  # [px]
    assert min(b.x0 for b in right) - max(b.x1 for b in left) >= em  # not "0.6 0"
    plt.close(fig)


def test_a_single_valued_dimension_and_a_given_title_still_state_the_values():
    s = at.Scene(liquid="water", d_i=300e-6)
    ds = at.sweep(s, T=[298.15], U_Umf=[2.0, 3.0], h0=[1e-6, 3e-6])
    assert ds.sizes["T"] == 1
    fig = operating_window(ds)
    assert "T = 25 degC" in _all_text(fig)
    plt.close(fig)
    fig = operating_window(ds, sel={"U_Umf": 3.0}, title="my title")
    text = _all_text(fig)
    assert "my title" in text and "T = 25 degC" in text and "U_Umf = 3" in text
    plt.close(fig)


def test_every_contour_drawn_carries_its_label():
    """u0* finite in a strip two cells wide (a melt just thick enough to rebound from): a
    contour line there is too short for its label and is left out, not drawn unreadable."""
    import xarray as xr
    from matplotlib.contour import ContourSet

    T = np.linspace(1073.15, 1673.15, 30)
    h0 = np.geomspace(0.05e-6, 2e-6, 30)
    u = np.full((30, 30), np.inf)
    u[20:, 8:10] = np.geomspace(9.0, 0.5, 10)[:, None] * [1.0, 1.3]
    ds = xr.Dataset({"propensity": (("T", "h0"), np.where(np.isinf(u), 1.0, 0.9)),
                     "u_star": (("T", "h0"), u)},
                    coords={"T": ("T", T, {"units": "K", "long_name": "bed temperature"}),
                            "h0": ("h0", h0, {"units": "m", "long_name": "coating"})})
    fig = operating_window(ds)
    sets = [c for ax in _panels(fig) for c in ax.collections if isinstance(c, ContourSet)]
    for cs in sets:
        assert _labelled(cs)
    assert bool(sets) == any("contours" in t for t in _legend_labels(fig))
    plt.close(fig)


def _labelled(cs) -> bool:
    """Every level of the contour set has a label on the panel."""
    return {f"{v:g} m/s" for v in cs.levels} <= {t.get_text() for t in cs.labelTexts}


def test_a_robust_map_draws_its_boundary_band_and_undecided_cells():
    import warnings

    import agglomtool as at
    from agglomtool.plots import operating_window

    warnings.simplefilter("ignore", at.PlausibilityWarning)
    scene = at.Scene(liquid="water", T=298.15, solid_i="silica-sand", d_i=300e-6)
    grid = dict(U_Umf=np.linspace(1.2, 8.0, 8), h0=np.geomspace(1e-6, 30e-6, 8))
    robust = at.sweep(scene, uncertain="assumed", samples=32, **grid)
    assert robust.undecided.any()  # the test needs undecided cells to draw
    fig = operating_window(robust)
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert "window boundary: P(propensity > 0.5) = 0.5" in labels
    assert "not decided (0.1 < P < 0.9)" in labels
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "Robust map: 32 draws per point" in texts
    plain = operating_window(at.sweep(scene, **grid))
    labels = [t.get_text() for leg in plain.legends for t in leg.get_texts()]
    assert not any("window boundary" in t or "not decided" in t for t in labels)


def test_a_robust_map_marks_the_points_whose_draws_have_no_impact_speed():
    """Where the nominal point has an impact speed but some draws (a bubble model drawn
    beyond a bubbling bed) have none, the robust answer is NaN (undecided = 2): the
    picture marks those cells with a legend, and never shows them as decided."""
    import warnings

    from matplotlib.collections import PolyCollection

    warnings.simplefilter("ignore", at.PlausibilityWarning)
    scene = at.Scene(liquid="water", T=298.15, solid_i="silica-sand", d_i=300e-6,
                     solid_j="ilmenite")
    robust = at.sweep(scene, uncertain="assumed", samples=32, seed=0, U_Umf=[3.0, 20.0],
                      h0=[5e-6, 20e-6])
    no_answer = (robust.undecided == 2) & (robust.speed_flag == 0)
    assert no_answer.any() and not no_answer.all()  # the test needs both kinds
    for var in ("propensity", "propensity_mean", "p_unsafe"):
        fig = operating_window(robust, var=var, x="h0", y="U_Umf")
        labels = _legend_labels(fig)
        assert any(t.startswith("no robust answer") for t in labels), (var, labels)
        (ax,) = _panels(fig)
        hatched = [c for c in ax.collections if isinstance(c, PolyCollection)
                   and c.get_hatch() == "++"]
        assert sum(len(c.get_paths()) for c in hatched) == int(no_answer.sum())
        plt.close(fig)


def test_a_map_without_finite_u_star_says_what_decides_it():
    import agglomtool as at
    from agglomtool.plots import operating_window

    melt = at.Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T=1123.15,
                    solid_i="silica-sand", d_i=300e-6)
    fig = operating_window(at.sweep(melt, T=[1073.15, 1173.15, 1223.15],
                                    h0=[0.05e-6, 0.5e-6, 1e-6]))
    texts = " ".join(t.get_text() for t in fig.texts).replace("\n", " ")
    assert "what decides is whether a bridge forms" in texts


def test_a_log_axis_under_three_decades_labels_1_2_5_as_numbers_without_overlap():
    """0.12-2 um on a log axis: Matplotlib's default labels minor ticks too there, and
    "3x10^-1" overlapped "4x10^-1"; the labels are 0.2, 0.5, 1, 2, apart."""
    s = at.Scene(liquid="hypothetical-slag", T=1173.15, d_i=1000e-6)
    ds = at.sweep(s, U_Umf=[2.0, 3.0, 4.0], h0=np.geomspace(0.12e-6, 2e-6, 12))
    fig = operating_window(ds)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    (ax,) = _panels(fig)
    axis = ax.xaxis if ax.get_xscale() == "log" else ax.yaxis
    shown = [t for t in axis.get_ticklabels() + axis.get_ticklabels(minor=True)
             if t.get_text() and t.get_visible()]
    lo, hi = (ax.get_xlim() if axis is ax.xaxis else ax.get_ylim())
    inside = [t for t in shown if lo <= (t.get_position()[0] if axis is ax.xaxis
                                         else t.get_position()[1]) <= hi]
    assert [t.get_text() for t in inside] == ["0.2", "0.5", "1", "2"]
    boxes = sorted((t.get_window_extent(r) for t in inside), key=lambda b: b.x0)
    assert all(not _overlap(a, b) for a, b in zip(boxes[:-1], boxes[1:], strict=True))
    plt.close(fig)


def test_a_y_axis_given_for_a_one_dimensional_map_is_not_moved_to_x():
    # the caller's y was drawn along x without a word (a line plot has its one dimension
    # on x); the tool's own choice still is
    h0 = np.geomspace(1e-6, 2e-5, 4)
    ds = xr.Dataset({"propensity": ("h0", np.linspace(0.1, 0.9, 4))}, coords={"h0": h0})
    with pytest.raises(ValueError, match=r"y = 'h0' leaves no dimension for x.*--x h0"):
        plan_layout(ds, y="h0")
    assert (plan_layout(ds).x, plan_layout(ds).y) == ("h0", None)
    assert (plan_layout(ds, x="h0").x, plan_layout(ds, x="h0").y) == ("h0", None)
