"""Sweeps: units everywhere, netCDF round trip, chunking (stores: test_store.py)."""

import json

import numpy as np
import pint
import pytest
import xarray as xr

from agglomtool.maps import sweep
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
GRID = dict(T=np.linspace(900.0, 1300.0, 4), solid_j=["silica-sand", "ilmenite"],
            h0=np.geomspace(0.12e-6, 2e-6, 5), U_Umf=[2.0, 4.0, 8.0])


@pytest.fixture(scope="module")
def ds():
    return sweep(SCENE, chunks=None, **GRID)


def test_units_and_long_names_everywhere(ds):
    ureg = pint.UnitRegistry()
    for name, var in ds.variables.items():
        assert "long_name" in var.attrs, name
        if var.dtype.kind == "U":  # names: no units
            assert "units" not in var.attrs, name
        else:
            ureg.parse_units(var.attrs["units"])  # raises if pint cannot parse
    for key in ("agglomtool_version", "model_tier", "scene"):
        assert ds.attrs[key]
    assert any(k.startswith("liquid ") for k in json.loads(ds.attrs["material_sources"]))


def test_dims_follow_dependencies(ds):
    assert ds.mu_g.dims == ("T",)
    assert "U_Umf" not in ds.u_star.dims
    assert ds.propensity.dims == ("T", "solid_j", "h0", "U_Umf")


def test_grid_point_equals_scene(ds):
    pt = ds.isel(T=2, solid_j=1, h0=3, U_Umf=1)
    s = SCENE.replace(T=float(pt.T), solid_j=str(pt.solid_j.values), h0=float(pt.h0),
                      U_Umf=float(pt.U_Umf))
    one = s.evaluate()
    for name in ("u_star", "e_w", "propensity", "Umf", "mu_g"):
        assert float(pt[name]) == pytest.approx(float(one[name]), rel=1e-12), name


def test_netcdf_round_trip(ds, tmp_path):
    ds.to_netcdf(tmp_path / "m.nc")
    with xr.open_dataset(tmp_path / "m.nc") as back:
        xr.testing.assert_identical(ds, back.load())
        assert back.agglomerated.dtype == bool


def test_chunked_equals_unchunked(ds):
    xr.testing.assert_identical(ds, sweep(SCENE, chunks=7, **GRID))


def test_bad_grids_name_the_field():
    with pytest.raises(ValueError, match="nonsense"):
        sweep(SCENE, nonsense=[1.0])
    with pytest.raises(ValueError, match="h0"):
        sweep(SCENE, h0=[-1e-6, 1e-6])
    with pytest.raises(ValueError, match="u0"):
        sweep(SCENE, u0=[0.1, 0.2])  # speed is excess-gas: u0 would be ignored
    with pytest.raises(ValueError, match="liquid"):
        sweep(SCENE, liquid=["hypothetical-slag", "lava"])
