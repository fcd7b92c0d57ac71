"""Throughput of the collision core: collisions per second and u0* solves per second.

Run: ``python benchmarks/bench_collision.py``. Prints figures; asserts nothing.
Batches: 1e6 collisions of the paper's reference cases at beta = 0 over a spread of impact
speeds, the same at mixed angles and pairs that exercise the special-case paths, and 1e4
critical-speed solves.
"""

from __future__ import annotations

import os
import time

import numpy as np

import agglomtool as at
from agglomtool.collision.outcome import Path


def best_of(fn, repeat=3):
    best = np.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(n=1_000_000, n_crit=10_000):
    rng = np.random.default_rng(1)
    water = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    air = at.Gas(mu=18.48e-6, rho=1.168)
    bed = at.Bed(eps=0.55)
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
    threads = os.environ.get("NUMBA_NUM_THREADS", "default")
    print(f"agglomtool {at.__version__}; numba threads: {threads}")

    # Warm up (compilation is cached on disk after the first run).
    at.collide(p, p, liquid=water, gas=air, bed=bed, u0=np.array([0.05, 0.1]))

    u0 = np.geomspace(0.01, 1.0, n)
    for details in (False, True):
        t, r = best_of(lambda d=details: at.collide(
            p, p, liquid=water, gas=air, bed=bed, u0=u0, beta_deg=0.0, details=d))
        print(f"beta = 0, identical pair, details={details!s:5}: {n / t / 1e6:6.2f} M collisions/s "
              f"({t * 1e3:.0f} ms for {n:.0e}; {r.agglomerated.mean():.1%} stick)")

    # Mixed angles, sizes, densities and coatings near the threshold: the special paths.
    beta = rng.uniform(0.0, 360.0, n)
    pj = at.Particle(d=rng.uniform(300e-6, 1500e-6, n), rho=rng.choice([2650.0, 4330.0], n),
                     h0=rng.uniform(1e-6, 9e-6, n), ha=0.1e-6)
    u0 = rng.uniform(0.02, 0.08, n)
    t, r = best_of(lambda: at.collide(p, pj, liquid=water, gas=air, bed=bed, u0=u0,
                                      beta_deg=beta, details=False))
    special = (r.path & (Path.APPROACH_I_STOPS | Path.APPROACH_J_STOPS
                         | Path.SEPARATION_I_STOPS | Path.SEPARATION_J_STOPS)) != 0
    print(f"mixed angles and pairs near u0*        : {n / t / 1e6:6.2f} M collisions/s "
          f"({special.mean():.1%} take a special path, {r.agglomerated.mean():.1%} stick)")

    # Kernel alone (no input preparation), to separate the two costs.
    from agglomtool.api import _lab_speeds
    from agglomtool.collision.paper import run_paper
    from agglomtool.pair import prepare_pair
    _, _, w = _lab_speeds(p, pj, u0, None)
    st = prepare_pair(p, pj, water, air, bed, beta, 0.9, True, "emulsion")
    arrays = [np.ascontiguousarray(np.broadcast_to(a, (n,))) for a in (
        st.m_i, st.m_j, st.r, st.H0, st.Ha, st.mu_l, st.gamma, st.cos_t, st.theta, w,
        st.fn_i, st.fn_j, st.e)]
    t, _ = best_of(lambda: run_paper(*arrays))
    print(f"kernel only, same mixed batch          : {n / t / 1e6:6.2f} M collisions/s")

    # Critical speeds.
    pj = at.Particle(d=rng.uniform(300e-6, 1500e-6, n_crit), rho=2650.0,
                     h0=rng.uniform(1e-6, 9e-6, n_crit), ha=0.1e-6)
    beta = rng.uniform(0.0, 360.0, n_crit)
    t, u_star = best_of(lambda: at.critical_impact_speed(p, pj, liquid=water, gas=air, bed=bed,
                                                         beta_deg=beta))
    print(f"critical_impact_speed, water, mixed    : {n_crit / t:8.0f} solves/s "
          f"({t:.3f} s for {n_crit:.0e}; median u0* {np.median(u_star):.4f} m/s)")
    slag = at.Liquid(mu=10.0, gamma=0.4, rho=2500.0, theta_deg=10.0)
    hot = at.Gas(mu=45.48e-6, rho=0.324)
    ps = at.Particle(d=1000e-6, rho=2650.0, h0=0.15e-6, ha=0.1e-6)
    pj = at.Particle(d=rng.uniform(300e-6, 1500e-6, n_crit), rho=2650.0,
                     h0=rng.uniform(0.11e-6, 0.3e-6, n_crit), ha=0.1e-6)
    t, u_star = best_of(lambda: at.critical_impact_speed(ps, pj, liquid=slag, gas=hot, bed=bed,
                                                         beta_deg=beta))
    print(f"critical_impact_speed, slag, mixed     : {n_crit / t:8.0f} solves/s "
          f"({t:.3f} s for {n_crit:.0e}; median u0* {np.median(u_star):.4f} m/s)")


if __name__ == "__main__":
    main()
