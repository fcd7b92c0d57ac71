"""Beds, not pairs: mixtures of solids and sizes, their weighting, sweeps and export."""

import math

import numpy as np
import pytest

import agglomtool as at
from agglomtool.bed import (
    Component,
    bed_propensity,
    bed_sweep,
    export_efficiency,
    read_efficiency,
)

WATER = dict(T=298.15, liquid="water", h0=5e-6, U_Umf=1.5)
SLAG = dict(T=1073.15, liquid="hypothetical-slag", h0=0.15e-6, U_Umf=1.5)


def _pair_average(scene, n):
    """Direction average of the pair propensity from Scene.evaluate, computed here: the
    isotropic normal has sin(beta) uniform on [-1, 1]."""
    s, w = np.polynomial.legendre.leggauss(n)
    props = [float(scene.replace(beta_deg=math.degrees(math.asin(x))).evaluate()["propensity"])
             for x in s]
    return float(np.dot(w, props) / 2.0), props


@pytest.mark.parametrize("cond", [WATER, SLAG], ids=["water", "slag"])
def test_monodisperse_bed_is_the_direction_averaged_pair(cond):
    scene = at.Scene(**cond, d_i=600e-6)
    ds = bed_propensity(scene, [Component("silica-sand", 1.0, d=[600e-6])], directions=6)
    expected, props = _pair_average(scene, 6)
    assert float(ds.propensity) == pytest.approx(expected, rel=1e-12, abs=1e-15)
    np.testing.assert_allclose(ds.sticking_probability.values[0, 0], props, rtol=1e-12,
                               atol=1e-15)
    assert float(ds.Umf) == pytest.approx(float(scene.evaluate()["Umf"]), rel=1e-12)
    # A lognormal of gsd 1 is the same bed.
    ds1 = bed_propensity(scene, [Component("silica-sand", 1.0, d50=600e-6, gsd=1.0)],
                         directions=6)
    assert float(ds1.propensity) == float(ds.propensity)


@pytest.mark.parametrize("cond", [WATER, SLAG], ids=["water", "slag"])
def test_pair_matrix_symmetric_with_direction_reversed(cond):
    scene = at.Scene(**cond)
    comps = [Component("silica-sand", 0.6, d50=800e-6, gsd=1.5, classes=3),
             Component("ilmenite", 0.4, d50=400e-6, gsd=1.2, classes=2, ha=0.1e-6, h0=0.0)]
    ds = bed_propensity(scene, comps, directions=4)
    s = ds.sin_beta.values
    np.testing.assert_allclose(s, -s[::-1], atol=1e-15)  # node k reversed is node -k
    for name in ("u_star", "sticking_probability"):
        m = ds[name].values
        swapped = np.transpose(m, (1, 0, 2))[:, :, ::-1]
        np.testing.assert_allclose(m, swapped, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(ds.efficiency.values, ds.efficiency.values.T, rtol=1e-12,
                               atol=1e-15)
    # Across components, compare with the bed listed the other way round (the block with
    # ilmenite as particle i is then computed, not filled by symmetry).
    rev = bed_propensity(scene, comps[::-1], directions=4)
    order = np.r_[np.arange(3) + 2, np.arange(2)]  # rev's classes in ds's order
    for name in ("u_star", "sticking_probability"):
        np.testing.assert_allclose(rev[name].values[np.ix_(order, order)], ds[name].values,
                                   rtol=1e-12, atol=1e-15)
    assert list(rev.component_cls.values[order]) == list(ds.component_cls.values)
    # A dry particle against a dry one cannot form a bridge; against a wet one it may (with
    # the 5 um water film; the 0.15 um slag film alone is too thin for the asperities).
    ilm = ds.component_cls.values == "ilmenite"
    assert np.all(ds.efficiency.values[np.ix_(ilm, ilm)] == 0.0)
    if cond is WATER:
        assert np.any(ds.efficiency.values[np.ix_(~ilm, ilm)] > 0.0)


def test_contributions_sum_to_the_bed_propensity():
    scene = at.Scene(**WATER)
    comps = [Component("silica-sand", 0.7, d50=1000e-6, gsd=1.4, classes=4),
             Component("ilmenite", 0.3, d50=1000e-6, ha=0.1e-6)]
    ds = bed_propensity(scene, comps, directions=4)
    total = float(ds.propensity)
    assert 0.0 < total < 1.0
    assert float(ds.propensity_by_class.sum()) == pytest.approx(total, rel=1e-12)
    assert float(ds.propensity_by_component.sum()) == pytest.approx(total, rel=1e-12)
    assert float(ds.rate_weight.sum()) == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(ds.rate_weight.values, ds.rate_weight.values.T, rtol=1e-12)
    # Hand check of one weight: n ~ w / (rho d^3), W ~ n_a n_b (D_a + D_b)^2.
    d = ds.d_cls.values + 2.0 * 5e-6
    rho = np.where(ds.component_cls.values == "ilmenite", 4330.0, 2650.0)
    n = ds.mass_fraction.values / (rho * ds.d_cls.values**3)
    W = n[:, None] * n[None, :] * (d[:, None] + d[None, :]) ** 2
    np.testing.assert_allclose(ds.rate_weight.values, W / W.sum(), rtol=1e-12)
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        assert ("units" in var.attrs) == (var.dtype.kind != "U"), name  # names: no units


def test_zero_fraction_component_changes_nothing():
    scene = at.Scene(**WATER)
    sand = Component("silica-sand", 1.0, d50=900e-6, gsd=1.3, classes=3)
    a = bed_propensity(scene, [sand], directions=4)
    b = bed_propensity(scene, [sand, Component("ilmenite", 0.0, d50=300e-6, ha=0.1e-6)],
                       directions=4)
    assert float(b.propensity) == pytest.approx(float(a.propensity), rel=1e-12)
    assert float(b.Umf) == pytest.approx(float(a.Umf), rel=1e-12)
    assert float(b.propensity_by_component.sel(component="ilmenite")) == 0.0


def test_fractions_must_sum_to_one_and_fields_are_checked():
    scene = at.Scene(**WATER)
    with pytest.raises(ValueError, match="sum to 0.9"):
        bed_propensity(scene, [Component("silica-sand", 0.6, d50=1e-3),
                               Component("ilmenite", 0.3, d50=1e-3)])
    with pytest.raises(ValueError, match="solid = 'unobtainium'"):
        Component("unobtainium", 1.0, d50=1e-3)
    with pytest.raises(ValueError, match=r"fraction = 1.5 is outside the allowed range \[0, 1\]"):
        Component("silica-sand", 1.5, d50=1e-3)
    with pytest.raises(ValueError, match="gsd = 0.5"):
        Component("silica-sand", 1.0, d50=1e-3, gsd=0.5)
    with pytest.raises(ValueError, match="classes = 0"):
        Component("silica-sand", 1.0, d50=1e-3, gsd=1.5, classes=0)
    with pytest.raises(ValueError, match="exactly one of d50"):
        Component("silica-sand", 1.0)
    with pytest.raises(ValueError, match="d_fractions"):
        Component("silica-sand", 1.0, d=[1e-3, 2e-3], d_fractions=[0.5, 0.6])
    with pytest.raises(ValueError, match="h0 = -1e-06"):
        Component("silica-sand", 1.0, d50=1e-3, h0=-1e-6)
    with pytest.raises(ValueError, match="'d_i' cannot be swept"):
        bed_sweep(scene, [Component("silica-sand", 1.0, d50=1e-3)], d_i=[1e-3])
    with pytest.raises(ValueError, match="needs mix"):
        bed_sweep(scene, [Component("silica-sand", 1.0, d50=1e-3)], fraction=[0.5])


def test_lognormal_classes_equal_mass_mid_quantiles():
    c = Component("silica-sand", 1.0, d50=500e-6, gsd=1.6, classes=5)
    d, w, lo, hi = c.size_classes()
    np.testing.assert_allclose(w, 0.2)
    assert d[2] == pytest.approx(500e-6, rel=1e-12)  # the middle class is the median
    np.testing.assert_allclose(np.log(d) - np.log(500e-6), -(np.log(d) - np.log(500e-6))[::-1],
                               atol=1e-12)
    assert np.all(lo < d) and np.all(d < hi) and np.all(hi[:-1] == lo[1:])


def test_sweep_matches_single_points_and_the_fraction_axis():
    scene = at.Scene(**WATER)
    comps = [Component("silica-sand", 1.0, d50=1000e-6), Component("ilmenite", 0.0, d50=1000e-6,
                                                                   ha=0.1e-6)]
    ds = bed_sweep(scene, comps, mix="ilmenite", directions=4, fraction=[0.0, 0.3, 1.0],
                   U_Umf=[1.5, 2.0])
    assert ds.propensity.dims == ("fraction", "U_Umf")
    for f in (0.0, 0.3, 1.0):
        for u in (1.5, 2.0):
            one = bed_propensity(scene.replace(U_Umf=u),
                                 [Component("silica-sand", 1.0 - f, d50=1000e-6),
                                  Component("ilmenite", f, d50=1000e-6, ha=0.1e-6)],
                                 directions=4)
            got = float(ds.propensity.sel(fraction=f, U_Umf=u))
            assert got == pytest.approx(float(one.propensity), rel=1e-12, abs=1e-15)
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        assert ("units" in var.attrs) == (var.dtype.kind != "U"), name  # names: no units


@pytest.mark.parametrize("suffix", [".csv", ".nc"])
def test_export_round_trips(tmp_path, suffix):
    scene = at.Scene(**SLAG)
    comps = [Component("silica-sand", 0.5, d50=700e-6, gsd=1.4, classes=3),
             Component("olivine", 0.5, d=[300e-6, 500e-6], d_fractions=[0.25, 0.75])]
    ds = bed_propensity(scene, comps, directions=4)
    path = export_efficiency(ds, tmp_path / f"eff{suffix}")
    back = read_efficiency(path)
    for name in ("efficiency", "rate_weight", "u_star_min"):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].attrs["units"] == ds[name].attrs["units"]
    for side in ("cls_i", "cls_j"):
        for c in ("d", "d_lo", "d_hi"):
            np.testing.assert_array_equal(back[f"{c}_{side}"].values, ds[f"{c}_{side}"].values)
            assert back[f"{c}_{side}"].attrs["units"] == "m"
        assert list(back[f"component_{side}"].values) == list(ds[f"component_{side}"].values)
    with pytest.raises(ValueError, match="suffix"):
        export_efficiency(ds, tmp_path / "eff.txt")
    # One point of a sweep with matrix=True: the efficiency only.
    sw = bed_sweep(scene, comps, directions=4, matrix=True, U_Umf=[2.0, 3.0])
    point = sw.sel(U_Umf=3.0)
    back = read_efficiency(export_efficiency(point, tmp_path / f"sweep{suffix}"))
    np.testing.assert_array_equal(back.efficiency.values, point.efficiency.values)
    assert "u_star_min" not in back
    with pytest.raises(ValueError, match="select one point"):
        export_efficiency(sw, tmp_path / f"all{suffix}")


def test_sweep_over_temperature_and_coating():
    """T and h0 axes (h0: every component that follows the scene's coating) equal single
    points; a component with its own coating keeps it."""
    scene = at.Scene(**WATER)
    comps = [Component("silica-sand", 0.8, d50=700e-6, gsd=1.3, classes=2),
             Component("olivine", 0.2, d50=400e-6, h0=0.0)]
    ds = bed_sweep(scene, comps, directions=2, T=[298.15, 338.15], h0=[3e-6, 8e-6])
    assert ds.propensity.dims == ("T", "h0")
    values = set()
    for T in (298.15, 338.15):
        for h0 in (3e-6, 8e-6):
            one = bed_propensity(scene.replace(T=T, h0=h0), comps, directions=2)
            got = float(ds.propensity.sel(T=T, h0=h0))
            assert got == pytest.approx(float(one.propensity), rel=1e-12, abs=1e-15)
            assert float(ds.Umf.sel(T=T, h0=h0)) == pytest.approx(float(one.Umf), rel=1e-12)
            assert float(one.h0_component.sel(component="olivine")) == 0.0
            values.add(round(got, 12))
    assert len(values) == 4  # every axis matters


def test_a_fraction_axis_of_a_bed_of_one_component_is_refused():
    """One component's fraction is 1 whatever the axis says: fraction = [0.2] gave the
    propensity of the whole bed labelled 0.2 (exit 0), and 0 a 'd = nan' error."""
    scene = at.Scene(**WATER)
    sand = [Component("silica-sand", 1.0, d50=300e-6)]
    for fraction in ([0.2], [0.0, 0.5]):
        with pytest.raises(ValueError, match=r"fraction: the bed has one component.*two or more"):
            bed_sweep(scene, sand, mix="silica-sand", fraction=fraction)


def test_mix_naming_a_solid_two_components_share_is_refused():
    """A bimodal sand as two components: mix = 'silica-sand' set the first, unsaid."""
    scene = at.Scene(**WATER)
    comps = [Component("silica-sand", 0.5, d50=300e-6), Component("silica-sand", 0.5,
                                                                  d50=600e-6)]
    with pytest.raises(ValueError, match=r"mix = 'silica-sand' names 2 components \(0, 1\)"):
        bed_sweep(scene, comps, mix="silica-sand", fraction=[0.2])
    ds = bed_sweep(scene, comps, mix=1, directions=2, fraction=[0.2])  # by index: taken
    assert ds.propensity.shape == (1,)
