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
