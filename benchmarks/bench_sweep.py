"""Sweep benchmarks: the time of a 1e6-point map and the peak memory of a 1e7-point sweep.

    python benchmarks/bench_sweep.py             # both
    python benchmarks/bench_sweep.py --map       # 1e6-point map, best and median of 5
    python benchmarks/bench_sweep.py --big DIR   # 1e7 points into a store in DIR, then
                                                 # again over the finished store

The map is T (100) x h0 (100) x U_Umf (100) of silica sand with the paper's slag: gas and
liquid properties, U_mf, 1e4 u0* solves (u0* does not depend on U/U_mf), 1e6 collisions
at the typical speed and 16 quadrature nodes per point for the propensity. Peak memory is
the process's maximum resident set size (``resource.getrusage``), measured in a fresh
subprocess so that nothing else counts.
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

from agglomtool.maps import sweep
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)


def grid(n_t, n_h, n_u):
    return dict(T=np.linspace(900.0, 1300.0, n_t), h0=np.geomspace(0.12e-6, 2e-6, n_h),
                U_Umf=np.linspace(1.5, 8.0, n_u))


def bench_map(repeats: int = 5) -> None:
    sweep(SCENE, **grid(4, 4, 4))  # compile and warm the property tables
    times = []
    load = os.getloadavg()
    for _ in range(repeats):
        t = time.perf_counter()
        ds = sweep(SCENE, **grid(100, 100, 100))
        times.append(time.perf_counter() - t)
    print(f"1e6-point map ({ds.propensity.size} points, {ds.u_star.size} u0* solves): "
          f"best {min(times):.2f} s, median {np.median(times):.2f} s of {repeats} (all: "
          f"{', '.join(f'{x:.2f}' for x in times)}); load average {load} at start, "
          f"{os.getloadavg()} at end")


def bench_big(store: str) -> None:
    t = time.perf_counter()
    ds = sweep(SCENE, store=store, progress=True, **grid(100, 1000, 100))
    mean = float(ds.propensity.mean().compute(scheduler="synchronous"))
    dt = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"1e7-point chunked sweep into {store}: {dt:.1f} s, mean propensity {mean:.4f}, "
          f"peak RSS {peak:.0f} MB (the result's data variables would take "
          f"{ds.nbytes / 1e6:.0f} MB in memory)")
    t = time.perf_counter()
    sweep(SCENE, store=store, **grid(100, 1000, 100)).close()
    print(f"  run again over the finished store (every block read back and checked): "
          f"{time.perf_counter() - t:.1f} s, peak RSS "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0:.0f} MB")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--map", action="store_true")
    ap.add_argument("--big", metavar="DIR")
    a = ap.parse_args()
    if a.map:
        bench_map()
    elif a.big:
        bench_big(a.big)
    else:
        subprocess.run([sys.executable, __file__, "--map"], check=True)
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([sys.executable, __file__, "--big", d + "/store"], check=True)
