"""The core's named records (:mod:`agglomtool.collision.records`): a tier call's arrays are
taken by name, a collision's pair state is read from them field by field, compiled and
interpreted alike, and a call with the wrong number of arrays is refused by name."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from agglomtool.collision.records import (
    INPUT_FIELDS,
    Pair,
    StageResult,
    TierInputs,
    pair_at,
    tier_inputs,
)
from agglomtool.collision.tiers import evaluate


def _arrays(n=5):
    # each field its own values, so that a field read from the wrong array shows
    return [np.arange(n, dtype=float) + 100.0 * k for k in range(len(INPUT_FIELDS))]


@njit
def _pairs(ins):
    out = np.empty((ins.w.shape[0], 12))
    for q in range(ins.w.shape[0]):
        p = pair_at(ins, q)
        out[q] = (p.m_i, p.m_j, p.r, p.H0, p.Ha, p.mu_l, p.gamma, p.cos_t, p.theta, p.fn_i,
                  p.fn_j, p.e)
    return out


def test_a_pair_is_read_field_by_field():
    ins = TierInputs(*_arrays())
    want = np.array([getattr(ins, name) for name in Pair._fields]).T
    np.testing.assert_array_equal(_pairs(ins), want)  # compiled
    for q in range(ins.w.shape[0]):  # interpreted
        assert pair_at.py_func(ins, q) == tuple(want[q])
    assert "w" not in Pair._fields and set(Pair._fields) | {"w"} == set(INPUT_FIELDS)


@njit
def _round_trip(pair, code):
    # built, passed out and read by name inside compiled code
    return StageResult(code, pair.m_i, pair.m_j, pair.r, 0, 0.0, 0.0, 0.0, 0.0)


def test_records_pass_in_and_out_of_compiled_code():
    pair = Pair(*(float(k) for k in range(12)))
    res = _round_trip(pair, 3)
    assert isinstance(res, StageResult)
    assert (res.code, res.k_end_i, res.k_end_j, res.d_stop) == (3, 0.0, 1.0, 2.0)


def test_tier_inputs_takes_a_record_or_the_arrays_in_order():
    arrays = _arrays()
    ins = TierInputs(*arrays)
    assert tier_inputs(ins) is ins
    assert tier_inputs(arrays) == ins
    with pytest.raises(ValueError, match=r"13 input arrays .*got 12"):
        tier_inputs(arrays[:12])
    with pytest.raises(ValueError, match=r"13 input arrays .*got 12"):
        evaluate("paper", *arrays[:12])
