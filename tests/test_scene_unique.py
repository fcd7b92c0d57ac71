"""Properties are evaluated once per distinct (T, P) state and broadcast back: the result is
the elementwise evaluation, whichever columns vary (one column by a plain sort, several
row-wise)."""

import numpy as np
import pytest

from agglomtool.scene import _on_unique


def f(T, P):
    return T * 2.0 + P, np.sqrt(T) - P


@pytest.mark.parametrize("T, P", [
    (np.random.default_rng(0).normal(300.0, 5.0, 1000), 101325.0),  # a Monte Carlo over T
    (300.0, np.random.default_rng(1).normal(1e5, 10.0, 50)),  # over P
    (np.random.default_rng(2).normal(300.0, 5.0, (10, 3)),
     np.random.default_rng(3).normal(1e5, 10.0, (10, 3))),  # both: row-wise
    (np.array([300.0, 300.0, 301.0]), np.array([1.0, 2.0, 2.0])),  # repeats, both vary
    (np.array([[300.0], [310.0]]), np.array([1.0, 2.0, 3.0])),  # broadcast grid
    (300.0, 101325.0),  # a scalar
    (np.empty(0), 1.0),  # nothing
])
def test_unique_evaluation_is_the_elementwise_one(T, P):
    calls = []

    def counted(t, p):
        calls.append(np.size(t))
        return f(t, p)

    got = _on_unique(counted, T, P)
    ref = f(*np.broadcast_arrays(np.asarray(T, float), np.asarray(P, float)))
    for a, b in zip(got, ref, strict=True):
        np.testing.assert_array_equal(a, b)
        assert a.shape == b.shape
    distinct = len({(float(t), float(p)) for t, p in zip(
        *[x.ravel() for x in np.broadcast_arrays(np.asarray(T, float),
                                                  np.asarray(P, float))], strict=True)})
    assert calls == [max(distinct, 1) if np.size(ref[0]) else 0]
