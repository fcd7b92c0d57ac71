"""A store's layout, written from the sweep's plan with zarr alone: the same files, byte
for byte, as xarray's ``to_zarr`` of the sweep's template Dataset, and the same fingerprint
as the lazy sweep's."""

import hashlib
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from zarr.codecs import Crc32cCodec, ZstdCodec

from agglomtool.maps import build, sweep
from agglomtool.maps.plan import _plan, _template
from agglomtool.maps.store import (
    _DATA,
    _Layout,
    _layout_files,
    _manifest,
    _sha,
    fingerprint,
    open_store,
)
from agglomtool.scene import Scene

SLAG = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
WATER = Scene(liquid="water", T=298.15, d_i=300e-6)
CASES = {
    "names": (SLAG, 4, dict(T=np.linspace(950.0, 1250.0, 3),
                            solid_j=["silica-sand", "ilmenite"], h0=[0.15e-6, 0.6e-6],
                            U_Umf=[2.0, 6.0])),
    "0-d outputs": (SLAG, 1, dict(U_Umf=[2.0, 4.0, 8.0])),
    "modes, uneven blocks": (SLAG, 5, dict(mode=["relative", "paper"], h0=[1e-7, 2e-7, 3e-7],
                                           d_i=[1e-3, 2e-3], T=[1000.0, 1100.0])),
    "long axis": (WATER, 3000, dict(T=[290.0, 300.0], U_Umf=np.linspace(1.2, 8.0, 7001))),
}


def _xarray_layout(plan, path: Path, sha: str) -> None:
    """The layout as the store wrote it before: xarray's to_zarr of the template."""
    ds = _template(plan)
    ds.attrs["store_fingerprint_sha256"] = sha
    encoding = {name: {"chunks": tuple(plan.chunks[d][0] for d in var.dims),
                       "compressors": [ZstdCodec(level=1), Crc32cCodec()]}
                for name, var in ds.data_vars.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds.to_zarr(path, mode="w", compute=False, encoding=encoding, zarr_format=3,
                   consolidated=False)


def _files(path: Path) -> dict:
    return {p.relative_to(path).as_posix(): p.read_bytes()
            for p in sorted(path.rglob("*")) if p.is_file()}


@pytest.mark.parametrize("case", CASES)
def test_layout_files_equal_xarrays_byte_for_byte(case, tmp_path):
    scene, chunks, grid = CASES[case]
    plan = _plan(scene, chunks, 16, grid)
    layout = _Layout.of(plan)
    sha = _sha(layout.fingerprint())
    _xarray_layout(plan, tmp_path / "x", sha)
    expected = _files(tmp_path / "x")
    got = _layout_files(layout, sha)
    assert sorted(got) == sorted(expected)
    for name in expected:
        assert got[name] == expected[name], name
    data_vars = set(plan.variables)
    manifest = {k: hashlib.sha256(v).hexdigest() for k, v in got.items()
                if k.endswith("zarr.json") or k.split("/")[0] not in data_vars}
    assert manifest == _manifest(tmp_path / "x", data_vars)


@pytest.mark.parametrize("case", CASES)
def test_fingerprint_from_the_plan_equals_the_lazy_sweeps(case):
    scene, chunks, grid = CASES[case]
    assert (_Layout.of(_plan(scene, chunks, 16, grid)).fingerprint()
            == fingerprint(build(scene, chunks=chunks, **grid)))


def test_a_store_reads_back_with_xarray_as_the_sweep(tmp_path):
    """Read by plain xarray (no agglomtool): variables, attributes, CF encodings."""
    scene, chunks, grid = CASES["names"]
    ref = sweep(scene, chunks=chunks, **grid)
    sweep(scene, chunks=chunks, store=tmp_path / "s", **grid).close()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = xr.open_zarr(tmp_path / "s" / _DATA, consolidated=False).compute()
    sha = _sha(fingerprint(build(scene, chunks=chunks, **grid)))
    assert got.attrs.pop("store_fingerprint_sha256") == sha
    xr.testing.assert_identical(ref, got)
    xr.testing.assert_identical(got, open_store(tmp_path / "s").compute())
    for name, var in got.variables.items():
        assert var.encoding["dtype"] == ref[name].dtype, name
        if var.dtype.kind == "f":
            assert np.isnan(var.encoding["_FillValue"]), name
