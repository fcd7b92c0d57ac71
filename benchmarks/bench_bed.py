"""Speed of the bed propensity against its goals.

Cases: a 3-component bed of 20 size classes each (60 classes, 8 collision directions, 16
speed nodes; water and slag) at one operating point; the same bed's distinct work done as
plain batches (one ``critical_impact_speed`` call over its 14,400 distinct collisions - the
pairs i < j in every direction, i = j in half of them - and one ``collide`` call over 16
speeds each: 230,400 collisions), the floor the one-batch bed is held against; an 11-class
point (8 + 3 classes), which is Python-bound; a g x g ``bed_sweep`` (T x U/U_mf), from
which the 30 x 30 sweep is extrapolated (``--full`` runs it).

Run: ``python3 benchmarks/bench_bed.py [--repeat 5] [--grid 4] [--full] [--against DIR]``.
Reports the best and the median of ``--repeat`` runs with the load average (timings on a
shared machine are noisy). ``--against DIR`` runs the same cases on the package in ``DIR``
(another checkout) right after, in a subprocess: an A/B in the same run.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
import warnings

import numpy as np

import agglomtool as at
from agglomtool import materials
from agglomtool.bed import Component, bed_propensity, bed_sweep
from agglomtool.scene import Resolved

WATER = dict(T=298.15, liquid="water", h0=5e-6, U_Umf=2.0)
SLAG = dict(T=1073.15, liquid="hypothetical-slag", h0=0.15e-6, U_Umf=2.0)


def bed():
    return [Component("silica-sand", 0.5, d50=800e-6, gsd=1.5, classes=20),
            Component("ilmenite", 0.3, d50=300e-6, gsd=1.3, classes=20),
            Component("olivine", 0.2, d50=400e-6, gsd=1.4, classes=20)]


def small_bed():
    return [Component("silica-sand", 0.7, d50=800e-6, gsd=1.5, classes=8),
            Component("ilmenite", 0.3, d50=300e-6, gsd=1.3, classes=3)]


def timed(func, repeat):
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        func()
        out.append(time.perf_counter() - t)
    return min(out), statistics.median(out)


def load() -> str:
    return f"load {os.getloadavg()[0]:.2f}"


def plain_batches(scene, comps, directions=8, nodes=16):
    """The bed point's distinct collisions as two plain batches: ``u0*`` of each (one call)
    and a collision at each of ``nodes`` speeds (one call); returns a function to time."""
    rows = [c.size_classes() for c in comps]
    cidx = np.concatenate([np.full(len(r[0]), k) for k, r in enumerate(rows)])
    d = np.concatenate([r[0] for r in rows])
    K = d.size
    s = np.polynomial.legendre.leggauss(directions)[0]
    beta = np.degrees(np.arcsin(s))
    i, j, k = (x.reshape(-1) for x in np.meshgrid(np.arange(K), np.arange(K),
                                                   np.arange(directions), indexing="ij"))
    keep = (i < j) | ((i == j) & (k <= directions - 1 - k))
    i, j, k = i[keep], j[keep], k[keep]
    sol = [materials.solid(c.solid) for c in comps]
    rho = np.array([m.density for m in sol])[cidx]
    ha = np.array([m.asperity_height for m in sol])[cidx]
    e = np.array([m.restitution_dry for m in sol])[cidx]
    r = Resolved(scene.values())
    one = bed_propensity(scene, comps, directions=directions, nodes=nodes)
    Umf = float(one.Umf)
    p_i = at.Particle(d=d[i], rho=rho[i], h0=scene.h0, ha=ha[i])
    p_j = at.Particle(d=d[j], rho=rho[j], h0=scene.h0, ha=ha[j])
    kw = dict(liquid=r.liquid, gas=r.gas, bed=at.Bed(eps=scene.eps, U=scene.U_e_Umf * Umf),
              beta_deg=beta[k], e=0.5 * (e[i] + e[j]), mode=scene.mode)
    theta = (scene.fluctuation_ratio * (scene.U_Umf - 1.0) * Umf) ** 2
    q = (np.arange(nodes) + 0.5) / nodes
    u = np.sqrt(-theta * np.log1p(-q))[:, None] * np.ones(i.size)  # Maxwellian quantiles

    def run():
        at.critical_impact_speed(p_i, p_j, u_max=scene.u_ceiling, **kw)
        at.collide(p_i, p_j, u0=u, details=False, **kw)

    return run, i.size, u.size


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--grid", type=int, default=4, help="points per axis of the measured grid")
    ap.add_argument("--full", action="store_true", help="also run the 30 x 30 grid")
    ap.add_argument("--against", help="a checkout whose package to time the same way after")
    args = ap.parse_args()
    warnings.simplefilter("ignore", at.PlausibilityWarning)
    comps = bed()
    n = sum(c.classes for c in comps)
    print(f"package: {os.path.dirname(os.path.dirname(at.__file__))}; "
          f"bed: {len(comps)} components, {n} classes, {n * (n + 1) // 2} unique pairs; "
          f"{os.cpu_count()} cores; {load()}")
    for cond in (WATER, SLAG):
        scene = at.Scene(**cond)
        name = cond["liquid"]
        bed_propensity(scene, comps)  # compile and warm the caches
        best, med = timed(lambda s=scene: bed_propensity(s, comps), args.repeat)
        print(f"{name:18s} one point, 3 x 20 classes: best {best * 1e3:.0f} ms, median "
              f"{med * 1e3:.0f} ms ({load()})")
        if cond is WATER:
            run, n_u, n_c = plain_batches(scene, comps)
            run()
            best, med = timed(run, args.repeat)
            print(f"{name:18s} its distinct work as plain batches ({n_u} u0*, {n_c} "
                  f"collisions): best {best * 1e3:.0f} ms, median {med * 1e3:.0f} ms "
                  f"({load()})")
            small = small_bed()
            bed_propensity(scene, small)
            best, med = timed(lambda s=scene, b=small: bed_propensity(s, b), 4 * args.repeat)
            print(f"{name:18s} one point, 11 classes: best {best * 1e3:.1f} ms, median "
                  f"{med * 1e3:.1f} ms ({load()})")
        g = args.grid
        grid = dict(T=np.linspace(cond["T"], cond["T"] + 50.0, g),
                    U_Umf=np.linspace(1.5, 3.0, g))
        best, med = timed(lambda s=scene, gr=grid: bed_sweep(s, comps, **gr), 1)
        per = best / (g * g)
        print(f"{name:18s} {g} x {g} grid: {best:.1f} s = {per * 1e3:.0f} ms/point -> "
              f"30 x 30 about {per * 900:.0f} s ({load()})")
        if args.full:
            grid = dict(T=np.linspace(cond["T"], cond["T"] + 50.0, 30),
                        U_Umf=np.linspace(1.5, 3.0, 30))
            t = time.perf_counter()
            bed_sweep(scene, comps, **grid)
            print(f"{name:18s} 30 x 30 grid: {time.perf_counter() - t:.1f} s ({load()})")
    if args.against:
        cmd = [sys.executable, __file__, "--repeat", str(args.repeat), "--grid",
               str(args.grid)] + (["--full"] if args.full else [])
        env = {**os.environ, "PYTHONPATH": os.path.abspath(args.against)}
        sys.stdout.flush()
        subprocess.run(cmd, env=env, check=True)


if __name__ == "__main__":
    main()
