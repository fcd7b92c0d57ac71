"""A sweep on a 2-worker dask.distributed LocalCluster against the default (one process).

    python benchmarks/bench_cluster.py [--points 330000] [--repeats 3]

Times, best and median of ``--repeats`` after one warm-up each (Numba's cache load in every
worker process): the default in-memory sweep, the default into a store, and the same two
with ``client=`` a ``LocalCluster(n_workers=2, processes=True, threads_per_worker=1)``.
Prints the load average: the machine may be shared, and the figures are noisy.

What to expect: the default already runs the compiled collision kernel on every core of the
process, so on one machine a cluster can only add overhead (process start, pickling each
block's graph, moving results, and each worker's Numba threads competing for the same cores).
A cluster pays off when its workers are on other machines, each with its own cores.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import tempfile
import time

import numpy as np

from agglomtool.maps import sweep
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)


def grid(points: int) -> dict:
    n_t = max(1, points // 10_000)
    return dict(T=np.linspace(900.0, 1300.0, n_t), h0=np.geomspace(0.12e-6, 2e-6, 100),
                U_Umf=np.linspace(1.5, 8.0, 100))


def timed(fn, repeats: int) -> list[float]:
    fn()  # warm-up
    out = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=330_000)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    g = grid(a.points)
    n = int(np.prod([len(v) for v in g.values()]))
    tmp = tempfile.mkdtemp()

    def stored(**kw):
        path = os.path.join(tmp, "s")
        shutil.rmtree(path, ignore_errors=True)
        sweep(SCENE, store=path, **kw, **g).close()

    from distributed import Client, LocalCluster

    runs = {
        "default, in memory": lambda: sweep(SCENE, client=False, **g),
        "default, store": lambda: stored(client=False),
    }
    results = {k: timed(f, a.repeats) for k, f in runs.items()}
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        results["2-worker cluster, in memory"] = timed(
            lambda: sweep(SCENE, client=client, **g), a.repeats)
        results["2-worker cluster, store"] = timed(lambda: stored(client=client), a.repeats)
    shutil.rmtree(tmp, ignore_errors=True)
    blocks = sweep(SCENE, compute=False, **g).propensity.data.npartitions
    print(f"{n:,} points, {blocks} blocks, {os.cpu_count()} CPUs, load average "
          f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    base = min(results["default, in memory"])
    for k, v in results.items():
        print(f"  {k:30s} best {min(v):6.2f} s  median {statistics.median(v):6.2f} s  "
              f"({min(v) / base:4.2f}x the default's best)")


if __name__ == "__main__":
    main()
