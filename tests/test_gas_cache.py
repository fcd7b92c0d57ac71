"""The disk cache of the gas tables: a cold command-line call without importing CoolProp."""

import subprocess
import sys

import numpy as np

from agglomtool.properties import _gas_tables as gt

CODE = """
import sys
from agglomtool.properties import gas_properties
g = gas_properties([300.0, 1073.15, 1500.0], 101325.0, "air")
print(repr(g.mu.tolist()), repr(g.rho.tolist()), "CoolProp" in sys.modules, sep="|")
"""


def _run(env_dir):
    import os

    env = {**os.environ, "AGGLOMTOOL_CACHE_DIR": str(env_dir)}
    out = subprocess.run([sys.executable, "-c", CODE], env=env, capture_output=True,
                         text=True, check=True).stdout.strip().split("|")
    return out[0], out[1], out[2] == "True"


def test_cached_table_gives_the_same_numbers_without_coolprop(tmp_path):
    mu1, rho1, imported1 = _run(tmp_path)
    assert imported1  # the first call builds the table with CoolProp
    assert len(list(tmp_path.glob("gas-table-Air-*.npz"))) == 1
    mu2, rho2, imported2 = _run(tmp_path)
    assert (mu2, rho2) == (mu1, rho1)  # bit for bit (repr of the floats)
    assert not imported2  # answered from the cache


def test_corrupt_cache_file_is_rebuilt(tmp_path):
    mu1, rho1, _ = _run(tmp_path)
    (path,) = tmp_path.glob("gas-table-Air-*.npz")
    path.write_bytes(b"garbage")
    mu2, rho2, imported = _run(tmp_path)
    assert imported and (mu2, rho2) == (mu1, rho1)
    with np.load(path) as data:  # rewritten whole
        assert data["ln_mu"].shape == (gt.T_GRID[2], gt.P_GRID[2])


def test_no_writable_directory_means_no_disk_cache(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("AGGLOMTOOL_CACHE_DIR", str(blocker / "sub"))
    assert gt.cache_dir() is None
    assert gt._cache_file("Air") is None
