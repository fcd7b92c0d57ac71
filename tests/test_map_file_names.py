"""Names on a map file's axes (a solid, a liquid, a mode) are written as CF character
arrays and read back as the map had them in memory.

The netCDF library of netCDF4 1.7.3 and later (netCDF-C 4.9.3, 4.10.1) ends the Python
process with a segmentation fault when a file holding netCDF-4 variable-length strings is
opened again after another of its handles was closed: a map left open in a session while
a picture of it is drawn was enough. The crash is checked in a child process (it would take
the test run with it)."""

import subprocess
import sys
import textwrap

import netCDF4
import numpy as np
import xarray as xr

import agglomtool as at
from agglomtool.maps.export import read_names
from agglomtool.plots import open_map


def _names_map(tmp_path):
    ds = at.sweep(at.Scene(liquid="water", T=298.15, d_i=300e-6),
                  solid_j=["silica-sand", "ilmenite"], h0=[2e-6, 5e-6], U_Umf=[1.5, 3.0])
    path = tmp_path / "names.nc"
    at.write_map(ds, path)
    return ds, path


def test_names_are_character_arrays_read_back_as_str(tmp_path):
    ds, path = _names_map(tmp_path)
    with netCDF4.Dataset(path) as f:
        assert f["solid_j"].dtype == np.dtype("S1")  # not a variable-length string
    back = open_map(path)
    assert back["solid_j"].dtype == ds["solid_j"].dtype
    assert back["solid_j"].values.tolist() == ["silica-sand", "ilmenite"]
    xr.testing.assert_equal(back["propensity"], ds["propensity"])
    with xr.open_dataset(path) as raw:  # xarray alone gives objects; the same names
        assert read_names(raw)["solid_j"].values.tolist() == ["silica-sand", "ilmenite"]


REOPEN = """
import sys
import xarray as xr
from agglomtool.plots import operating_window
path = sys.argv[1]
kept = xr.open_dataset(path)  # a map left open in a session
for _ in range(3):
    with xr.open_dataset(path) as other:
        other["solid_j"].values
    operating_window(path)
print("survived")
"""


def test_a_map_file_opened_twice_does_not_crash_the_process(tmp_path):
    _, path = _names_map(tmp_path)
    job = tmp_path / "reopen.py"
    job.write_text(textwrap.dedent(REOPEN))
    out = subprocess.run([sys.executable, str(job), str(path)], capture_output=True,
                         text=True, timeout=600, env={"MPLBACKEND": "Agg",
                                                      **__import__("os").environ})
    assert out.returncode == 0, (out.returncode, out.stderr[-2000:])
    assert out.stdout.split()[-1] == "survived"
