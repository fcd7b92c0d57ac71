"""An in-memory map's automatic block size follows the thread count (fewer, larger blocks on
many threads); a store's and a lazy map's blocks do not; the values never depend on it."""

import logging

import numba
import numpy as np
import pytest
import xarray as xr

from agglomtool.maps import build, layout, sweep
from agglomtool.maps.estimate import estimate_sweep
from agglomtool.maps.layout import DEFAULT_BLOCK, IN_MEMORY_BLOCK, MAX_BLOCK_FACTOR, auto_block
from agglomtool.scene import Scene

WATER = Scene(liquid="water", T=298.15, d_i=300e-6)
AXES = dict(T=np.linspace(283.15, 363.15, 6), h0=np.geomspace(1e-6, 30e-6, 5),
            U_Umf=np.linspace(1.2, 8.0, 7))


@pytest.mark.parametrize("threads, factor", [(1, 1), (2, 1), (7, 1), (8, 2), (16, 4),
                                             (31, 7), (32, 8), (256, MAX_BLOCK_FACTOR)])
def test_auto_block_grows_with_threads_and_is_capped(threads, factor):
    assert auto_block(threads) == factor * IN_MEMORY_BLOCK


def _spy(monkeypatch, points):
    """Replace the sweep's auto_block by one giving ``points``; the thread counts it saw."""
    seen = []

    def fake(threads):
        seen.append(threads)
        return points

    monkeypatch.setattr(layout, "auto_block", fake)
    return seen


def test_in_memory_auto_map_uses_the_thread_counts_block(monkeypatch, caplog):
    seen = _spy(monkeypatch, 35)  # 6 x 5 x 7 = 210 points: 6 blocks of 35
    with caplog.at_level(logging.INFO, logger="agglomtool.maps"):
        ds = sweep(WATER, **AXES)
    assert seen == [numba.get_num_threads()]
    assert any("in 6 blocks" in r.getMessage() for r in caplog.records)
    whole = sweep(WATER, chunks=None, **AXES)
    xr.testing.assert_identical(ds, whole)
    for name in ds.variables:  # bit for bit, NaN and -0.0 included
        a, b = np.ascontiguousarray(ds[name].values), np.ascontiguousarray(whole[name].values)
        assert a.tobytes() == b.tobytes(), name


def test_store_lazy_and_explicit_blocks_do_not_follow_the_threads(monkeypatch, tmp_path):
    seen = _spy(monkeypatch, 35)
    sweep(WATER, store=tmp_path / "s", **AXES)
    build(WATER, **AXES)
    sweep(WATER, chunks=DEFAULT_BLOCK, **AXES)
    sweep(WATER, chunks="auto", client=None, compute=False, **AXES)
    assert seen == []


def test_the_estimate_plans_the_sweeps_blocks(monkeypatch):
    """estimate_sweep counts the blocks the sweep will compute: the thread count's in
    memory, the fixed size into a store."""
    seen = _spy(monkeypatch, 35)
    assert estimate_sweep(WATER, calibrate=False, **AXES).blocks == 6
    assert seen == [numba.get_num_threads()]
    assert estimate_sweep(WATER, calibrate=False, store="s", **AXES).blocks == 1
    assert seen == [numba.get_num_threads()]
