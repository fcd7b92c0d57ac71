"""Strong scaling of 4e6-point operating maps and of a 30 x 30 bed sweep over Numba threads.

    python benchmarks/bench_scaling.py [--threads 1 2 4 8 16] [--repeats 3] [--bed]
                                       [--profile DIR] [--cluster N]

For each thread count (``numba.set_num_threads``; the process must start with at least as
many, ``NUMBA_NUM_THREADS``), best and median of ``--repeats`` of:

- a 4e6-point water map (300 um sand, T 100 x h0 200 x U/U_mf 200, the default excess-gas
  speeds, u0* at every point, propensity), the README's kind of map;
- the same for the paper's slag against 1 mm sand;
- one plain 4e6-point ``collide`` of the water map's pairs at their typical speed (the
  kernel alone, what the map is held against).

The efficiency from 2 to n threads is ``t(2) / (t(n) n / 2)`` on the medians. ``--bed``
adds the 30 x 30 ``bed_sweep`` of the 3-component x 20-class water bed of
``bench_bed.py`` at 2 threads and at the most; ``--profile DIR`` writes a cProfile of one
water map at the most threads (the serial remainder: time spent outside the compiled
kernels); ``--cluster N`` times the water map on a LocalCluster of N one-thread workers.
The figures depend on the machine: the script prints its core count and load average.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import statistics
import sys
import time
import warnings

import numba
import numpy as np

from agglomtool.maps import sweep
from agglomtool.scene import Resolved, Scene

WATER = Scene(liquid="water", T=298.15, d_i=300e-6)
SLAG = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
AXES = {
    "water": (WATER, dict(T=np.linspace(283.15, 363.15, 100), h0=np.geomspace(1e-6, 30e-6, 200),
                          U_Umf=np.linspace(1.2, 8.0, 200))),
    "slag": (SLAG, dict(T=np.linspace(900.0, 1300.0, 100), h0=np.geomspace(0.12e-6, 2e-6, 200),
                        U_Umf=np.linspace(1.2, 8.0, 200))),
}


def small(axes):
    return {k: v[::40] for k, v in axes.items()}


def plain_collide(scene, axes):
    """One plain collide of the map's pairs at their typical speed (inputs resolved first)."""
    names = list(axes)
    values = dict(scene.values())
    for k, name in enumerate(names):
        shape = [1] * len(names)
        shape[k] = -1
        values[name] = np.asarray(axes[name]).reshape(shape)
    r = Resolved(values)
    u = np.broadcast_to(r.u_typical, tuple(len(axes[n]) for n in names))
    r.collide(u[:1, :1, :1])
    return lambda: r.collide(u)


def timed(fn, repeats):
    out = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return out


def fmt(ts):
    return f"best {min(ts):.3f} s, median {statistics.median(ts):.3f} s"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, nargs="*", default=[1, 2, 4, 8, 16])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--bed", action="store_true")
    ap.add_argument("--profile", metavar="DIR")
    ap.add_argument("--cluster", type=int, default=0)
    a = ap.parse_args()
    threads = [n for n in a.threads if n <= numba.config.NUMBA_NUM_THREADS]
    print(f"{os.cpu_count()} cores, Numba {numba.__version__} threading layer "
          f"{numba.config.THREADING_LAYER}, NUMBA_NUM_THREADS {numba.config.NUMBA_NUM_THREADS}, "
          f"numpy {np.__version__}, load {os.getloadavg()}", flush=True)
    warnings.simplefilter("ignore")
    t0 = time.perf_counter()
    for scene, axes in AXES.values():
        sweep(scene, **small(axes))
    col = plain_collide(*AXES["water"])
    col()
    print(f"compile and warm-up {time.perf_counter() - t0:.1f} s", flush=True)
    med = {}
    for n in threads:
        numba.set_num_threads(n)
        line = [f"{n:2d} threads"]
        for name, (scene, axes) in AXES.items():
            ts = timed(lambda s=scene, x=axes: sweep(s, **x), a.repeats)
            med[name, n] = statistics.median(ts)
            line.append(f"{name} map {fmt(ts)}")
        ts = timed(col, a.repeats)
        med["collide", n] = statistics.median(ts)
        line.append(f"plain collide {fmt(ts)}")
        print(line[0] + ": " + "; ".join(line[1:]) + f"; load {os.getloadavg()[0]:.1f}", flush=True)
    if 2 in threads:
        for name in ("water", "slag", "collide"):
            eff = ", ".join(f"{n}: {med[name, 2] / (med[name, n] * n / 2):.0%}"
                            for n in threads if n > 2)
            ratio = ", ".join(f"{n}: {med[name, n] / med['collide', n]:.2f}x"
                              for n in threads if name != "collide")
            print(f"{name}: efficiency from 2 threads {eff}"
                  + (f"; map / collide {ratio}" if ratio else ""), flush=True)
    top = max(threads)
    numba.set_num_threads(top)
    if a.profile:
        os.makedirs(a.profile, exist_ok=True)
        for name, (scene, axes) in AXES.items():
            prof = cProfile.Profile()
            prof.enable()
            sweep(scene, **axes)
            prof.disable()
            path = os.path.join(a.profile, f"profile_{name}_{top}.txt")
            with open(path, "w") as f:
                st = pstats.Stats(prof, stream=f).sort_stats("tottime")
                st.print_stats(45)
                st.sort_stats("cumulative").print_stats(45)
            print(f"wrote {path}", flush=True)
    if a.bed:
        sys.path.insert(0, os.path.dirname(__file__))
        from bench_bed import WATER as BED_WATER
        from bench_bed import bed

        from agglomtool.bed import bed_sweep

        scene, comps = Scene(**BED_WATER), bed()
        grid = dict(T=np.linspace(scene.T, scene.T + 50.0, 30), U_Umf=np.linspace(1.5, 3.0, 30))
        bed_sweep(scene, comps, T=grid["T"][:2], U_Umf=grid["U_Umf"][:2])
        for n in sorted({min(2, top), top}):
            numba.set_num_threads(n)
            ts = timed(lambda: bed_sweep(scene, comps, **grid), 1 if n <= 2 else a.repeats)
            print(f"bed 30 x 30 (3 x 20 classes, water) at {n} threads: {fmt(ts)}; load "
                  f"{os.getloadavg()[0]:.1f}", flush=True)
    if a.cluster:
        from dask.distributed import Client, LocalCluster

        scene, axes = AXES["water"]
        with LocalCluster(n_workers=a.cluster, processes=True, threads_per_worker=1,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            t = time.perf_counter()
            sweep(scene, client=client, **small(axes))
            print(f"cluster of {a.cluster} workers: start and warm-up "
                  f"{time.perf_counter() - t:.1f} s", flush=True)
            ts = timed(lambda: sweep(scene, client=client, **axes), a.repeats)
            print(f"water map on the cluster: {fmt(ts)} (in-process at {top} threads: "
                  f"median {med.get(('water', top), float('nan')):.3f} s)", flush=True)


if __name__ == "__main__":
    main()
