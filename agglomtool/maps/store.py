"""Resumable sweeps: finished blocks are written to a directory and skipped on restart.

Layout of a store directory::

    manifest.json            what the sweep is (grid, chunks, scene, version)
    block_<i>_<j>_....nc     one netCDF file per finished block (written atomically)

A block file is written to ``*.nc.tmp`` and renamed when complete, so an interrupted run
leaves no half-written block behind. The result is opened lazily from the block files.
"""

from __future__ import annotations

import contextlib
import itertools
import json
import os
import sys
import time
from pathlib import Path

import dask
import numpy as np
import xarray as xr

__all__ = ["run_with_store", "open_store", "progress_callback", "Progress"]


class Progress:
    """A progress bar on stderr: ``tqdm`` when installed, else one rewritten text line."""

    def __init__(self, total: int, desc: str = "sweep", enabled: bool = True,
                 unit: str = "block"):
        self.total, self.desc, self.enabled, self.n, self.unit = total, desc, enabled, 0, unit
        self._bar = None
        self._t0 = self._last = time.perf_counter()
        if enabled:
            try:
                from tqdm import tqdm

                self._bar = tqdm(total=total, desc=desc, unit=unit)
            except ImportError:
                self._draw()

    def _draw(self) -> None:
        frac = self.n / self.total if self.total else 1.0
        bar = "#" * int(30 * frac)
        dt = time.perf_counter() - self._t0
        sys.stderr.write(
            f"\r{self.desc}: [{bar:<30}] {self.n}/{self.total} {self.unit}s {dt:6.1f} s")
        sys.stderr.flush()

    def update(self, k: int = 1) -> None:
        self.n += k
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.update(k)
        elif self.n == self.total or time.perf_counter() - self._last > 0.2:
            self._last = time.perf_counter()
            self._draw()

    def close(self) -> None:
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.close()
        else:
            self._draw()
            sys.stderr.write("\n")


@contextlib.contextmanager
def progress_callback():
    """Progress of a dask computation (tasks), shown with :class:`Progress`."""
    from dask.callbacks import Callback

    class _CB(Callback):
        def _start_state(self, dsk, state):
            n = len(state["ready"]) + len(state["waiting"])
            self.bar = Progress(n, "sweep", unit="task")

        def _posttask(self, key, result, dsk, state, worker_id):
            self.bar.update()

        def _finish(self, dsk, state, errored):
            self.bar.close()

    with _CB():
        yield


def _manifest(ds: xr.Dataset) -> dict:
    chunks = {k: [int(c) for c in v] for k, v in ds.chunks.items()}
    coords = {k: np.asarray(ds[k].values).tolist() for k in ds.dims}
    return {"dims": list(ds.dims), "chunks": chunks, "coords": coords,
            "scene": ds.attrs.get("scene"), "nodes": ds.attrs.get("quadrature_nodes"),
            "agglomtool_version": ds.attrs.get("agglomtool_version")}


def _blocks(chunks: dict):
    """(index tuple, {dim: slice}) of every block, in C order."""
    dims = list(chunks)
    starts = {d: np.concatenate([[0], np.cumsum(chunks[d])]) for d in dims}
    for idx in itertools.product(*[range(len(chunks[d])) for d in dims]):
        sl = {d: slice(int(starts[d][i]), int(starts[d][i + 1])) for d, i in zip(dims, idx,
                                                                                strict=True)}
        yield idx, sl


def run_with_store(ds: xr.Dataset, store, *, progress: bool = False) -> xr.Dataset:
    """Compute the lazy sweep ``ds`` block by block into ``store``; skip finished blocks.

    Raises
    ------
    ValueError
        If ``store`` holds blocks of a different sweep (another grid, chunking or scene).
    """
    store = Path(store)
    store.mkdir(parents=True, exist_ok=True)
    manifest = _manifest(ds)
    mpath = store / "manifest.json"
    if mpath.exists():
        old = json.loads(mpath.read_text())
        if old != json.loads(json.dumps(manifest)):
            raise ValueError(
                f"store {store} holds a different sweep (grid, chunks or scene differ); "
                "use another directory or delete it"
            )
    else:
        mpath.write_text(json.dumps(manifest))
    for tmp in store.glob("*.nc.tmp"):
        tmp.unlink()
    chunks = {d: manifest["chunks"][d] for d in manifest["dims"]}
    blocks = list(_blocks(chunks))
    bar = Progress(len(blocks), f"sweep -> {store}", progress)
    with dask.config.set(scheduler="synchronous"):
        for idx, sl in blocks:
            path = store / ("block_" + "_".join(str(i) for i in idx) + ".nc")
            if not path.exists():
                part = ds.isel(sl).compute()
                tmp = path.with_name(path.name + ".tmp")
                part.to_netcdf(tmp)
                os.replace(tmp, path)
            bar.update()
    bar.close()
    return open_store(store)


def open_store(store) -> xr.Dataset:
    """The Dataset of a finished store, opened lazily (dask) from its block files.

    Blocks are put together in the order of the manifest (``combine="nested"``), so
    coordinates keep the order of the grid as given.
    """
    store = Path(store)
    mpath = store / "manifest.json"
    if not mpath.exists():
        raise ValueError(f"{store} is not a sweep store (no manifest.json)")
    manifest = json.loads(mpath.read_text())
    dims = manifest["dims"]
    counts = [len(manifest["chunks"][d]) for d in dims]
    missing = []

    def nest(prefix):
        if len(prefix) == len(dims):
            path = store / ("block_" + "_".join(str(i) for i in prefix) + ".nc")
            if not path.exists():
                missing.append(path.name)
            return str(path)
        return [nest(prefix + (i,)) for i in range(counts[len(prefix)])]

    files = nest(())
    if missing:
        raise ValueError(f"store {store} is incomplete: {len(missing)} blocks missing "
                         f"(first: {missing[0]}); run the sweep again to finish it")
    return xr.open_mfdataset(
        files, combine="nested", concat_dim=dims, data_vars="minimal", coords="minimal",
        compat="override", parallel=False,
    )
