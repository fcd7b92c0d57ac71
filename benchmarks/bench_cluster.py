"""What a sweep on a dask.distributed cluster costs the client: per block and fixed.

    python benchmarks/bench_cluster.py [--points 1000000] [--repeats 5] [--workers 2]
                                       [--few 4] [--many 100]

The README's kind of map (water on 300 um sand, T x h0 x U/U_mf, the default excess-gas
speeds, u0* at every point, propensity) of ``--points`` points, computed:

- here, in memory and into a store (``client=False``, the default block size);
- on a ``LocalCluster(n_workers=--workers, processes=True, threads_per_worker=1)``, in
  memory and into a store, cut into ``--few`` and into ``--many`` blocks.

Each is timed ``--repeats`` times after one warm-up (Numba's cache load in every worker),
the runs interleaved; the wall time and the CPU time of this process (the client, which
here also runs the scheduler) are printed, best and median. From them:

- the client's CPU per block: the slope between ``--few`` and ``--many`` blocks (the same
  points, so the same numbers to compute and to move), in memory and into a store;
- the store's fixed cost to the client: its CPU into a store less in memory at ``--few``
  blocks, less the per-block difference times ``--few`` (the layout, the fingerprint,
  opening the store, its summaries).

Prints which agglomtool it timed (an A/B runs it with another checkout on PYTHONPATH), the
core count and the load average: the machine may be shared, and the figures are noisy.

What to expect: the default already runs the compiled collision kernel on every core of the
process, so on one machine a cluster can only add overhead (process start, moving results,
and each worker's Numba threads competing for the same cores). A cluster pays off when its
workers are on other machines, each with its own cores.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import tempfile
import time
import warnings

import numpy as np

import agglomtool
from agglomtool.maps import sweep
from agglomtool.scene import Scene

WATER = Scene(liquid="water", T=298.15, d_i=300e-6)


def grid(points: int) -> dict:
    n_t = max(1, points // 40_000)
    return dict(T=np.linspace(283.15, 363.15, n_t), h0=np.geomspace(1e-6, 30e-6, 200),
                U_Umf=np.linspace(1.2, 8.0, 200))


def fmt(values: list[float]) -> str:
    return f"best {min(values):6.3f} s, median {statistics.median(values):6.3f} s"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--few", type=int, default=4)
    ap.add_argument("--many", type=int, default=100)
    a = ap.parse_args()
    warnings.simplefilter("ignore")
    g = grid(a.points)
    n = int(np.prod([len(v) for v in g.values()]))
    print(f"agglomtool from {os.path.dirname(agglomtool.__file__)}; {n:,} points; "
          f"{os.cpu_count()} CPUs; load {os.getloadavg()}", flush=True)
    tmp = tempfile.mkdtemp()

    def run(client, chunks, store):
        path = os.path.join(tmp, "s")
        kw = {"store": path} if store else {}
        if chunks is not None:
            kw["chunks"] = chunks
        c, t = time.process_time(), time.perf_counter()
        ds = sweep(WATER, client=client, **kw, **g)
        wall, cpu = time.perf_counter() - t, time.process_time() - c
        ds.close()
        shutil.rmtree(path, ignore_errors=True)
        return wall, cpu

    from distributed import Client, LocalCluster

    from agglomtool.maps.plan import SweepPlan

    few, many = -(-n // a.few), -(-n // a.many)  # points per block
    blocks_of = {c: SweepPlan.from_dataset(sweep(WATER, chunks=c, compute=False, **g)).n_blocks
                 for c in (few, many)}
    cases = {("here", None, False): "here, in memory", ("here", None, True): "here, store"}
    for chunks, blocks in blocks_of.items():
        cases["cluster", chunks, False] = f"cluster, in memory, {blocks} blocks"
        cases["cluster", chunks, True] = f"cluster, store, {blocks} blocks"
    got: dict = {k: [] for k in cases}
    with LocalCluster(n_workers=a.workers, processes=True, threads_per_worker=1,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        for where, chunks, store in cases:  # warm-up
            run(client if where == "cluster" else False, chunks, store)
        for _ in range(a.repeats):
            for where, chunks, store in cases:
                got[where, chunks, store].append(
                    run(client if where == "cluster" else False, chunks, store))
    shutil.rmtree(tmp, ignore_errors=True)
    for key, name in cases.items():
        walls, cpus = [w for w, _ in got[key]], [c for _, c in got[key]]
        print(f"  {name:32s} wall {fmt(walls)}; client CPU {fmt(cpus)}")
    for how in (min, statistics.median):
        cpu = {k: how([c for _, c in v]) for k, v in got.items()}
        per = {s: (cpu["cluster", many, s] - cpu["cluster", few, s])
               / (blocks_of[many] - blocks_of[few]) for s in (False, True)}
        fixed = (cpu["cluster", few, True] - cpu["cluster", few, False]
                 - (per[True] - per[False]) * blocks_of[few])
        print(f"  ({how.__name__}) client CPU per block: in memory {per[False] * 1e3:.2f} ms, "
              f"into a store {per[True] * 1e3:.2f} ms; the store's fixed cost "
              f"{fixed * 1e3:.0f} ms")
    print(f"load {os.getloadavg()}")


if __name__ == "__main__":
    main()
