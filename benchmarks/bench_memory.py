"""Peak memory of large runs, each in a fresh process (``resource.getrusage`` max RSS).

    python benchmarks/bench_memory.py                 # Monte Carlo, 1e7 samples
    python benchmarks/bench_memory.py --n 2e7

For :func:`agglomtool.uncertainty.monte_carlo` on the paper's Table 4 water case (nine
uncertain inputs) at two chunk sizes, with and without the per-sample output
(``keep_samples``), and a process that only imports and warms up (the baseline: Python,
numpy, Numba and the compiled kernels). Figures, not assertions; the 1e7-point
store-backed sweep is ``benchmarks/bench_sweep.py --big DIR``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys

CHILD = """
import resource, sys, time
from agglomtool.uncertainty import monte_carlo, table4_case
n, chunk, keep = int(float(sys.argv[1])), int(float(sys.argv[2])), sys.argv[3] == "1"
kw = table4_case("water", 0.52)
monte_carlo(**kw, n=1000, seed=1)
t = time.perf_counter()
if n:
    ds = monte_carlo(**kw, n=n, seed=1, chunk_size=chunk, keep_samples=keep)
print(f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} "
      f"{time.perf_counter() - t:.1f}")
"""


def run(n: float, chunk: float, keep: bool) -> tuple[str, str]:
    out = subprocess.run([sys.executable, "-c", CHILD, str(n), str(chunk), str(int(keep))],
                         check=True, capture_output=True, text=True).stdout.split()
    return out[0], out[1]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=float, default=1e7)
    a = ap.parse_args()
    print(f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    peak, _ = run(0, 1, False)
    print(f"baseline (import + warm-up): peak RSS {peak} MB")
    for keep in (False, True):
        for chunk in (1e5, 1e6):
            peak, dt = run(a.n, chunk, keep)
            print(f"monte_carlo n = {a.n:.0e}, chunk_size = {chunk:.0e}, keep_samples = "
                  f"{keep}: peak RSS {peak} MB ({dt} s)")


if __name__ == "__main__":
    main()
