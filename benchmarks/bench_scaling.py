"""Strong scaling of 4e6-point operating maps and of a 30 x 30 bed sweep over Numba threads.

    python benchmarks/bench_scaling.py [--threads 1 2 4 8 16] [--repeats 3] [--bed]
                                       [--profile DIR] [--cluster N] [--chunks N]
                                       [--per-kernel] [--ceiling]

For each thread count (``numba.set_num_threads``; the process must start with at least as
many, ``NUMBA_NUM_THREADS``), best and median of ``--repeats`` of:

- a 4e6-point water map (300 um sand, T 100 x h0 200 x U/U_mf 200, the default excess-gas
  speeds, u0* at every point, propensity), the README's kind of map;
- the same for the paper's slag against 1 mm sand;
- one plain 4e6-point ``collide`` of the water map's pairs at their typical speed (the
  kernel alone, what the map is held against).

Each time is followed by the median seconds spent inside the package's parallel kernels
(every ``parallel_launch`` timed) and by the rest, the serial remainder (each run's time
less its time in the kernels, best and median). The efficiency from 2
to n threads is ``t(2) / (t(n) n / 2)`` on the medians. ``--bed``
adds the 30 x 30 ``bed_sweep`` of the 3-component x 20-class water bed of
``bench_bed.py`` at 2 threads and at the most; ``--profile DIR`` writes a cProfile of one
water map at the most threads (the serial remainder: time spent outside the compiled
kernels); ``--per-kernel`` times the water map
by kernel at each thread count (and the rest, outside the kernels); ``--ceiling`` first
times a synthetic compute-bound kernel over the same thread
counts (what the machine gives a perfectly parallel loop); ``--chunks N`` gives the in-process maps
blocks of N points instead of the sweep's ``"auto"`` (which grows with the threads: the
earlier fixed 262144 points is ``--chunks 262144``); ``--cluster N`` times the water
map on a LocalCluster of N one-thread workers, in memory and into a store, with the client
process's CPU time. The figures depend on the machine: the script prints its core count
and load average.
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
from agglomtool.scene import Scene

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_sweep import _plain_collide as plain_collide  # noqa: E402

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


#: Seconds spent inside the parallel kernels since the last reset (``_instrument``), in
#: all and by kernel (``--per-kernel``).
IN_KERNELS = [0.0]
PER_KERNEL: dict[str, float] = {}


def _instrument() -> None:
    """Time every parallel launch of the package: each module's ``parallel_launch`` wrapped
    (what is left of a map's time is its serial remainder: Python, numpy, small kernels)."""
    import importlib
    import pkgutil

    import agglomtool
    from agglomtool import _jit

    real = _jit.parallel_launch

    def launch(kernel, *args):
        t = time.perf_counter()
        try:
            return real(kernel, *args)
        finally:
            dt = time.perf_counter() - t
            IN_KERNELS[0] += dt
            name = getattr(kernel, "__name__", str(kernel))
            PER_KERNEL[name] = PER_KERNEL.get(name, 0.0) + dt

    for info in pkgutil.walk_packages(agglomtool.__path__, "agglomtool."):
        if info.name.endswith("__main__"):
            continue
        mod = importlib.import_module(info.name)
        if getattr(mod, "parallel_launch", None) is real:
            mod.parallel_launch = launch


def timed(fn, repeats, kernels=None):
    """Wall times of ``repeats`` calls; ``kernels`` (a list) gets each call's seconds inside
    the parallel kernels."""
    out = []
    for _ in range(repeats):
        IN_KERNELS[0] = 0.0
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
        if kernels is not None:
            kernels.append(IN_KERNELS[0])
    return out


def fmt(ts):
    return f"best {min(ts):.3f} s, median {statistics.median(ts):.3f} s"


@numba.njit(parallel=True, cache=True)
def _synthetic(x, out):
    """A compute-bound loop with no memory traffic to speak of (5 exp/log1p/sqrt per
    element), in equal 4096-element blocks like the kernels': what the machine's cores
    give a perfectly parallel kernel."""
    n = x.shape[0]
    for b in numba.prange((n + 4095) // 4096):
        for i in range(b * 4096, min(n, (b + 1) * 4096)):
            v = x[i]
            for _ in range(5):
                v = np.sqrt(np.log1p(np.exp(-v) + v))
            out[i] = v


def ceiling(threads, repeats) -> None:
    x = np.random.default_rng(0).uniform(0.1, 2.0, 4_000_000)
    out = np.empty_like(x)
    _synthetic(x[:10], out[:10])
    med = {}
    for n in threads:
        numba.set_num_threads(n)
        ts = timed(lambda: _synthetic(x, out), repeats)
        med[n] = statistics.median(ts)
        print(f"synthetic compute-bound kernel, 4e6 elements, {n:2d} threads: {fmt(ts)}",
              flush=True)
    if 2 in med:
        print("synthetic: efficiency from 2 threads " + ", ".join(
            f"{n}: {med[2] / (med[n] * n / 2):.0%}" for n in threads if n > 2), flush=True)


def per_kernel(threads, repeats, chunks) -> None:
    """The water map's time by kernel at each thread count (medians over ``repeats``
    maps), the rest outside the kernels, and each part's efficiency from 2 threads."""
    scene, axes = AXES["water"]
    med = {}
    for n in threads:
        numba.set_num_threads(n)
        runs, walls = [], []
        for _ in range(repeats):
            PER_KERNEL.clear()
            IN_KERNELS[0] = 0.0
            t = time.perf_counter()
            sweep(scene, chunks=chunks, **axes)
            walls.append(time.perf_counter() - t)
            runs.append({**PER_KERNEL, "(outside the kernels)": walls[-1] - IN_KERNELS[0]})
        names = sorted({k for r in runs for k in r}, key=lambda k: -runs[0].get(k, 0.0))
        med[n] = {k: statistics.median(r.get(k, 0.0) for r in runs) for k in names}
        print(f"water map by kernel, {n:2d} threads (median of {repeats}, whole map "
              f"{statistics.median(walls):.3f} s): "
              + ", ".join(f"{k} {1e3 * v:.1f} ms" for k, v in med[n].items() if v >= 5e-4),
              flush=True)
    if 2 in med:
        for n in (n for n in threads if n > 2):
            eff = {k: med[2][k] / (v * n / 2) for k, v in med[n].items()
                   if v > 0 and med[2].get(k, 0.0) >= 5e-3}
            print(f"by kernel, efficiency from 2 to {n} threads: "
                  + ", ".join(f"{k} {e:.0%}" for k, e in eff.items()), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--threads", type=int, nargs="*", default=[1, 2, 4, 8, 16])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--bed", action="store_true")
    ap.add_argument("--profile", metavar="DIR")
    ap.add_argument("--cluster", type=int, default=0)
    ap.add_argument("--chunks", type=int, default=None,
                    help="the in-process maps' block size in points (default: the sweep's "
                         "'auto', which grows with the threads)")
    ap.add_argument("--per-kernel", action="store_true",
                    help="the water map's time by kernel at each thread count")
    ap.add_argument("--ceiling", action="store_true",
                    help="first, a synthetic compute-bound kernel: the machine's own scaling")
    a = ap.parse_args()
    threads = [n for n in a.threads if n <= numba.config.NUMBA_NUM_THREADS]
    chunks = "auto" if a.chunks is None else a.chunks
    import agglomtool

    print(f"agglomtool from {os.path.dirname(agglomtool.__file__)}", flush=True)
    print(f"{os.cpu_count()} cores, Numba {numba.__version__} threading layer "
          f"{numba.config.THREADING_LAYER}, NUMBA_NUM_THREADS {numba.config.NUMBA_NUM_THREADS}, "
          f"numpy {np.__version__}, load {os.getloadavg()}", flush=True)
    warnings.simplefilter("ignore")
    if a.ceiling:
        ceiling(threads, a.repeats)
    _instrument()
    t0 = time.perf_counter()
    for scene, axes in AXES.values():
        sweep(scene, **small(axes))
        sweep(scene, **axes)  # the parallel paths of a map as large as the timed ones
    col = plain_collide(*AXES["water"])  # bench_sweep's: one collide at the typical speed
    col()
    print(f"compile and warm-up {time.perf_counter() - t0:.1f} s; threading layer "
          f"{numba.threading_layer()}", flush=True)
    med = {}
    for n in threads:
        numba.set_num_threads(n)
        line = [f"{n:2d} threads"]
        for name, (scene, axes) in AXES.items():
            kt: list[float] = []
            ts = timed(lambda s=scene, x=axes: sweep(s, chunks=chunks, **x), a.repeats, kt)
            med[name, n] = statistics.median(ts)
            rest = [t - k for t, k in zip(ts, kt, strict=True)]
            line.append(f"{name} map {fmt(ts)} (in kernels {statistics.median(kt):.3f} s; "
                        f"serial remainder best {min(rest):.3f} s, median "
                        f"{statistics.median(rest):.3f} s)")
        kt = []
        ts = timed(col, a.repeats, kt)
        med["collide", n] = statistics.median(ts)
        line.append(f"plain collide {fmt(ts)} (in kernels {statistics.median(kt):.3f} s)")
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
    if a.per_kernel:
        per_kernel(threads, a.repeats, chunks)
    numba.set_num_threads(top)
    if a.profile:
        os.makedirs(a.profile, exist_ok=True)
        for name, (scene, axes) in AXES.items():
            prof = cProfile.Profile()
            prof.enable()
            sweep(scene, chunks=chunks, **axes)
            prof.disable()
            path = os.path.join(a.profile, f"profile_{name}_{top}.txt")
            with open(path, "w") as f:
                st = pstats.Stats(prof, stream=f).sort_stats("tottime")
                st.print_stats(45)
                st.sort_stats("cumulative").print_stats(45)
            print(f"wrote {path}", flush=True)
    if a.bed:
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
        import shutil
        import tempfile

        from dask.distributed import Client, LocalCluster

        from agglomtool.maps.plan import SweepPlan

        scene, axes = AXES["water"]
        with LocalCluster(n_workers=a.cluster, processes=True, threads_per_worker=1,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            t = time.perf_counter()
            sweep(scene, client=client, **small(axes))
            print(f"cluster of {a.cluster} one-thread workers: warm-up "
                  f"{time.perf_counter() - t:.1f} s", flush=True)
            for how in ("in memory", "into a store"):
                walls, cpus = [], []
                for _ in range(a.repeats):
                    tmp = tempfile.mkdtemp()
                    store = {"store": os.path.join(tmp, "s.zarr")} if how != "in memory" else {}
                    c, t = time.process_time(), time.perf_counter()
                    ds = sweep(scene, client=client, progress=False, **store, **axes)
                    walls.append(time.perf_counter() - t)
                    cpus.append(time.process_time() - c)
                    ds.close()
                    shutil.rmtree(tmp)
                n_blocks = SweepPlan.from_dataset(sweep(scene, compute=False, **axes)).n_blocks
                print(f"water map on the cluster, {how}: {fmt(walls)}; the client's CPU "
                      f"median {statistics.median(cpus):.3f} s for {n_blocks} blocks "
                      f"(in-process at {top} threads: median "
                      f"{med.get(('water', top), float('nan')):.3f} s)", flush=True)

if __name__ == "__main__":
    main()
