"""Big grids: the estimate before a sweep, the refusal of a result larger than memory, the
progress bar, no dask warning, the compile notice."""

import logging
import math
import time
import warnings

import numpy as np
import pytest
import xarray as xr

from agglomtool.maps import build, estimate_sweep, sweep
from agglomtool.maps import estimate as estimate_module
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=300e-6)
GRID = dict(T=np.linspace(950.0, 1250.0, 5), solid_j=["silica-sand", "ilmenite"],
            h0=[0.15e-6, 0.3e-6, 0.6e-6], U_Umf=[2.0, 4.0, 6.0, 8.0])
#: 1e11 points: 4642 values on each of three axes.
HUGE = dict(T=np.linspace(900.0, 1300.0, 4642), h0=np.geomspace(1e-7, 2e-6, 4642),
            U_Umf=np.linspace(1.1, 8.0, 4642))


def _quiet(fn, *args, **kw):
    """``fn(*args, **kw)`` with every warning an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return fn(*args, **kw)


def test_counts_and_sizes_are_those_of_the_result(tmp_path):
    """Points, blocks and bytes are exact: the in-memory size is the result's own nbytes,
    the store's the same arrays uncompressed; blocks follow the chunks (names by one)."""
    est = estimate_sweep(SCENE, chunks=4, store=tmp_path / "s", **GRID)
    ds = sweep(SCENE, chunks=4, **GRID)
    assert est.points == 5 * 2 * 3 * 4 == ds.propensity.size
    # chunks=4: the last axes whole first: U_Umf 4, then h0 1, solid_j 1, T 1
    assert est.blocks == 5 * 2 * 3 * 1
    assert est.memory_bytes == ds.nbytes
    assert est.store_bytes == ds.nbytes
    assert estimate_sweep(SCENE, chunks=None, **GRID).blocks == 2  # one per solid_j name
    assert estimate_sweep(SCENE, **GRID).store_bytes is None


def test_time_is_measured_and_positive():
    est = estimate_sweep(SCENE, chunks=None, calibrate=True, **GRID)
    assert est.seconds is not None and 0.0 < est.seconds < math.inf
    assert "1 block (60 points) timed here" in est.method
    assert "estimate" in est.describe()
    assert estimate_sweep(SCENE, chunks=None, **GRID).seconds is None  # small: not timed


def test_a_sweep_logs_its_time_after_its_first_block(monkeypatch, caplog):
    monkeypatch.setattr(estimate_module, "CALIBRATE_ABOVE", 10)
    seen = []
    monkeypatch.setattr(estimate_module, "warm_up", lambda plan: seen.append("warm-up"))
    with caplog.at_level(logging.INFO, logger="agglomtool.maps"):
        ds = sweep(SCENE, chunks=4, **GRID)
    (line,) = [r.getMessage() for r in caplog.records if "points" in r.getMessage()]
    assert "sweep of 120 points in 30 blocks: about" in line
    assert "3 blocks (12 points) timed" in line
    assert seen == ["warm-up"]
    xr.testing.assert_identical(ds, sweep(SCENE, chunks=None, **GRID))


def test_a_result_larger_than_memory_is_refused_at_once():
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"store=") as info:
        sweep(Scene(), **HUGE)
    assert time.perf_counter() - t0 < 2.0
    msg = str(info.value)
    assert "1e+11 points" in msg and "available" in msg


def test_the_refusal_names_what_is_needed_and_what_is_available(monkeypatch):
    need = estimate_sweep(SCENE, **GRID).memory_bytes
    monkeypatch.setattr(estimate_module, "available_memory", lambda: need - 1)
    with pytest.raises(ValueError, match=r"store=") as info:
        sweep(SCENE, **GRID)
    assert (info.value.needed, info.value.available) == (need, need - 1)
    assert "in memory" in str(info.value) and "available" in str(info.value)
    monkeypatch.setattr(estimate_module, "available_memory", lambda: need)
    sweep(SCENE, **GRID)  # fits exactly: runs


def test_a_huge_store_sweep_reaches_its_first_block_without_a_huge_graph(tmp_path,
                                                                          monkeypatch):
    """1e11 points into a store: no task graph over its 385286 blocks is built first (the
    old one took 19 s and 1.7 GB, and dask warned); the first block is interrupted here."""
    from agglomtool.maps.plan import SweepPlan

    est = estimate_sweep(Scene(), store=tmp_path / "s", calibrate=False, **HUGE)
    assert est.points == 4642**3 and est.blocks == 4642 * 83
    assert est.store_bytes > 1e12

    class FirstBlock(Exception):
        pass

    def first_block(self, sl, wanted):
        raise FirstBlock

    monkeypatch.setattr(SweepPlan, "evaluate", first_block)
    t0 = time.perf_counter()
    with pytest.raises(FirstBlock):
        _quiet(sweep, Scene(), store=tmp_path / "s", **HUGE)
    assert time.perf_counter() - t0 < 60.0
    assert sum(f.stat().st_size for f in (tmp_path / "s").rglob("*") if f.is_file()) < 1e6


def test_run_with_store_of_a_lazy_sweep(tmp_path):
    """The public entry with a Dataset of build(): its blocks come from the plan it
    records."""
    from agglomtool.maps.store import run_with_store

    got = run_with_store(build(SCENE, chunks=7, **GRID), tmp_path / "s").compute()
    xr.testing.assert_identical(sweep(SCENE, chunks=None, **GRID), got)
    with pytest.raises(ValueError, match="not a sweep made by agglomtool.maps.build"):
        run_with_store(xr.Dataset(), tmp_path / "t")


def test_no_dask_warning_where_many_blocks_broadcast():
    """Blocks split along two axes: dask's blockwise broadcasting used to warn
    ("Increasing number of chunks by factor of 11")."""
    grid = dict(T=np.linspace(950.0, 1250.0, 11), h0=np.geomspace(0.15e-6, 1e-6, 11))
    lazy = _quiet(build, SCENE, chunks={"T": 1, "h0": 1}, **grid)
    assert len(lazy.chunks["T"]) == 11 and len(lazy.chunks["h0"]) == 11
    got = _quiet(sweep, SCENE, chunks={"T": 1, "h0": 1}, **grid)
    ref = sweep(SCENE, chunks=None, **grid)
    xr.testing.assert_identical(ref, got)
    xr.testing.assert_identical(ref, lazy.compute(scheduler="synchronous"))


def test_lazy_and_computed_sweeps_agree_bitwise(tmp_path):
    ref = sweep(SCENE, chunks=None, **GRID)
    for got in (build(SCENE, chunks=5, **GRID).compute(scheduler="synchronous"),
                sweep(SCENE, chunks=5, **GRID),
                sweep(SCENE, chunks=5, store=tmp_path / "s", **GRID).compute()):
        xr.testing.assert_identical(ref, got)
        for name in ref.data_vars:
            assert ref[name].values.tobytes() == got[name].values.tobytes(), name


def test_big_sweeps_log_the_estimate_once(monkeypatch, caplog):
    monkeypatch.setattr(estimate_module, "BIG_POINTS", 10)
    with caplog.at_level(logging.INFO, logger="agglomtool.maps"):
        sweep(SCENE, **GRID)
    lines = [r for r in caplog.records if "points" in r.getMessage()]
    assert len(lines) == 1 and lines[0].levelno == logging.WARNING
    assert "120 points" in lines[0].getMessage()


def test_small_sweeps_log_it_at_info_only(caplog):
    with caplog.at_level(logging.INFO, logger="agglomtool.maps"):
        sweep(SCENE, **GRID)
    lines = [r for r in caplog.records if "points" in r.getMessage()]
    assert len(lines) == 1 and lines[0].levelno == logging.INFO


def test_progress_bar_shows_points_rate_and_time_left(capfd):
    sweep(SCENE, chunks=4, progress=True, **GRID)
    err = capfd.readouterr().err
    assert "120/120" in err and "pt/s" in err and "100%" in err
    assert "<" in err  # tqdm's [elapsed<remaining, rate]


def test_progress_off_writes_nothing(capfd):
    sweep(SCENE, chunks=4, **GRID)
    assert capfd.readouterr().err == ""


def test_compile_notice_is_said_once():
    import numba

    from agglomtool.maps.progress import compile_notice

    said = []
    with compile_notice(said.append, seconds=12):
        numba.njit(lambda x: x + 1)(1)
        numba.njit(lambda x: x + 2)(1)
    assert len(said) == 1 and "compiling kernels (first run only, ~12 s)" in said[0]
    with compile_notice(said.append, seconds=12):
        pass
    assert len(said) == 1
