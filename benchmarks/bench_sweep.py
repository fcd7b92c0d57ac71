"""Sweep benchmarks: the time of a 1e6-point map and the peak memory of a 1e7-point sweep.

    python benchmarks/bench_sweep.py             # both
    python benchmarks/bench_sweep.py --map       # 1e6-point map, best and median of 5
    python benchmarks/bench_sweep.py --speeds    # 1e6-point maps of water and the slag with
                                                 # each speed law, against one plain 1e6
                                                 # collide of the same pairs
    python benchmarks/bench_sweep.py --big DIR   # 1e7 points into a store in DIR, then
                                                 # again over the finished store
    python benchmarks/bench_sweep.py --speed-models  # the 1e6-point map under each
                                                 # impact-speed model, interleaved (A/B)
    python benchmarks/bench_sweep.py --tiers     # the maps under each model tier and
                                                 # drag slip against a plain collide
    python benchmarks/bench_sweep.py --tiers --law-first  # the same with the speed law's
                                                 # axis first (U_Umf x T x h0): each
                                                 # pair's points 1e4 apart
    python benchmarks/bench_sweep.py --busy      # the water map on all threads and on
                                                 # one, with and without a core held
                                                 # by another process

The map is T (100) x h0 (100) x U_Umf (100) of silica sand with the paper's slag: gas and
liquid properties, U_mf, 1e4 u0* solves (u0* does not depend on U/U_mf), 1e6 collisions
at the typical speed and 16 quadrature nodes per point for the propensity. Peak memory is
the process's maximum resident set size (``resource.getrusage``), measured in a fresh
subprocess so that nothing else counts.

``--speeds``: 1e6-point maps (u0* at every point, propensity) of water (300 um sand, T x h0
x a speed axis) and of the slag (as above), with the default excess-gas speeds (U/U_mf
axis), and fixed, lognormal (sigma_ln 0.5) and Maxwellian speeds (an axis of u0 or of the
granular temperature); each against one plain 1e6-point ``collide`` of the same pairs at
their typical speed, timed in the same run (best and median of ``--repeats``, the load
average at the start and the end).
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

from agglomtool.maps import sweep
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)


def grid(n_t, n_h, n_u, u_hi=8.0):
    return dict(T=np.linspace(900.0, 1300.0, n_t), h0=np.geomspace(0.12e-6, 2e-6, n_h),
                U_Umf=np.linspace(1.5, u_hi, n_u))


def bench_map(repeats: int = 5) -> None:
    sweep(SCENE, **grid(4, 4, 4))  # compile and warm the property tables
    times = []
    load = os.getloadavg()
    for _ in range(repeats):
        t = time.perf_counter()
        ds = sweep(SCENE, **grid(100, 100, 100))
        times.append(time.perf_counter() - t)
    print(f"1e6-point map ({ds.propensity.size} points, {ds.u_star.size} u0* solves): "
          f"best {min(times):.2f} s, median {np.median(times):.2f} s of {repeats} (all: "
          f"{', '.join(f'{x:.2f}' for x in times)}); load average {load} at start, "
          f"{os.getloadavg()} at end")


def bench_speed_models(repeats: int = 5) -> None:
    """The 1e6-point map under each impact-speed model of the registry, the models taken in
    turn within each repeat (A/B in the same process, so that the machine's load hits all
    alike); the bed's geometry is the Scene's default (0.3 m column and bed). U/U_mf up
    to 4 (not 8): beyond, the 1 mm sand's bubbles and wakes would fill this bed (the
    bubble models' ValueError), and every model is timed on the same grid."""
    import warnings

    import numba

    import agglomtool
    from agglomtool.bed.speed_models import IMPACT_SPEED_MODELS

    # which checkout is timed, on how many threads (NUMBA_NUM_THREADS sets them)
    print(f"agglomtool from {agglomtool.__file__}, {numba.get_num_threads()} threads",
          flush=True)
    models = list(IMPACT_SPEED_MODELS)
    times = {m: [] for m in models}
    load = os.getloadavg()
    with warnings.catch_warnings():
        # 1 mm sand is Geldart D: the bubble models say so at every map
        warnings.simplefilter("ignore")
        for m in models:
            # compile, warm tables; 16**3 points: the laws' map passes (from 4096) too
            sweep(SCENE.replace(speed=m), **grid(16, 16, 16, 4.0))
        for _ in range(repeats):
            for m in models:
                t = time.perf_counter()
                sweep(SCENE.replace(speed=m), **grid(100, 100, 100, 4.0))
                times[m].append(time.perf_counter() - t)
    ref = np.median(times[models[0]])
    for m in models:
        med = np.median(times[m])
        print(f"{m:>20}: best {min(times[m]):.3f} s, median {med:.3f} s of {repeats} "
              f"({100 * (med / ref - 1):+.1f} % against {models[0]}; all: "
              f"{', '.join(f'{x:.2f}' for x in times[m])})")
    # The speed law alone on 1e6 points (what a model adds, whatever the quadrature does):
    # random points (every input of one element per point), and a map's layout (U over
    # a 100**3 grid, U_mf over its first two axes, the gas density over the first, the
    # rest one value each: the steps of 0 along axes a map's passes take); wall time and
    # the process's CPU time (all threads: what more threads divide)
    from agglomtool.bed.speed_models import speed_law

    rng = np.random.default_rng(0)
    n = 1_000_000
    Umf = rng.uniform(0.2, 0.4, n)
    random = {"U": Umf * rng.uniform(1.5, 4.0, n), "Umf": Umf, "d_p": np.full(n, 1e-3),
              "rho_p": 2650.0, "rho_g": 0.3, "eps": 0.55, "e": 0.9,
              "fluctuation_ratio": 1.0, "column_diameter": 0.3, "orifice_area": 0.0,
              "height": 0.15, "wake_fraction": 0.25}
    Umf = np.linspace(0.2, 0.4, 100)[:, None, None] * np.linspace(1.0, 1.1, 100)[:, None]
    on_map = {**random, "U": Umf * np.linspace(1.5, 4.0, 100), "Umf": Umf,
              "d_p": np.float64(1e-3), "rho_g": np.linspace(0.4, 0.25, 100)[:, None, None]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for label, inputs in (("random", random), ("map layout", on_map)):
            for m in models:
                x = {k: inputs[k] for k in IMPACT_SPEED_MODELS[m].needs}
                law_t, cpu_t = [], []
                for _ in range(repeats):
                    c, t = time.process_time(), time.perf_counter()
                    speed_law(m, x).median()
                    law_t.append(time.perf_counter() - t)
                    cpu_t.append(time.process_time() - c)
                best, med = min(law_t), np.median(law_t)
                print(f"{m:>20}: speed law and median on 1e6 points ({label}) best "
                      f"{1e3 * best:.1f} ms, median {1e3 * med:.1f} ms ({100 * med / ref:.1f} "
                      f"% of the excess-gas map's median), CPU median "
                      f"{1e3 * np.median(cpu_t):.1f} ms")
    print(f"load average {load} at start, {os.getloadavg()} at end")


WATER = Scene(liquid="water", T=298.15, d_i=300e-6)
#: name -> (scene, its T and h0 axes)
MATERIALS = {
    "water": (WATER, dict(T=np.linspace(283.15, 363.15, 100), h0=np.geomspace(1e-6, 30e-6, 100))),
    "slag": (SCENE, dict(T=np.linspace(900.0, 1300.0, 100), h0=np.geomspace(0.12e-6, 2e-6, 100))),
}
#: speed law -> (its scene fields, its swept axis)
LAWS = {
    "excess-gas": ({}, dict(U_Umf=np.linspace(1.2, 8.0, 100))),
    "fixed": ({"speed": "fixed", "u0": 0.1}, dict(u0=np.geomspace(0.01, 2.0, 100))),
    "lognormal": ({"speed": "lognormal", "u0": 0.1, "sigma_ln": 0.5},
                  dict(u0=np.geomspace(0.01, 2.0, 100))),
    "maxwellian": ({"speed": "maxwellian", "granular_temperature": 0.01},
                   dict(granular_temperature=np.geomspace(1e-4, 1.0, 100))),
}


def _plain_collide(scene, axes):
    """A function timing one plain ``collide`` of the map's 1e6 pairs at their typical
    speed (the inputs resolved beforehand, outside the timing)."""
    from agglomtool.scene import Resolved

    names = list(axes)
    # each axis along its own dimension (numpy's open mesh), as a map's block
    r = Resolved({**scene.values(), **dict(zip(names, np.ix_(*axes.values()), strict=True))})
    shape = tuple(len(axes[n]) for n in names)
    u = np.broadcast_to(r.u_typical, shape)
    r.collide(u[:1, :1, :1])
    return lambda: r.collide(u)


def _map_against_collide(sc, axes, repeats, warm_step):
    """``(last map, map times, collide times, load at the start)``: the map of ``sc`` over
    ``axes`` and one plain ``collide`` of its pairs, in turn ``repeats`` times, after a
    map over every ``warm_step``-th value of each axis (compilation, property tables)."""
    sweep(sc, **{k: v[::warm_step] for k, v in axes.items()})
    plain = _plain_collide(sc, axes)
    plain()
    load = os.getloadavg()
    t_map, t_col = [], []
    ds = None
    for _ in range(repeats):
        t = time.perf_counter()
        ds = sweep(sc, **axes)
        t_map.append(time.perf_counter() - t)
        t = time.perf_counter()
        plain()
        t_col.append(time.perf_counter() - t)
    return ds, t_map, t_col, load


def bench_speeds(repeats: int = 5, which=None) -> None:
    import agglomtool

    # which checkout is timed (the script's own directory comes first on sys.path: an A/B
    # against another checkout runs this file from elsewhere with PYTHONPATH set)
    print(f"agglomtool {agglomtool.__version__} from {agglomtool.__file__}", flush=True)
    for mat, (scene, base) in MATERIALS.items():
        for law, (fields, axis) in LAWS.items():
            if which and f"{mat}/{law}" not in which:
                continue
            sc = Scene(**{**scene.values(), **fields})
            ds, t_map, t_col, load = _map_against_collide(sc, {**base, **axis}, repeats, 33)
            ratio = np.median(t_map) / np.median(t_col)
            print(f"{mat:5s} {law:10s} map ({ds.propensity.size} points, mean propensity "
                  f"{float(ds.propensity.mean()):.4f}): best {min(t_map):.3f} s, median "
                  f"{np.median(t_map):.3f} s; plain collide best {min(t_col):.3f} s, median "
                  f"{np.median(t_col):.3f} s; map / collide (medians) {ratio:.1f}x; load "
                  f"{load[0]:.2f} -> {os.getloadavg()[0]:.2f}", flush=True)


#: The settings whose propensity is bracketed with the tier's own kernel (no closed form
#: of the sticking set), beside the default's, for ``--tiers``.
TIERS = {
    "relative": {},
    "paper": {"mode": "paper"},
    "auto": {"mode": "auto"},
    "paper, beta 90": {"mode": "paper", "beta_deg": 90.0},
    "drag_slip particle": {"drag_slip": "particle"},
}


def bench_tiers(repeats: int = 5, which=None, law_first=False) -> None:
    """The 1e6-point maps of ``--speeds`` (excess-gas speeds) under each of :data:`TIERS`,
    against one plain ``collide`` of the same pairs in the same settings, timed in the
    same run: where the propensity is bracketed with the tier's kernel instead of found
    in closed form. ``law_first``: the speed law's axis first (``U_Umf x T x h0``), so
    that the points of one pair lie far apart, as in a map whose grid lists ``U_Umf``
    before the pair's axes (the README's granulator map has it in the middle)."""
    fields, axis = LAWS["excess-gas"]
    for mat, (scene, base) in MATERIALS.items():
        for name, extra in TIERS.items():
            if which and name not in which:
                continue
            sc = Scene(**{**scene.values(), **fields, **extra})
            axes = {**axis, **base} if law_first else {**base, **axis}
            _, t_map, t_col, load = _map_against_collide(sc, axes, repeats, 10)
            label = f"{name} (law first)" if law_first else name
            print(f"{mat:5s} {label:18s}: map best {min(t_map):.3f} s, median "
                  f"{np.median(t_map):.3f} s; plain collide median {np.median(t_col):.3f} s; "
                  f"map / collide {np.median(t_map) / np.median(t_col):.1f}x; load "
                  f"{load[0]:.2f} -> {os.getloadavg()[0]:.2f}", flush=True)


def bench_big(store: str) -> None:
    t = time.perf_counter()
    ds = sweep(SCENE, store=store, progress=True, **grid(100, 1000, 100))
    mean = float(ds.propensity.mean().compute(scheduler="synchronous"))
    dt = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"1e7-point chunked sweep into {store}: {dt:.1f} s, mean propensity {mean:.4f}, "
          f"peak RSS {peak:.0f} MB (the result's data variables would take "
          f"{ds.nbytes / 1e6:.0f} MB in memory)")
    t = time.perf_counter()
    sweep(SCENE, store=store, **grid(100, 1000, 100)).close()
    print(f"  run again over the finished store (every block read back and checked): "
          f"{time.perf_counter() - t:.1f} s, peak RSS "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0:.0f} MB")


def bench_busy(repeats: int = 7) -> None:
    """The 1e6-point water map of ``--speeds`` (excess-gas speeds) on every thread and on
    one, with nothing else running, then with one core held by another process (a busy
    loop in a child process): what a map costs where other jobs hold cores."""
    import warnings

    import numba

    scene, base = MATERIALS["water"]
    fields, axis = LAWS["excess-gas"]
    grid_ = {**base, **axis}
    most = numba.get_num_threads()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sweep(scene.replace(**fields), **{k: v[::10] for k, v in grid_.items()})  # compile
        for busy in (False, True):
            child = (subprocess.Popen([sys.executable, "-c", "while True: pass"])
                     if busy else None)
            try:
                time.sleep(0.5 if busy else 0.0)
                for threads in dict.fromkeys((most, 1)):
                    numba.set_num_threads(threads)
                    times = []
                    for _ in range(repeats):
                        t = time.perf_counter()
                        sweep(scene.replace(**fields), **grid_)
                        times.append(time.perf_counter() - t)
                    print(f"{'one core held' if busy else 'nothing else'}: {threads} "
                          f"thread(s) best {min(times):.3f} s, median "
                          f"{np.median(times):.3f} s of {repeats}; load "
                          f"{os.getloadavg()[0]:.2f}", flush=True)
            finally:
                numba.set_num_threads(most)
                if child is not None:
                    child.kill()
                    child.wait()


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--map", action="store_true")
    ap.add_argument("--big", metavar="DIR")
    ap.add_argument("--speed-models", action="store_true")
    ap.add_argument("--speeds", nargs="*", metavar="MATERIAL/LAW",
                    help="the maps of each speed law (all, or those named: water/fixed ...)")
    ap.add_argument("--busy", action="store_true")
    ap.add_argument("--tiers", nargs="*", metavar="SETTING",
                    help="the water and slag maps under each model tier and drag slip "
                         "(all, or those named: auto, 'paper, beta 90', ...)")
    ap.add_argument("--law-first", action="store_true",
                    help="with --tiers: the speed law's axis first (each pair's points "
                         "far apart)")
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    if a.tiers is not None:
        bench_tiers(a.repeats, a.tiers, a.law_first)
    elif a.busy:
        bench_busy(max(a.repeats, 7))
    elif a.speeds is not None:
        bench_speeds(a.repeats, a.speeds)
    elif a.speed_models:
        bench_speed_models(a.repeats)
    elif a.map:
        bench_map(a.repeats)
    elif a.big:
        bench_big(a.big)
    else:
        subprocess.run([sys.executable, __file__, "--map"], check=True)
        with tempfile.TemporaryDirectory() as d:
            subprocess.run([sys.executable, __file__, "--big", d + "/store"], check=True)
