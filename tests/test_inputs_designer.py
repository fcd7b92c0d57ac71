"""Inputs a designer cannot get silently wrong: units at the edge, plausibility
warnings naming the field, provenance of every resolved input."""

import json
import tomllib
import warnings

import numpy as np
import pint
import pytest
import xarray as xr

import agglomtool as at
from agglomtool.maps.config import parse_config
from agglomtool.plausibility import PlausibilityWarning

UREG = pint.get_application_registry()


def test_quantities_and_unit_strings_equal_si_floats():
    si = at.Scene(T=1123.15, h0=5e-6, d_i=500e-6, P=1.5e5)
    q = at.Scene(T=UREG.Quantity(850.0, "degC"), h0=5 * UREG.um, d_i=0.5 * UREG.mm,
                 P=1.5 * UREG.bar)
    s = at.Scene(T="850 degC", h0="5 um", d_i="500 um", P="1.5 bar")
    assert q.values() == si.values() == s.values()  # exactly: 5 um is 5e-6 m
    assert float(q.evaluate()["u_star"]) == float(si.evaluate()["u_star"])


def test_quantity_grid_equals_si_grid():
    T = np.array([800.0, 850.0, 900.0])
    a = at.sweep(at.Scene(u0=0.3), T=T + 273.15, h0=[1e-6, 2e-6])
    b = at.sweep(at.Scene(u0=0.3), T=T * UREG.degC, h0=["1 um", "2 um"])
    xr.testing.assert_identical(a, b)


def test_toml_with_unit_strings_gives_the_same_map():
    si = parse_config(tomllib.loads(
        '[scene]\nT = 1123.15\nd_i = 500e-6\n[grid]\nh0 = { start = 1e-6, stop = 4e-6, num = 3 }'
        '\nU_Umf = [2.0, 4.0]'))
    units = parse_config(tomllib.loads(
        '[scene]\nT = "850 degC"\nd_i = "500 um"\n[grid]\nh0 = { start = "1 um", stop = '
        '"4 um", num = 3 }\nU_Umf = ["2", 4.0]'))
    assert si.scene == units.scene
    for k in si.grid:
        np.testing.assert_array_equal(si.grid[k], units.grid[k])
    xr.testing.assert_identical(at.sweep(si.scene, **si.grid),
                                at.sweep(units.scene, **units.grid))


@pytest.mark.parametrize("value,needle", [("5 kg", r"units of \[mass\]"),
                                          ("5 umm", "not a unit pint knows"),
                                          ("five um", "not a number with a unit")])
def test_bad_unit_strings_name_the_field(value, needle):
    with pytest.raises(ValueError, match=rf"h0 = .*{needle}"):
        at.Scene(h0=value)


@pytest.mark.parametrize("kwargs,field", [
    (dict(h0=5), "h0"),                     # meant 5 um
    (dict(d_i=500), "d_i"),                 # meant 500 um
    (dict(P=1.5), "P"),                     # meant 1.5 bar
    (dict(ha_i=1e-12), "ha_i"),
    (dict(u0=50.0), "u0"),                  # above the 10 m/s ceiling
    (dict(solid_j="ilmenite", d_i=800e-6), "d_j (= d_i)"),
])
def test_slips_warn_naming_the_field(kwargs, field):
    with pytest.warns(PlausibilityWarning, match=rf"^{field.replace('(', '.').replace(')', '.')}"
                      " = "):
        at.Scene(**kwargs)


def test_plausible_scene_is_silent_and_warnings_can_be_errors():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        at.Scene(liquid="water", T="25 degC", h0="5 um", d_i="300 um")
        warnings.simplefilter("error", PlausibilityWarning)
        with pytest.raises(PlausibilityWarning):
            at.Scene(h0=5)


def test_sweep_warns_once_for_implausible_grid_values():
    with pytest.warns(PlausibilityWarning) as record:
        at.sweep(at.Scene(u0=0.3), d_i=[300e-6, 0.5], T=[1000.0, 1100.0])
    msgs = [str(w.message) for w in record if w.category is PlausibilityWarning]
    assert len(msgs) == len(set(msgs)) >= 1 and any(m.startswith("d_i = 0.5") for m in msgs)


def test_every_resolved_input_has_an_origin():
    s = at.Scene(liquid="water", T=298.15, solid_j="ilmenite", h0=5e-6, d_i=300e-6)
    prov = s.provenance()
    assert prov["T"][2] == "given" and prov["P"][2] == "default"
    assert prov["ha_j"][:4] == (1e-6, "m", "database: solid ilmenite.asperity_height",
                                "assumed")
    assert prov["rho_i"][3] == "database"
    assert prov["d_j"][2] == "derived: d_i"
    text = s.describe()
    assert "ha_j" in text and "<- assumed" in text and "kg/m**3" in text
    given = at.Scene(liquid="water", T=298.15, solid_j="ilmenite", h0=5e-6, ha_j=2e-6,
                     d_i=300e-6)
    assert given.provenance()["ha_j"][2] == "given"


def test_map_lists_origins_and_assumptions():
    ds = at.sweep(at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6),
                  solid_j=["silica-sand", "ilmenite"], U_Umf=[2.0, 4.0])
    prov = json.loads(ds.attrs["provenance"])
    assert prov["T"] == {"value": 298.15, "units": "K", "origin": "given", "confidence": "user"}
    assert "solid_j" not in prov  # swept: its coordinate says it
    assert "ilmenite asperity_height = 1 um" in ds.attrs["assumed_inputs"]
    from agglomtool.plots import operating_window

    fig = operating_window(ds)
    notes = [t.get_text() for t in fig.texts]
    assert any("ilmenite asperity_height = 1 um" in n for n in notes)


def test_core_api_converts_quantities_once_at_the_edge():
    water = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    air = at.Gas(mu=1.8e-5, rho=1.2)
    si = at.Particle(d=500e-6, rho=2650.0, h0=5e-6, ha=1e-7)
    q = at.Particle(d=500 * UREG.um, rho=2.65 * UREG("g/cm**3"), h0="5 um" and 5 * UREG.um,
                    ha=0.1 * UREG.um)
    assert (float(q.d), float(q.h0), float(q.ha)) == (500e-6, 5e-6, 1e-7)
    a = at.collide(si, si, liquid=water, gas=air, u0=0.1)
    b = at.collide(q, q, liquid=water, gas=air, u0=10 * UREG("cm/s"))
    np.testing.assert_allclose(b.e_w, a.e_w, rtol=1e-12)  # rho: 2.65 g/cm3 -> 2650.0000000000005
    with pytest.raises(ValueError, match=r"d = 5 kg has units of \[mass\]"):
        at.Particle(d=5 * UREG.kg, rho=2650.0, h0=0.0, ha=0.0)


def test_readable_result_and_explanation():
    water = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    air = at.Gas(mu=1.8e-5, rho=1.2)
    p = at.Particle(d=500e-6, rho=2650.0, h0=5e-6, ha=1e-7)
    r = at.collide(p, p, liquid=water, gas=air, u0=np.linspace(0.01, 1.0, 50))
    text = repr(r)
    assert "shape=(50,)" in text and "agglomerate" in text and len(text) < 300
    one = at.collide(p, p, liquid=water, gas=air, u0=0.1, details=True).explain()
    assert "K_ini_i" in one and " J" in one and " m/s" in one
    assert "= -0 " not in one + " " and "= -0\n" not in one


def test_water_above_its_boiling_point_and_melts_outside_calibration_warn():
    with pytest.warns(PlausibilityWarning, match=r"^T = 383.15 K is at or above water's "
                                                 "boiling point"):
        at.Scene(liquid="water", T=383.15, h0=5e-6, d_i=300e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        at.Scene(liquid="water", T=383.15, P=3e5, h0=5e-6, d_i=300e-6)  # 3 bar: still liquid
    with pytest.warns(PlausibilityWarning, match="calibration"):
        at.materials.liquid("blast-furnace-slag", T=1773.15, viscosity_model="grd")


def test_a_cold_melt_is_said_in_k_and_degc_and_the_slip_as_a_condition():
    # 500 degC typed with its unit: the warning shows it was read so (773.15 K = 500 degC)
    # and offers the degC-as-K remedy only as a condition (it had asserted the slip)
    with pytest.warns(PlausibilityWarning) as rec:
        at.Scene(liquid="k-silicate-ash-melt", T="500 degC")
    text = " ".join(str(w.message) for w in rec if "oxide melt" in str(w.message))
    assert text.startswith("T = 773.15 K (500 degC) is below 873.15 K (600 degC)"), text
    assert "if 773.15 was meant in degC" in text and "typed as K?" not in text


def test_an_emulsion_faster_than_the_gas_fed_is_said():
    # U_Umf = 1.05 with the default U_e_Umf = 1.1: U_e > U, more gas in the emulsion than
    # the bed is fed (the drag of the body forces would use it silently)
    with pytest.warns(PlausibilityWarning, match=r"^U_Umf = 1.05 is below U_e_Umf = 1.1"):
        at.Scene(U_Umf=1.05)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        at.Scene(U_Umf=1.05, U_e_Umf=1.0)  # the emulsion at U_mf: consistent
        at.Scene(U_Umf=1.05, body_forces=False)  # no drag: U_e is not used
        at.Scene(U_Umf=1.5)
