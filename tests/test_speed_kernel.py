"""Faster kernels, same numbers: the stopping-gap search and the serial path.

- :func:`agglomtool.collision.paper._first_zero` skips stretches of scan points that an
  energy bound proves positive; it must return bitwise what the plain scan
  (``_first_zero_scan``) returns, on stages that are monotonic and on stages where a body
  force that helps the motion makes the running energy non-monotonic (several zeros);
- the paper kernel built on it must give the published-model outcomes on the hard sets
  (covered by ``test_kernel_compiled``, ``test_stability`` and ``test_fused_equality``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from agglomtool.collision.bridge import gap_parts, ln_f_diff
from agglomtool.collision.paper import _first_zero, _first_zero_scan, _running_energy
from agglomtool.collision.records import Bridge, Gap, Mover


@njit
def _both(d_start, d_end, k, share, v, m, force, c, kcap, a2):
    s_start, kind, val = gap_parts(d_start, a2)
    start = Gap(d_start, s_start, kind, val)
    mover = Mover(k, v, share, m, force)
    bridge = Bridge(c, kcap, a2)
    if not c * abs(ln_f_diff(d_start, d_end, a2)) < m * v:
        return np.nan, np.nan, 0
    if not k > 0.0:
        return np.nan, np.nan, 0
    if _running_energy(d_end, start, mover, bridge) > 0.0:
        return np.nan, np.nan, 0
    a = _first_zero(start, d_end, mover, bridge)
    b = _first_zero_scan(start, d_end, mover, bridge)
    # Count the rises of the energy on a fine grid: a non-monotonic energy.
    changes = 0
    prev = k
    q = (d_end / d_start) ** (1.0 / 400)
    d = d_start
    for _ in range(400):
        d = d * q
        e = _running_energy(d, start, mover, bridge)
        if e > prev:
            changes += 1
        prev = e
    return a, b, changes


def _cases(rng, n):
    ha = 10.0 ** rng.uniform(-8, -6, n)
    h0 = ha * 10.0 ** rng.uniform(0.01, 2.5, n)
    a2 = (h0 - ha) * (h0 + ha)
    sep = rng.random(n) < 0.5
    h_rupt = h0 * 10.0 ** rng.uniform(-0.5, 1.0, n)
    d_start = np.where(sep, ha, h0)
    d_end = np.where(sep, np.maximum(h_rupt, 1.001 * ha), ha)
    m = 10.0 ** rng.uniform(-9, -5, n)
    m[: n // 10] = np.inf
    v = 10.0 ** rng.uniform(-3, 1, n)
    share = rng.uniform(0.0, 1.0, n)
    share[n // 10: n // 5] = 1.0
    c = 10.0 ** rng.uniform(-12, -6, n)
    kcap = 10.0 ** rng.uniform(-6, -3, n)
    # Body forces of either sign, some strong enough to make the energy rise again.
    k = 0.5 * np.where(np.isinf(m), 1e-7, m) * v * v * 10.0 ** rng.uniform(-2, 0, n)
    scale = k / np.abs(d_end - d_start)
    force = scale * rng.choice([-3.0, -0.3, 0.0, 0.3, 3.0], n)
    return d_start, d_end, k, share, v, m, force, c, kcap, a2


def test_skipping_search_equals_the_plain_scan_bitwise():
    rng = np.random.default_rng(7)
    checked = nonmono = 0
    for args in zip(*_cases(rng, 40000), strict=True):
        a, b, changes = _both(*args)
        if np.isnan(a) and np.isnan(b):
            continue
        checked += 1
        nonmono += changes > 0
        assert a == b, (args, a, b)
    assert checked > 3000
    assert nonmono > 20  # the non-monotonic stages are exercised


def test_an_underflowing_rebound_is_a_consistent_stick():
    """e ~ 1e-219 leaves an energy below the smallest double: e_w comes out 0, and the stage
    must then say so (it used to say REBOUND with e_w = 0). Found by hypothesis in
    ``test_invariants``."""
    import agglomtool as at

    plate = at.Particle.plate(h0=1e-05, ha=1e-05)
    small = at.Particle(d=1e-05, rho=500.0, h0=1e-06, ha=1e-07)
    kw = dict(liquid=at.Liquid(mu=1.0, gamma=1.0, rho=500.0, theta_deg=0.0),
              gas=at.Gas(mu=1.848e-05, rho=1.168), bed=at.Bed(eps=0.5), u0=1.0,
              e=1.248959125936988e-219)
    for mode in ("paper", "relative"):
        for p_i, p_j in ((plate, small), (small, plate)):
            r = at.collide(p_i, p_j, beta_deg=0.0, mode=mode, **kw)
            assert r.e_w == 0.0
            assert r.stage == int(at.Stage.SEPARATION_ENERGY)


def test_collide_allocates_little_beyond_its_outputs():
    """1e5 collisions without details: numpy allocates the outputs and less than one more
    array of n float64 in modes paper and relative, less than three in auto (its tier and
    bound per collision, and the prepared rows of the collisions sent to "ode"); the goal is
    under 10, the numpy preparation made about 170."""
    import tracemalloc

    import agglomtool as at

    n = 100_000
    rng = np.random.default_rng(3)
    p = at.Particle(d=1e-3, rho=2650.0, h0=5e-6, ha=0.1e-6)
    pj = at.Particle(d=rng.uniform(3e-4, 1.5e-3, n), rho=2650.0, h0=5e-6, ha=0.1e-6)
    water = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    kw = dict(liquid=water, gas=at.Gas(mu=18.48e-6, rho=1.168), u0=rng.uniform(0.02, 1.0, n),
              beta_deg=rng.uniform(0.0, 360.0, n), details=False)
    for mode, limit in (("paper", 1), ("relative", 1), ("auto", 3)):
        at.collide(p, pj, mode=mode, **kw)  # compiled kernels loaded
        tracemalloc.start()
        r = at.collide(p, pj, mode=mode, **kw)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        outputs = sum(a.nbytes for a in (r.e_w, r.agglomerated, r.stage, r.path, r.w))
        assert peak - outputs < limit * 8 * n, (mode, (peak - outputs) / (8 * n))
