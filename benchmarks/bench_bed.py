"""Speed of the bed propensity: a 3-component bed, 20 size classes each (60 classes, 1830
unique pairs of classes, 8 collision directions, 16 speed nodes), at one operating point and
over a small operating grid; the 30 x 30 grid is extrapolated from it (``--full`` runs it).

Run: ``python3 benchmarks/bench_bed.py [--repeat 5] [--grid 4] [--full]``. Reports the best
and the median time with the load average (timings on a shared machine are noisy).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

import agglomtool as at
from agglomtool.bed import Component, bed_propensity, bed_sweep


def bed():
    return [Component("silica-sand", 0.5, d50=800e-6, gsd=1.5, classes=20),
            Component("ilmenite", 0.3, d50=300e-6, gsd=1.3, classes=20),
            Component("olivine", 0.2, d50=400e-6, gsd=1.4, classes=20)]


def timed(func, repeat):
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        func()
        out.append(time.perf_counter() - t)
    return min(out), statistics.median(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--grid", type=int, default=4, help="points per axis of the measured grid")
    ap.add_argument("--full", action="store_true", help="also run the 30 x 30 grid")
    args = ap.parse_args()
    comps = bed()
    n = sum(c.classes for c in comps)
    print(f"bed: {len(comps)} components, {n} classes, {n * (n + 1) // 2} unique pairs")
    for cond in (dict(T=298.15, liquid="water", h0=5e-6, U_Umf=2.0),
                 dict(T=1073.15, liquid="hypothetical-slag", h0=0.15e-6, U_Umf=2.0)):
        scene = at.Scene(**cond)
        bed_propensity(scene, comps)  # compile and warm the caches
        best, med = timed(lambda s=scene: bed_propensity(s, comps), args.repeat)
        print(f"{cond['liquid']:18s} one point: best {best:.2f} s, median {med:.2f} s "
              f"(load {os.getloadavg()[0]:.2f})")
        g = args.grid
        grid = dict(T=np.linspace(cond["T"], cond["T"] + 50.0, g),
                    U_Umf=np.linspace(1.5, 3.0, g))
        best, med = timed(lambda s=scene, gr=grid: bed_sweep(s, comps, **gr), 1)
        per = best / (g * g)
        print(f"{cond['liquid']:18s} {g} x {g} grid: {best:.1f} s = {per:.2f} s/point -> "
              f"30 x 30 about {per * 900 / 60:.0f} min (load {os.getloadavg()[0]:.2f})")
        if args.full:
            grid = dict(T=np.linspace(cond["T"], cond["T"] + 50.0, 30),
                        U_Umf=np.linspace(1.5, 3.0, 30))
            t = time.perf_counter()
            bed_sweep(scene, comps, **grid)
            print(f"{cond['liquid']:18s} 30 x 30 grid: {time.perf_counter() - t:.0f} s")


if __name__ == "__main__":
    main()
