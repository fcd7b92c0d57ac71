"""Command-line start-up and map file size (the figures quoted in the README).

Prints, best and median of 5 fresh processes each:
- ``agglomtool --version``, ``--help`` and ``collide --help``;
- one ``collide`` with warm caches (Numba's compiled kernels and the gas tables on disk);
- one ``collide`` with both caches empty (the first call after an install);
and the size of a 1e6-point map written uncompressed and compressed (``write_map``).

    python benchmarks/bench_cli.py
"""

import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def timed(args, env=None, n=5):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "agglomtool", *args], check=True,
                       capture_output=True, env=env)
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times)


def main():
    print(f"load average {os.getloadavg()[0]:.2f} (2 cores)")
    for args in (["--version"], ["--help"], ["collide", "--help"], ["collide"]):
        best, med = timed(args)
        print(f"{' '.join(args):16s} best {best:.2f} s, median {med:.2f} s (warm caches)")
    cold = []
    for _ in range(3):
        with tempfile.TemporaryDirectory() as nb, tempfile.TemporaryDirectory() as gas:
            env = {**os.environ, "NUMBA_CACHE_DIR": nb, "AGGLOMTOOL_CACHE_DIR": gas}
            cold.append(timed(["collide"], env=env, n=1)[0])
    print(f"collide          best {min(cold):.2f} s, median {statistics.median(cold):.2f} s "
          "(empty Numba and gas-table caches: the first call after an install)")

    import agglomtool as at

    scene = at.Scene(liquid="water", T=298.15, h0=5e-6)
    ds = at.sweep(scene, solid_j=["silica-sand", "ilmenite"],
                  U_Umf=np.linspace(1.5, 8.0, 100), h0=np.geomspace(1e-6, 100e-6, 100),
                  d_i=np.linspace(200e-6, 900e-6, 50))
    with tempfile.TemporaryDirectory() as tmp:
        raw = at.write_map(ds, os.path.join(tmp, "raw.nc"), complevel=0).stat().st_size
        t0 = time.perf_counter()
        z = at.write_map(ds, os.path.join(tmp, "z.nc")).stat().st_size
        dt = time.perf_counter() - t0
    n = int(np.prod(list(ds.propensity.shape)))
    print(f"map of {n:.1e} points: {raw / 1e6:.1f} MB uncompressed, {z / 1e6:.1f} MB "
          f"compressed (ratio {z / raw:.2f}, zlib level 4, {dt:.1f} s to write)")


if __name__ == "__main__":
    main()
