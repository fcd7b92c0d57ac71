"""Valid requests that used to crash, and inputs that used to be taken silently or
inconsistently: each as a user types it, from the API and from the command line."""

import contextlib
import tomllib
import warnings

import numpy as np
import pint
import pytest
import xarray as xr

import agglomtool as at
from agglomtool.bed import Component, bed_propensity, bed_sweep
from agglomtool.bed.config import parse_bed_config
from agglomtool.cli import main
from agglomtool.maps.config import ConfigError, parse_config
from agglomtool.plausibility import PlausibilityWarning
from agglomtool.uncertainty.distributions import LogNormal, Normal, Uniform, to_si

UREG = pint.get_application_registry()
WATER = dict(liquid="water", T=323.15, h0=5e-6, d_i=500e-6)


@contextlib.contextmanager
def _quiet():
    """A context in which any PlausibilityWarning fails the test."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        yield


# --- sweeping U (the superficial gas velocity) -----------------------------------------

def test_sweep_over_U_gives_U_as_the_coordinate_and_each_point_is_the_scene():
    scene = at.Scene(**WATER)
    ds = at.sweep(scene, U=[0.3, 0.6])
    assert "U" in ds.coords and "U" not in ds.data_vars
    assert ds.propensity.dims == ("U",)
    for u in (0.3, 0.6):
        one = scene.replace(U=u).evaluate()
        for name in ("propensity", "u_typical", "e_w", "u_star"):
            assert float(ds.sel(U=u)[name]) == pytest.approx(float(one[name]), rel=1e-12)
    # Where U is not swept, the effective U (U_Umf * U_mf) is an output, as before.
    by_number = at.sweep(scene, U_Umf=[2.0, 3.0])
    assert by_number["U"].dims == ("U_Umf",)
    np.testing.assert_allclose(by_number["U"].values, [2.0, 3.0] * by_number["Umf"].values,
                               rtol=1e-12)


def test_bed_sweep_over_U():
    scene = at.Scene(**WATER)
    comps = [Component("silica-sand", 1.0, d=[500e-6])]
    ds = bed_sweep(scene, comps, directions=2, U=[0.3, 0.6])
    assert "U" in ds.coords and "U" not in ds.data_vars
    for u in (0.3, 0.6):
        one = bed_propensity(scene.replace(U=u), comps, directions=2)
        assert float(ds.propensity.sel(U=u)) == pytest.approx(float(one.propensity),
                                                              rel=1e-12)


def test_map_config_over_U_in_units(tmp_path):
    cfg = tmp_path / "u.toml"
    cfg.write_text('[scene]\nliquid = "water"\nT = "50 degC"\nh0 = "5 um"\nd_i = "500 um"\n'
                   '[grid]\nU = ["30 cm/s", "60 cm/s"]\n')
    out = tmp_path / "u.nc"
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 0
    with xr.open_dataset(out) as ds:
        np.testing.assert_array_equal(ds.U.values, [0.3, 0.6])
        assert "U" not in ds.data_vars


# --- one validation of a grid, at the values swept ---------------------------------------

WATER_OVER_T = """
[scene]
liquid = "water"
d_i = "500 um"
[grid]
T = ["20 degC", "50 degC"]
h0 = ["2 um", "5 um"]
"""


def test_water_map_over_T_needs_no_scene_T(tmp_path):
    with _quiet():  # the Scene's default T (a melt's 800 degC) is swept: nothing to say
        cfg = parse_config(tomllib.loads(WATER_OVER_T))
    np.testing.assert_array_equal(cfg.grid["T"], [293.15, 323.15])
    path = tmp_path / "w.toml"
    path.write_text(WATER_OVER_T)
    assert main(["--strict", "map", str(path), "-o", str(tmp_path / "w.nc"), "-q"]) == 0


def test_grid_axes_are_checked_together_not_at_the_scene_defaults():
    # u0 is swept, so speed = "fixed" (swept too) has its u0: not the Scene's None.
    ds = at.sweep(at.Scene(**WATER), speed=["fixed", "lognormal"], u0=[0.2, 0.4])
    assert ds.propensity.dims == ("speed", "u0")
    expect = at.Scene(**WATER, speed="lognormal", u0=0.4).evaluate()
    assert float(ds.propensity.sel(speed="lognormal", u0=0.4)) == pytest.approx(
        float(expect["propensity"]), rel=1e-12)


def test_grid_errors_still_name_the_key():
    text = WATER_OVER_T.replace('"50 degC"', '"500 degC"')
    with pytest.raises(ConfigError, match=r"\[grid\] T: .*water.*T = 773.15"):
        parse_config(tomllib.loads(text))
    with pytest.raises(ConfigError, match=r"\[grid\] h0: .*h0 = -1e-06"):
        parse_config(tomllib.loads(WATER_OVER_T.replace('"2 um"', '"-1 um"')))


@pytest.mark.parametrize("axis, first_bare", [
    ('T = ["20 degC", "80 degC", 5]', "5"),          # a range written as a list
    ('h0 = [2e-6, "5 um"]', "2e-06"),
])
def test_a_grid_list_mixing_units_and_bare_numbers_is_refused(axis, first_bare):
    # Without the check, T = ["20 degC", "80 degC", 5] swept 293.15 K, 353.15 K and 5 K
    # (and failed on 5 K with an error about air's equation of state, not the list).
    text = '[scene]\nliquid = "water"\nT = "50 degC"\n[grid]\n' + axis + "\n"
    key = axis.split(" ")[0]
    with pytest.raises(ConfigError, match=rf"\[grid\] {key}: .*mixes quantities with units "
                                          rf".*bare numbers \({first_bare}, read as"):
        parse_config(tomllib.loads(text))


def test_a_grid_list_of_bare_numbers_or_of_quantities_is_taken():
    # a dimensionless field's "2" and 4.0 mean the same; a number in quotes is no unit
    text = '[scene]\nliquid = "water"\nT = "50 degC"\n[grid]\nU_Umf = ["2", 4.0]\n'
    assert parse_config(tomllib.loads(text)).grid["U_Umf"] == pytest.approx([2.0, 4.0])
    text = text.replace('U_Umf = ["2", 4.0]', 'h0 = ["2e-6", 4e-6]')
    assert parse_config(tomllib.loads(text)).grid["h0"] == pytest.approx([2e-6, 4e-6])
    text = '[scene]\nliquid = "water"\nT = "50 degC"\n[grid]\nT = ["20 degC", "80 degC"]\n'
    assert parse_config(tomllib.loads(text)).grid["T"] == pytest.approx([293.15, 353.15])
    text = text.replace('["20 degC", "80 degC"]', "[293.15, 353.15]")
    assert parse_config(tomllib.loads(text)).grid["T"] == pytest.approx([293.15, 353.15])


# --- pressures CoolProp cannot evaluate ----------------------------------------------------

def test_pressure_below_water_triple_point_is_refused_naming_P():
    with pytest.warns(PlausibilityWarning, match="P = 1.5 Pa"):
        scene = at.Scene(liquid="water", T=300.0, P=1.5, h0=5e-6, d_i=500e-6)
    with pytest.raises(ValueError, match=r"P = 1.5 .*611.6"):
        scene.evaluate()


def test_cli_pressure_slip_is_an_error_naming_P(capsys):
    assert main(["collide", "--liquid", "water", "--T", "300", "--P", "1.5"]) == 2
    err = capsys.readouterr().err
    assert "P = 1.5" in err and "611.6" in err and "rhomolar" not in err


# --- beds are checked for plausibility as scenes are ---------------------------------------

@pytest.mark.parametrize("kwargs,needle", [
    (dict(solid="ilmenite", fraction=1.0, d50=1000e-6),
     r"d50 = 0.001 m is above the typical size range of ilmenite"),
    (dict(solid="silica-sand", fraction=1.0, d50=500.0), r"d50 = 500 m is above"),
    (dict(solid="silica-sand", fraction=1.0, d=[500e-6, 5e-6]), r"d = 5e-06 m is below"),
    (dict(solid="silica-sand", fraction=1.0, d50=500e-6, h0=5.0), r"h0 = 5 m is more than"),
    (dict(solid="silica-sand", fraction=1.0, d50=500e-6, ha=1e-3), r"ha = 0.001 m is outside"),
])
def test_component_slips_warn(kwargs, needle):
    with pytest.warns(PlausibilityWarning, match=needle):
        Component(**kwargs)


def test_plausible_component_is_silent():
    with _quiet():
        Component("ilmenite", 1.0, d50="250 um", gsd=1.2, classes=3)


def test_bed_checks_the_scene_coating_against_the_components():
    scene = at.Scene(liquid="water", T=300.0, h0=40e-6, d_i=1000e-6)
    comps = [Component("ilmenite", 1.0, d50=300e-6)]
    with pytest.warns(PlausibilityWarning, match=r"h0 = 4e-05 m is more than 0.1 of the "
                      r"particle diameter \(0.0003 m"):
        bed_propensity(scene, comps, directions=2)


BED = """
[scene]
liquid = "water"
T = "25 degC"
h0 = "5 um"
U_Umf = 2.0
[[component]]
solid = "silica-sand"
fraction = 1.0
d50 = 500
"""


def test_bed_config_slip_warns_and_strict_refuses(tmp_path, capsys):
    with pytest.warns(PlausibilityWarning, match=r"\[\[component\]\] 1: d50 = 500 m"):
        parse_bed_config(tomllib.loads(BED), "bed.toml")
    path = tmp_path / "bed.toml"
    path.write_text(BED)
    assert main(["--strict", "bed", str(path), "-o", str(tmp_path / "b.nc")]) == 2
    assert "d50 = 500 m" in capsys.readouterr().err
    assert not (tmp_path / "b.nc").exists()


def test_bed_config_with_a_melt_scene_is_not_checked_at_a_dummy_temperature():
    text = ('[scene]\nliquid = "k-silicate-ash-melt"\nT = "850 degC"\nh0 = "0.5 um"\n'
            '[[component]]\nsolid = "silica-sand"\nfraction = 1.0\nd50 = "500 um"\n')
    with _quiet():
        cfg = parse_bed_config(tomllib.loads(text))
    assert cfg.scene.T == pytest.approx(1123.15)


# --- one unit entry point ------------------------------------------------------------------

def test_component_takes_units():
    a = Component("silica-sand", 1.0, d50="500 um", h0="5 um", ha="0.5 um")
    b = Component("silica-sand", 1.0, d50=500e-6, h0=5e-6, ha=0.5e-6)
    assert a == b
    c = Component("silica-sand", 1.0, d=["400 um", 0.5 * UREG.mm])
    assert c.d == (400e-6, 500e-6)
    with pytest.raises(ValueError, match=r"d50 = .*units of \[mass\]"):
        Component("silica-sand", 1.0, d50="5 kg")


@pytest.mark.parametrize("args,kw", [
    ((50.0, 5.0), dict(units="degC")), (("50 degC", 5.0), {}), (("50 degC", "5 K"), {}),
    ((UREG.Quantity(50.0, "degC"), 5.0), {}), (("50 degC", "5 delta_degC"), {}),
])
def test_temperature_distributions_in_degC(args, kw):
    si = to_si("T", Normal(*args, **kw), "K")
    assert si.mean == pytest.approx(323.15, rel=1e-15) and si.sd == 5.0


def test_distributions_take_unit_strings_for_every_parameter():
    n = to_si("d_i", Normal("500 um", "50 um", lo="300 um"), "m")
    assert (n.mean, n.sd, n.lo) == (500e-6, 50e-6, 300e-6)
    ln = to_si("h0", LogNormal("5 um", "1 um"), "m")
    assert (ln.mean, ln.sd) == (5e-6, 1e-6)
    u = to_si("T", Uniform("40 degC", "60 degC"), "K")
    assert (u.low, u.high) == pytest.approx((313.15, 333.15), rel=1e-15)
    old = to_si("mu_l", Normal(10.0, 1.0, units="mPa s"), "Pa s")  # the spellings kept
    assert (old.mean, old.sd) == pytest.approx((0.01, 0.001), rel=1e-15)


def test_distribution_unit_errors_name_the_parameter():
    with pytest.raises(ValueError, match=r"sd = 5.0 kg has units of \[mass\]"):
        to_si("T", Normal("50 degC", "5 kg"), "K")
    with pytest.raises(ValueError, match=r"uncertain\['T'\].*units of \[length\]"):
        to_si("T", Normal(50.0, 5.0, units="um"), "K")
    with pytest.raises(ValueError, match=r"mean = 'warm' is not a number"):
        Normal("warm", 5.0)
    with pytest.raises(ValueError, match=r"has units: .*to_si"):
        Normal("50 degC", 5.0).sample(np.random.default_rng(0), 3)


def test_scene_monte_carlo_with_a_temperature_in_degC():
    scene = at.Scene(liquid="water", T="50 degC", h0="5 um", d_i="500 um", u0=0.3)
    a = at.monte_carlo(scene, uncertain={"T": Normal(50.0, 2.0, units="degC")}, n=64, seed=1)
    b = at.monte_carlo(scene, uncertain={"T": Normal(323.15, 2.0)}, n=64, seed=1)
    np.testing.assert_allclose(a["T"].values, b["T"].values, rtol=1e-15)
    np.testing.assert_allclose(a.e_w.values, b.e_w.values, rtol=1e-12)


def test_plot_sel_takes_units(tmp_path):
    path = tmp_path / "m.nc"
    at.sweep(at.Scene(**WATER), d_i=[400e-6, 500e-6], h0=[2e-6, 5e-6],
             U_Umf=[2.0, 3.0]).to_netcdf(path)
    for sel in ("d_i=400 um", "d_i=0.4 mm", "d_i=400e-6"):
        assert main(["plot", str(path), "-o", str(tmp_path / "p.png"), "--sel", sel]) == 0


@pytest.mark.parametrize("typed,hint", [("50 C", "degC"), ("120 F", "degF")])
def test_coulomb_for_celsius_gets_a_hint(typed, hint, capsys):
    with pytest.raises(ValueError, match=rf"T = .*did you mean \"{typed.split()[0]} {hint}\""):
        at.Scene(T=typed)
    assert main(["collide", "--T", typed]) == 2
    assert f'did you mean "{typed.split()[0]} {hint}"' in capsys.readouterr().err


def test_melt_temperature_typed_as_degC_warns():
    with pytest.warns(PlausibilityWarning, match=r"^T = 850 K .*k-silicate-ash-melt.*"
                      r"\"850 degC\""):
        at.Scene(liquid="k-silicate-ash-melt", T=850.0)
    with pytest.warns(PlausibilityWarning, match=r"^T = 850 K"):
        at.sweep(at.Scene(liquid="k-silicate-ash-melt", h0=0.5e-6), chunks=None,
                 T=[850.0, 1123.15])
    with _quiet():
        at.Scene(liquid="k-silicate-ash-melt", T="850 degC")
        at.Scene(liquid="blast-furnace-slag", T="1500 degC")


# --- the command line ------------------------------------------------------------------------

def test_strict_before_or_after_every_subcommand(tmp_path, capsys):
    for argv in (["--strict", "collide", "--h0", "5"], ["collide", "--h0", "5", "--strict"],
                 ["collide", "--strict", "--h0", "5"]):
        assert main(argv) == 2, argv
        assert "error (--strict)" in capsys.readouterr().err
    assert main(["collide", "--h0", "5"]) == 0  # a warning only
    assert main(["reference", "--beta", "0", "--strict"]) == 0
    cfg = tmp_path / "w.toml"
    cfg.write_text(WATER_OVER_T)
    assert main(["map", str(cfg), "-o", str(tmp_path / "w.nc"), "-q", "--strict"]) == 0


def test_store_refusal_speaks_the_callers_language(tmp_path, capsys):
    scene = at.Scene(**WATER)
    grid = dict(h0=np.geomspace(1e-6, 10e-6, 30), U_Umf=[2.0, 3.0])
    store = tmp_path / "s"
    at.sweep(scene, store=store, chunks=2, **grid)
    with pytest.raises(ValueError, match="overwrite=True") as info:
        at.sweep(scene, store=store, chunks=4, **grid)
    text = str(info.value)
    # 30 chunks of h0 then 15: counted, a few listed, not a cut-off JSON text.
    assert "chunks h0: stored 30 chunks [1, 1, 1, ..., 1], now 15 chunks [2, 2, 2, ..., 2]" \
        in text, text
    cfg = tmp_path / "c.toml"
    cfg.write_text('[scene]\nliquid = "water"\nT = 323.15\nh0 = 5e-6\nd_i = 500e-6\n'
                   '[grid]\nh0 = { start = 1e-6, stop = 10e-6, num = 30, log = true }\n'
                   'U_Umf = [2.0, 3.0]\n[options]\nchunks = 2\n')
    out = tmp_path / "m.nc"
    assert main(["map", str(cfg), "-o", str(out), "-q", "--keep-parts"]) == 0
    cfg.write_text(cfg.read_text().replace("chunks = 2", "chunks = 4"))
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert "--overwrite" in err and "overwrite=True" not in err
    assert "30 chunks" in err


def test_what_a_person_types_means_the_same_whatever_pint_registry_is_active():
    """cf_xarray.units replaces pint's application registry with UDUNITS spellings, where
    "C" is a temperature; agglomtool reads typed units with a registry of its own."""
    import cf_xarray.units  # noqa: F401  (sets pint's application registry)
    import pint

    assert pint.get_application_registry() is not None
    with pytest.raises(ValueError, match=r'did you mean "50 degC"'):
        at.Scene(T="50 C")
    assert at.Scene(T="50 degC").T == pytest.approx(323.15)
    q = pint.get_application_registry().Quantity(500, "um")  # a user's own Quantity
    assert at.Scene(d_i=q).d_i == pytest.approx(500e-6)


def test_a_pressure_axis_that_boils_the_water_is_the_key_named():
    # the swept P = 1 bar boils water at 110 degC: the grid's key, not the [scene], is named
    text = """
[scene]
liquid = "water"
T = "110 degC"
[grid]
P = ["1 bar", "2 bar"]
"""
    with _quiet(), pytest.raises(ConfigError, match=r"\[grid\] P: .*water at T = 383.15 K, "
                                                    r"P = 100000 Pa is not a liquid"):
        parse_config(tomllib.loads(text))


@pytest.mark.parametrize("axis", ['T = { start = "800 degC", stop = 1200, num = 5 }',
                                  'h0 = { start = 1e-6, stop = "20 um", num = 3 }'])
def test_a_range_mixing_a_unit_and_a_bare_number_is_refused(axis):
    # { start = "800 degC", stop = 1200 } had swept 1073.15-1200 K: 800-927 degC, exit 0
    text = f'[scene]\nliquid = "k-silicate-ash-melt"\n[grid]\n{axis}\n'
    key = axis.split()[0]
    with pytest.raises(ConfigError, match=rf"\[grid\] {key}: start and stop mix quantities "
                                          r"with units .* and bare numbers .*give both"):
        parse_config(tomllib.loads(text))


def test_a_scene_typed_with_both_U_and_U_Umf_is_refused(tmp_path, capsys):
    # U_Umf sets U only where U is not given: typed beside U, it was dropped without a word
    text = ('[scene]\nliquid = "water"\nT = "25 degC"\nU = 0.5\nU_Umf = 2\n'
            '[grid]\nh0 = [1e-6, 5e-6]\n')
    with pytest.raises(ConfigError, match=r"\[scene\] U_Umf: U_Umf = 2 has no effect where U "
                                          r"is given \(U = 0.5 m/s\)"):
        parse_config(tomllib.loads(text))
    argv = ["collide", "--liquid", "water", "--T", "298.15", "--U", "0.5", "--U-Umf", "2"]
    assert main(argv) == 2
    assert "U_Umf = 2 has no effect where U is given" in capsys.readouterr().err
