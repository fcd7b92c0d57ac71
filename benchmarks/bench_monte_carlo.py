"""Speed of the Monte Carlo propagation: samples per second at 1e6 samples.

Run ``python benchmarks/bench_monte_carlo.py``. Prints, for the paper's Table 4 reference
analyses (water and slag, e_w about 0.52 at the mean inputs, nine normal inputs), the
wall time of a full :func:`agglomtool.uncertainty.monte_carlo` call (draw, evaluate,
summarise) and of its parts, best of ``REPEATS`` after one warm-up call (Numba's cache
load). Other model tiers in ``agglomtool.MODES`` are timed at 1e5 samples first and at
1e6 only if that took under a second. Figures, not assertions.
"""

from __future__ import annotations

import os
import platform
import time

import numba
import numpy as np

import agglomtool as at
from agglomtool.uncertainty import monte_carlo, table4_case
from agglomtool.uncertainty._inputs import base_inputs, evaluate_e_w
from agglomtool.uncertainty.monte_carlo import draw_inputs

N = 1_000_000
REPEATS = 3


def best_of(fn, repeats=REPEATS):
    fn()  # warm-up: loads the compiled kernel
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def report(label, n, seconds):
    print(f"  {label:38s} {seconds:7.3f} s   {n / seconds / 1e6:6.2f} M samples/s")


def main() -> None:
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
          f"numba threads {numba.get_num_threads()}, numpy {np.__version__}, "
          f"load average {os.getloadavg()[0]:.2f} (other processes slow these figures)")
    for case in ("water", "slag"):
        kw = table4_case(case, 0.52)
        print(f"\n{case}, Table 4 reference sds, n = {N:,}, mode = 'paper'")
        report("monte_carlo (draw+evaluate+summary)", N,
               best_of(lambda kw=kw: monte_carlo(**kw, n=N, seed=1)))
        report("monte_carlo, keep_samples=False", N,
               best_of(lambda kw=kw: monte_carlo(**kw, n=N, seed=1, keep_samples=False)))
        report("  draw 9 inputs (truncated normal)", N,
               best_of(lambda kw=kw: draw_inputs(kw["uncertain"], N, 1)))
        values, _, _ = draw_inputs(kw["uncertain"], N, 1)
        base = base_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                           kw["u0"], None, 0.0, kw["e"], True, "emulsion")
        report("  collide() on the draws", N,
               best_of(lambda base=base, values=values: evaluate_e_w(base, values, "paper")))
    kw = table4_case("water", 0.52)
    others = [m for m in at.MODES if m != "paper"]
    if others:
        print("\nother tiers (water):")
    for mode in others:
        kw_mode = {**kw, "mode": mode}
        t_small = best_of(lambda kw_mode=kw_mode: monte_carlo(**kw_mode, n=100_000, seed=1),
                          repeats=1)
        report(f"mode={mode!r}, n=1e5", 100_000, t_small)
        if t_small < 1.0:
            report(f"mode={mode!r}, n=1e6", N,
                   best_of(lambda kw_mode=kw_mode: monte_carlo(**kw_mode, n=N, seed=1)))


if __name__ == "__main__":
    main()
