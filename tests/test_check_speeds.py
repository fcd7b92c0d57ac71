"""The speed rules of ``collide`` on large batches: the parallel scan (min-reductions over
the threads) names the same rule and the same first offending collision as a plain numpy
reference, whatever the order the threads take."""

import numpy as np
import pytest

from agglomtool.collision.fused import SERIAL_BELOW, check_speeds


def reference(d_i, d_j, u0, u0_j, n):
    """First offender of each rule, by numpy, in the rules' order."""
    d_i, d_j, u0 = (np.broadcast_to(a, n) for a in (d_i, d_j, u0))
    plate_i, plate_j = np.isinf(d_i), np.isinf(d_j)
    if u0_j.size:
        v = np.broadcast_to(u0_j, n)
        rules = [plate_j & (v != 0.0), plate_i & (u0 != 0.0)]
        w = u0 + v
    else:
        rules = [np.zeros(n, bool), np.zeros(n, bool)]
        w = np.where(plate_i, 0.0, u0) + np.where(plate_j, 0.0, u0)
    with np.errstate(invalid="ignore"):
        rules += [~(w > 0.0), np.isinf(w)]
    for code, bad in enumerate(rules, start=1):
        if bad.any():
            return code, int(np.flatnonzero(bad)[0])
    return 0, -1


@pytest.mark.parametrize("n", [SERIAL_BELOW - 1, SERIAL_BELOW, 200_003])
@pytest.mark.parametrize("given", [False, True])
@pytest.mark.parametrize("seed", range(6))
def test_parallel_and_serial_scans_name_the_first_offender(n, given, seed):
    rng = np.random.default_rng(seed)
    d_i = rng.uniform(1e-4, 1e-3, n)
    d_j = rng.uniform(1e-4, 1e-3, n)
    u0 = rng.uniform(0.01, 1.0, n)
    u0_j = rng.uniform(0.01, 1.0, n) if given else np.empty(0)
    # Scatter a few offenders of a random subset of the rules (several per rule, so that
    # the first one must be found, not any one).
    for _ in range(rng.integers(0, 4)):
        k = rng.integers(0, n, 5)
        kind = rng.integers(0, 4)
        if kind == 0:
            d_j[k] = np.inf  # with u0_j given and nonzero: rule 1
        elif kind == 1:
            d_i[k] = np.inf  # with u0_j given: rule 2
        elif kind == 2:
            u0[k] = -u0[k] * 3.0  # not approaching: rule 3
        else:
            u0[k] = np.inf  # rule 4
    got = check_speeds(d_i, d_j, u0, u0_j, n)
    assert got == reference(d_i, d_j, u0, u0_j, n)


def test_all_good_and_broadcast_inputs():
    n = 50_000
    one = np.array([5e-4])
    assert check_speeds(one, one, np.full(n, 0.1), np.empty(0), n) == (0, -1)
    u0 = np.full(n, 0.1)
    u0[[17, 40_000]] = 0.0
    assert check_speeds(one, one, u0, np.empty(0), n) == (3, 17)


@pytest.mark.parametrize("n", [SERIAL_BELOW - 1, 200_003])
@pytest.mark.parametrize("given", [False, True])
@pytest.mark.parametrize("seed", range(4))
def test_the_kernels_own_pass_names_the_same_offender(n, given, seed):
    """``fused_batch(check=True)`` (what ``collide`` uses for modes paper and relative)
    applies the rules inside the kernel's loop, and so does ``auto_fused(check=True)``
    (mode auto): the same rule and first offender as the reference, and the collisions that
    obey every rule get the same outcomes as without the check."""
    from agglomtool.api import _fused_inputs
    from agglomtool.collision.auto import auto_fused
    from agglomtool.collision.fused import INPUT_NAMES, TIER_PAPER, TIER_RELATIVE, fused_batch
    from agglomtool.inputs import Bed, Gas, Liquid, Particle

    rng = np.random.default_rng(100 + seed)
    d_i = rng.uniform(1e-4, 1e-3, n)
    d_j = rng.uniform(1e-4, 1e-3, n)
    u0 = rng.uniform(0.01, 1.0, n)
    u0_j = rng.uniform(0.01, 1.0, n) if given else None
    for _ in range(rng.integers(0, 4)):
        k = rng.integers(0, n, 5)
        kind = rng.integers(0, 4)
        if kind == 0:
            d_j[k] = np.inf
        elif kind == 1:
            d_i[k] = np.inf
        elif kind == 2:
            u0[k] = -u0[k] * 3.0
        else:
            u0[k] = np.inf
    both = np.isinf(d_i) & np.isinf(d_j)
    d_j[both] = 5e-4  # at most one plate per pair (a Particle-level rule)
    kw = dict(liquid=Liquid(mu=1e-3, gamma=0.07, rho=1000.0, theta_deg=10.0),
              gas=Gas(mu=1.8e-5, rho=1.2), bed=Bed(eps=0.55), beta_deg=30.0, e=0.9)
    p_i = Particle(d=d_i, rho=2500.0, h0=5e-6, ha=1e-7)
    p_j = Particle(d=d_j, rho=2500.0, h0=5e-6, ha=1e-7)
    # collide refuses an infinite speed before the kernel (its physical range): the
    # kernel's own rule 4 is reached here by putting the offenders into its inputs
    finite = np.where(np.isinf(u0), 1.0, u0)
    _, ins, steps, _ = _fused_inputs(p_i, p_j, kw["liquid"], kw["gas"], kw["bed"],
                                     kw["beta_deg"], kw["e"], finite, u0_j, check=False)
    k_u0 = INPUT_NAMES.index("u0")
    ins = tuple(np.ascontiguousarray(u0, dtype=np.float64) if k == k_u0 else a
                for k, a in enumerate(ins))
    expect = reference(d_i, d_j, u0, np.empty(0) if u0_j is None else u0_j, n)
    for tier in (TIER_PAPER, TIER_RELATIVE):
        *out, first = fused_batch(ins, steps, n, tier, body=True, particle_slip=False, check=True)
        assert first == expect
        plain = fused_batch(ins, steps, n, tier, body=True, particle_slip=False)
        with np.errstate(invalid="ignore"):
            w = np.where(np.isinf(d_i), 0.0, u0) + (
                np.where(np.isinf(d_j), 0.0, u0) if u0_j is None else u0_j)
            good = (w > 0.0) & np.isfinite(w)
        for a, b in zip(out[:4], plain[:4], strict=True):
            np.testing.assert_array_equal(a[good], b[good])
    *out, first = auto_fused(ins, steps, n, body=True, particle_slip=False, check=True)
    assert first == expect
    if not expect[0]:
        plain = auto_fused(ins, steps, n, body=True, particle_slip=False)
        for a, b in zip(out, plain, strict=True):
            np.testing.assert_array_equal(a, b)
