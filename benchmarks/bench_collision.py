"""Throughput of the collision core against its speed goals, each next to its floor.

Run: ``python benchmarks/bench_collision.py [--quick]``. Prints figures; asserts nothing.

Every figure is the best and the median of ``REPEATS`` (>= 5) timed runs after a warm-up,
with the load average of the machine: on a shared machine the absolute figures are noisy,
the ratios to the floor measured in the same run are the reliable part. The floor
(:mod:`floor`) is a straight-line compiled loop doing only the ordinary path's arithmetic,
preparation included, on the same input arrays.

Workload ("mixed"): 1e6 collisions of 20 000 distinct scenes (each element carries its own
arrays: solid diameters 0.3-1.5 mm, densities 2650 or 4330 kg/m3, coatings, an angle in
0-360 deg; half water in air at 25 C with coatings 1-9 um, half slag in hot gas with coatings
0.11-0.3 um), each at a speed 0.5-3 times its own u0* (mode "paper").
"""

from __future__ import annotations

import os
import sys
import time
import tracemalloc
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from floor import floor_batch  # noqa: E402

import agglomtool as at  # noqa: E402
from agglomtool.api import _FUSED, _fused_inputs  # noqa: E402
from agglomtool.collision.auto import PIECES, auto_fused  # noqa: E402
from agglomtool.collision.critical import critical_speeds  # noqa: E402

REPEATS = 7
WATER = dict(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
SLAG = dict(mu=10.0, gamma=0.4, rho=2500.0, theta_deg=10.0)
AIR = dict(mu=18.48e-6, rho=1.168)
HOT = dict(mu=45.48e-6, rho=0.324)


def timings(fn, repeats=REPEATS):
    """(best, median) wall time [s] of ``repeats`` calls after one warm-up call."""
    fn()
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), float(np.median(ts))


def paired(fn, ref_fn, repeats=REPEATS):
    """``fn`` and a reference ``ref_fn`` (the floor, say) timed in alternation, so that both
    see the same load: ``((best, median) of fn, (best, median) of ref_fn, median of the
    per-pair ratios fn / ref_fn)``."""
    fn()
    ref_fn()
    ts, rs = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        t1 = time.perf_counter()
        ref_fn()
        t2 = time.perf_counter()
        ts.append(t1 - t0)
        rs.append(t2 - t1)
    ratio = float(np.median(np.array(ts) / np.array(rs)))
    return (min(ts), float(np.median(ts))), (min(rs), float(np.median(rs))), ratio


def scenes(rng, n):
    """``n`` mixed scenes as collide() keywords (without u0)."""
    slag = rng.random(n) < 0.5

    def pick(a, b):
        return np.where(slag, b, a)

    h0_lo, h0_hi = pick(1e-6, 0.11e-6), pick(9e-6, 0.3e-6)
    p_i = at.Particle(d=rng.uniform(300e-6, 1500e-6, n), rho=rng.choice([2650.0, 4330.0], n),
                      h0=h0_lo + (h0_hi - h0_lo) * rng.random(n), ha=0.1e-6)
    p_j = at.Particle(d=rng.uniform(300e-6, 1500e-6, n), rho=rng.choice([2650.0, 4330.0], n),
                      h0=h0_lo + (h0_hi - h0_lo) * rng.random(n), ha=0.1e-6)
    liquid = at.Liquid(**{k: pick(WATER[k], SLAG[k]) for k in WATER})
    gas = at.Gas(**{k: pick(AIR[k], HOT[k]) for k in AIR})
    return dict(p_i=p_i, p_j=p_j, liquid=liquid, gas=gas, bed=at.Bed(eps=0.55),
                beta_deg=rng.uniform(0.0, 360.0, n))


def take(kw, idx):
    """The scenes ``idx`` of ``kw`` (every field gathered into its own array)."""
    out = {}
    for name, val in kw.items():
        if isinstance(val, np.ndarray):
            out[name] = val[idx]
        elif hasattr(val, "__dataclass_fields__"):
            fields = {f: (getattr(val, f)[idx] if np.ndim(getattr(val, f)) else getattr(val, f))
                      for f in val.__dataclass_fields__ if getattr(val, f) is not None
                      and f not in ("name", "source")}
            out[name] = type(val)(**fields)
        else:
            out[name] = val
    return out


def line(label, figure, unit, best, median, floor=None, goal="", ratio=None):
    if floor is not None:
        ratio = f"  floor {floor * 1e3:8.2f} ms  ratio {ratio:5.2f}"
    else:
        ratio = ""
    print(f"{label:44s} {figure:9.3g} {unit:12s} best {best * 1e3:8.2f} ms  median "
          f"{median * 1e3:8.2f} ms{ratio}  {goal}")


def main(n=1_000_000, n_pool=20_000, n_crit=10_000):
    rng = np.random.default_rng(1)
    print(f"agglomtool {at.__version__}; numba {numba.__version__}, "
          f"{numba.config.NUMBA_NUM_THREADS} threads; cores {os.cpu_count()}; "
          f"load average at start {os.getloadavg()}")
    pool = scenes(rng, n_pool)
    u_star = at.critical_impact_speed(**pool)
    idx = rng.integers(0, n_pool, n)
    kw = take(pool, idx)
    u0 = u_star[idx] * rng.uniform(0.5, 3.0, n)

    # The floor on the same inputs.
    _, ins, steps, _ = _fused_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                                     kw["beta_deg"], 0.9, u0, None)
    floor_best, floor_med = timings(lambda: floor_batch(ins, steps, n))
    line("floor (ordinary-path arithmetic), 1e6", n / floor_med / 1e6, "M coll/s",
         floor_best, floor_med, goal="(alone; each ratio below uses the floor interleaved "
         "with its own runs)")
    goals = {"paper": 1.5, "relative": 1.5, "auto": 2.0}
    def floor_fn():
        return floor_batch(ins, steps, n)

    for mode, goal in goals.items():
        (best, med), (_, f_med), ratio = paired(
            lambda m=mode: at.collide(**kw, u0=u0, mode=m, details=False), floor_fn)
        line(f"collide mode={mode}, 1e6 mixed, details off", n / med / 1e6, "M coll/s", best,
             med, f_med, f"goal >= 10 M/s idle, ratio <= {goal}", ratio)
    pieces = auto_fused(ins, steps, n, body=True, particle_slip=False, return_pieces=True)[4]
    shares = ", ".join(f"{label} {np.mean(pieces == v):.1%}" for v, label in
                       [(1, "whole-stage closed forms")]
                       + [(p, f"{p} pieces") for p in PIECES] + [(0, "ode")])
    print(f"    (auto's forms: {shares})")
    r = at.collide(**kw, u0=u0, mode="paper", details=False)
    special = (r.path & 0b1111) != 0
    print(f"    (mixed batch, mode paper: {r.agglomerated.mean():.1%} stick, "
          f"{special.mean():.1%} take a one-particle-stops path)")
    (best, med), (_, f_med), ratio = paired(
        lambda: at.collide(**kw, u0=u0, mode="paper", details=True), floor_fn, 5)
    line("collide mode=paper, 1e6 mixed, details on", n / med / 1e6, "M coll/s", best, med,
         f_med, ratio=ratio)

    # Memory: peak allocations beyond inputs and outputs, in arrays of n float64.
    tracemalloc.start()
    res = at.collide(**kw, u0=u0, details=False)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    out_bytes = res.e_w.nbytes + res.stage.nbytes + res.path.nbytes + res.w.nbytes
    out_bytes += res.agglomerated.nbytes
    print(f"{'memory, collide 1e6 details off':44s} {(peak - out_bytes) / (8 * n):9.2f} "
          f"arrays of n float64 beyond the outputs (peak {peak / 1e6:.0f} MB; goal < 10)")

    # Small batches from Python.
    for m, goal in ((1, 50e-6), (100, 100e-6)):
        sub = take(kw, np.arange(m))
        us = u0[:m]
        if m == 1:
            sub = {k: (type(v)(**{f: float(np.ravel(getattr(v, f))[0])
                                  for f in v.__dataclass_fields__
                                  if getattr(v, f) is not None and f not in ("name", "source")})
                       if hasattr(v, "__dataclass_fields__") else
                       (float(v[0]) if isinstance(v, np.ndarray) else v))
                   for k, v in sub.items()}
            us = float(us[0])
        best, med = timings(lambda s=sub, u=us: at.collide(**s, u0=u, details=False), 2001)
        line(f"collide n = {m}, details off", med * 1e6, "us/call", best, med,
             goal=f"goal median < {goal * 1e6:.0f} us")

    # Critical speeds: the default solver (relative: near-closed form checked by the kernel;
    # paper: a bracket around it) and, for the record, the plain search it replaced.
    for label, sub in (("mixed water and slag", take(pool, np.arange(n_crit))),):
        _, c_ins, c_steps, _ = _fused_inputs(sub["p_i"], sub["p_j"], sub["liquid"],
                                             sub["gas"], sub["bed"], sub["beta_deg"], 0.9,
                                             None, None, speeds=False)
        for mode in ("paper", "relative"):
            best, med = timings(lambda s=sub, m=mode: at.critical_impact_speed(**s, mode=m), 5)
            line(f"critical_impact_speed 1e4, {label}, {mode}", n_crit / med, "solves/s", best,
                 med, goal="goal < 100 ms")
            best, med = timings(lambda m=mode, a=c_ins, b=c_steps: critical_speeds(
                a, b, n_crit, _FUSED[m], body=True, particle_slip=False, rtol=1e-6,
                closed_form=False), 5)
            line(f"  the same by the plain search, {mode}", n_crit / med, "solves/s", best,
                 med)
    print(f"load average at end {os.getloadavg()}")


if __name__ == "__main__":
    main()
