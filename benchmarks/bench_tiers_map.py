"""What the default tier costs on operating maps: one map per tier, best and median of 5.

The tool's default tier is "auto" unless it is more than 3x slower than "relative" on maps,
in which case "relative" (``agglomtool._fields.DEFAULT_MODE`` says which, and why). Two
maps: water on 300 um sand (U/Umf x h0 x beta, 1e5 points) and the viscous K-silicate melt
(T x h0 x U/Umf, 3e4 points).

    python3 benchmarks/bench_tiers_map.py
"""

import os
import statistics
import time

import numpy as np

import agglomtool as at

MODES = ("relative", "auto", "paper")


def timed_maps(scene, grid, repeats):
    for mode in MODES:  # compile outside the timing
        at.sweep(scene.replace(mode=mode), **{k: v[:2] for k, v in grid.items()})
    times = {m: [] for m in MODES}
    for _ in range(repeats):
        for mode in MODES:  # interleaved: the load hits every tier alike
            t0 = time.perf_counter()
            at.sweep(scene.replace(mode=mode), **grid)
            times[mode].append(time.perf_counter() - t0)
    return times


def main():
    water = at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
    melt = at.Scene(liquid="k-silicate-ash-melt", gas="biomass-flue-gas", h0=0.2e-6)
    cases = {
        "water, 1e5 points": (water, dict(U_Umf=np.linspace(1.2, 8, 100),
                                          h0=np.geomspace(1e-6, 30e-6, 100),
                                          beta_deg=np.linspace(-90, 90, 10))),
        "K-silicate melt, 3e4 points": (melt, dict(T=np.linspace(1073.15, 1673.15, 100),
                                                   h0=np.geomspace(0.05e-6, 2e-6, 100),
                                                   U_Umf=np.array([2.0, 4.0, 8.0]))),
    }
    print(f"load average {os.getloadavg()[0]:.2f} (2 cores)")
    for name, (scene, grid) in cases.items():
        t = timed_maps(scene, grid, 5)
        rel = statistics.median(t["relative"])
        parts = [f"{m} {min(v):.3f}/{statistics.median(v):.3f} s "
                 f"({statistics.median(v) / rel:.2f}x relative)" for m, v in t.items()]
        print(f"{name}: " + ", ".join(parts))


if __name__ == "__main__":
    main()
