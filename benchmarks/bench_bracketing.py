"""The compiled bracketing against the numpy batches of the same method, on maps.

The propensity of the tiers without a closed-form sticking set (modes "auto", "ode" and
"ode_selfconsistent", mode "paper" with gravity off the collision axis, ``drag_slip =
"particle"``) is bracketed with the tier's own kernel. It runs in one compiled pass per block
(``agglomtool.collision.sticking_bracketed``); the numpy batches of
``agglomtool.collision.sticking_numeric`` are its reference. This script maps water and
slag (T x h0 x the law's axis, ``--points`` values each) under each setting and each speed
law, once each way, and prints the largest difference of the propensity and both times
(the second of two maps each, after a warm-up; one run, not a timing benchmark:
``bench_sweep.py --tiers`` times the 1e6-point maps).

    python3 benchmarks/bench_bracketing.py [--points 20]
"""

import argparse
import os
import time
import warnings
from unittest import mock

import numpy as np
from bench_sweep import LAWS, MATERIALS, TIERS

import agglomtool.collision.sticking_bracketed as compiled
from agglomtool import Scene, sweep

#: The settings whose propensity is bracketed (``bench_sweep.TIERS``'s, and the ODE tiers).
SETTINGS = {name: TIERS[name] for name in ("auto", "paper, beta 90", "drag_slip particle")}
SETTINGS.update({"ode": {"mode": "ode"}, "ode_selfconsistent": {"mode": "ode_selfconsistent"}})


def one(scene, axes):
    sweep(scene, **axes)
    t = time.perf_counter()
    ds = sweep(scene, **axes)
    return ds.propensity.values, time.perf_counter() - t


def main(points: int, settings) -> None:
    print(f"load average {os.getloadavg()[0]:.2f} at start", flush=True)
    worst = 0.0
    for mat, (scene, base) in MATERIALS.items():
        for name in settings:
            for law, (fields, axis) in LAWS.items():
                sc = Scene(**{**scene.values(), **fields, **SETTINGS[name]})
                axes = {k: v[::max(1, 100 // points)][:points]
                        for k, v in {**base, **axis}.items()}
                p_c, t_c = one(sc, axes)
                with mock.patch.object(compiled, "kind_of", lambda tier: None):
                    p_n, t_n = one(sc, axes)
                diff = float(np.max(np.abs(p_c - p_n)))
                worst = max(worst, diff)
                print(f"{mat:5s} {name:18s} {law:10s} {p_c.size} points: max |compiled - "
                      f"numpy| {diff:.1e}; compiled {t_c:.3f} s, numpy {t_n:.3f} s; NaN "
                      f"{int(np.isnan(p_c).sum())} / {int(np.isnan(p_n).sum())}", flush=True)
    print(f"largest difference {worst:.1e}; load average {os.getloadavg()[0]:.2f} at end")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=20)
    ap.add_argument("--settings", nargs="*", choices=list(SETTINGS), default=list(SETTINGS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = ap.parse_args()
        main(a.points, a.settings)
