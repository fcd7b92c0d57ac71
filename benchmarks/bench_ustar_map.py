"""A map where every point needs its own u0*, against a plain 1e6 ``collide``.

Run: ``python benchmarks/bench_ustar_map.py [--quick]``. Prints figures; asserts nothing.

Goal: 1e6 u0* solves within 3x of 1e6 plain collisions (mode "relative", details off),
both measured in this run. Three figures, each the best and the median of ``REPEATS``
(>= 5) timed runs after a warm-up, with the load average:

1. ``collide``: 1e6 mixed collisions (``bench_collision.scenes``: water and slag, solid
   sizes, densities, coatings and angles drawn per element), mode "relative", details off;
2. ``critical_impact_speed``: the same 1e6 mixed scenes, mode "relative" (every element
   its own u0*), with the near-closed form (default) and with the plain search
   (``closed_form=False``) for the record;
3. the critical group of a map: ``maps.build`` of a 100 (d_i, 0.1-1 mm) x 100 (h0,
   1-9 um) x 100 (T, 280-360 K) grid of glass beads coated with water in air, computing
   ``u_star`` (and its flag, ``Ca_star``, ``regime``) only: 1e6 points, no two alike (T
   changes the water's viscosity, surface tension and density and the air), property
   evaluation and dask blocks included.

The ratios are taken against the median ``collide`` time of the same run, interleaved so
that both see the same load.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_collision import scenes  # noqa: E402

import agglomtool as at  # noqa: E402
from agglomtool.api import _FUSED, _fused_inputs  # noqa: E402
from agglomtool.collision.critical import (  # noqa: E402
    HOW_BRACKET,
    HOW_CLOSED,
    HOW_SEARCH,
    critical_speeds,
)
from agglomtool.maps import build  # noqa: E402
from agglomtool.scene import Scene  # noqa: E402

REPEATS = 5
SCENE = Scene(solid_i="glass-beads", liquid="water", gas="air", T=300.0, h0=5e-6,
              d_i=500e-6)


def map_grid(n):
    return dict(d_i=np.geomspace(100e-6, 1e-3, n), h0=np.geomspace(1e-6, 9e-6, n),
                T=np.linspace(280.0, 360.0, n))


def interleaved(fns, repeats=REPEATS):
    """``{name: [times]}`` of the callables ``fns`` (a dict), run in turn ``repeats`` times
    after one warm-up each."""
    for fn in fns.values():
        fn()
    out = {k: [] for k in fns}
    for _ in range(repeats):
        for k, fn in fns.items():
            t0 = time.perf_counter()
            fn()
            out[k].append(time.perf_counter() - t0)
    return out


def main(n=1_000_000, n_side=100):
    rng = np.random.default_rng(1)
    print(f"agglomtool {at.__version__}; numba {numba.__version__}, "
          f"{numba.config.NUMBA_NUM_THREADS} threads; cores {os.cpu_count()}; "
          f"load average at start {os.getloadavg()}")
    kw = scenes(rng, n)
    u0 = rng.uniform(0.05, 3.0, n)
    _, ins, steps, _ = _fused_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                                     kw["beta_deg"], 0.9, None, None, speeds=False)

    def collide():
        return at.collide(**kw, u0=u0, details=False)

    def critical():
        return at.critical_impact_speed(**kw)

    def critical_search():
        return critical_speeds(ins, steps, n, _FUSED["relative"], body=True,
                               particle_slip=False, rtol=1e-6, closed_form=False)

    ds = build(SCENE, **map_grid(n_side))
    crit = ds[["u_star", "u_star_flag", "Ca_star", "regime"]]

    def map_critical():
        return crit.compute(scheduler="synchronous")

    fns = {"collide": collide, "critical": critical, "map": map_critical}
    times = interleaved(fns)
    ref = float(np.median(times["collide"]))
    labels = {
        "collide": f"collide {n:.0e} mixed, relative, details off",
        "critical": f"critical_impact_speed {n:.0e} mixed, relative",
        "map": f"map {n_side}^3 (d_i x h0 x T), critical group",
    }
    for k, ts in times.items():
        best, med = min(ts), float(np.median(ts))
        ratio = med / ref
        goal = "" if k == "collide" else "  (goal <= 3)"
        print(f"{labels[k]:48s} best {best:7.3f} s  median {med:7.3f} s  "
              f"{n / med / 1e6:6.2f} M/s  ratio to collide {ratio:5.2f}{goal}")

    # How the 1e6 mixed u0* were found, and the plain search for the record.
    u_cf, how = critical_speeds(ins, steps, n, _FUSED["relative"], body=True,
                                particle_slip=False, rtol=1e-6, return_how=True)
    counts = {name: int(np.count_nonzero(how == code)) for name, code in
              (("closed form", HOW_CLOSED), ("bracket", HOW_BRACKET), ("search", HOW_SEARCH))}
    print(f"    (mixed {n:.0e}: {counts}; finite {np.isfinite(u_cf).mean():.1%})")
    ts = interleaved({"search": critical_search}, repeats=REPEATS)["search"]
    print(f"{'critical, plain search (closed_form=False)':48s} best {min(ts):7.3f} s  median "
          f"{np.median(ts):7.3f} s  {n / np.median(ts) / 1e6:6.2f} M/s  ratio to collide "
          f"{np.median(ts) / ref:5.2f}")
    u_map = crit.compute(scheduler="synchronous").u_star.values
    distinct = np.unique(u_map[np.isfinite(u_map)]).size
    print(f"    (map: {u_map.size} points, {distinct} distinct finite u0*, "
          f"{np.isinf(u_map).sum()} above the ceiling)")
    print(f"load average at end {os.getloadavg()}")


if __name__ == "__main__":
    if "--quick" in sys.argv:
        main(n=100_000, n_side=47)
    else:
        main()
