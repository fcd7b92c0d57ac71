"""What a map's block pays per call, cut without changing an answer: ``check_range`` of one
element reads it as a Python float (no numpy reduction), and the fused inputs' broadcast
copies and strides are made without ``np.broadcast_to`` / ``np.require``: each checked here
against the general path it shortens (the same verdicts, messages, values and strides)."""

import itertools
import math
import re

import numpy as np
import pytest

from agglomtool._validate import as_float_array, check_range
from agglomtool.collision import fused

VALUES = [0.0, 1.0, 0.5, 2.0, -1.0, 1e-300, math.nan, math.inf, -math.inf, -0.0]
BOUNDS = [dict(lo=0.0, hi=1.0), dict(lo=0.0, hi=1.0, lo_open=True, hi_open=True),
          dict(lo=0.0, hi=None), dict(lo=None, hi=1.0, allow_inf=True),
          dict(lo=0.0, hi=1.0, allow_inf=True), dict(lo=None, hi=None)]


def _verdict(fn):
    """``("ok", value bytes)`` or ``("error", message)`` of ``fn()``."""
    try:
        out = fn()
    except ValueError as exc:
        return "error", str(exc)
    return "ok", np.asarray(out, dtype=float).tobytes()


@pytest.mark.parametrize("kw", BOUNDS)
@pytest.mark.parametrize("v", VALUES)
def test_one_element_arrays_as_the_general_path(v, kw):
    """A 0-d, a (1,) and a (1, 1) array: the verdict of the Python float (the scalar
    path's), and the message of two equal elements (the reductions' path) but for the
    index, which one element names for a NaN only (as before: a NaN's index wherever the
    array has an axis, a bad value's where it has more than one element)."""
    ref = _verdict(lambda: check_range("x", float(v), **kw))
    pair = _verdict(lambda: check_range("x", np.array([v, v]), **kw))
    assert ref[0] == pair[0]
    for shape in ((), (1,), (1, 1)):
        arr = np.full(shape, v)
        got = _verdict(lambda a=arr: check_range("x", a, **kw))
        assert got[0] == ref[0], (shape, got, ref)
        if got[0] == "error":
            index = f" at index {(0,) * len(shape)}" if shape and math.isnan(v) else ""
            assert got[1] == re.sub(r" at index \(\d+,\)", index, pair[1])
            assert got[1] == ref[1].replace("x = nan", f"x = nan{index}")
        else:
            assert check_range("x", arr, **kw) is arr  # the float64 array itself
            assert got[1] == np.asarray(v, dtype=float).tobytes()
        nan = _verdict(lambda a=arr: as_float_array("x", a))
        assert nan[0] == ("error" if math.isnan(v) else "ok")


def test_nan_named_before_other_bad_values():
    with pytest.raises(ValueError, match=r"x = nan at index \(2,\) is not a number"):
        check_range("x", np.array([-5.0, 3.0, np.nan]), 0.0, 1.0)
    with pytest.raises(ValueError, match=r"x = -5.0 at index \(0,\) is outside"):
        check_range("x", np.array([-5.0, 3.0, 0.5]), 0.0, 1.0)


def _shapes():
    for shape in [(3, 4, 5), (1, 4, 1), (2, 1, 3, 1), (5,), (1, 1), (2, 2, 1, 3)]:
        for own in itertools.product(*[(1, m) for m in shape]):
            for lead in range(len(shape) + 1):
                yield shape, own[lead:]


def test_fused_inputs_copies_and_strides_as_numpy_broadcasts():
    rng = np.random.default_rng(0)
    checked = 0
    for shape, own_shape in _shapes():
        a = rng.random(own_shape)
        n = math.prod(shape)
        flipped = a[::-1] if a.ndim else a  # (negative strides)
        for view in (a, np.asfortranarray(a), np.broadcast_to(a, own_shape), flipped):
            if view.size == 1 or (view.size == n and view.flags.c_contiguous
                                  and view.flags.writeable):
                continue  # taken as it is (no copy, no strides)
            own, strides = fused._own_values(view, shape, n)
            mine = np.ascontiguousarray(view)
            assert strides == [s // 8 for s in np.broadcast_to(mine, shape).strides]
            assert own.tobytes() == mine.tobytes()
            flat, step = fused._flat_input(view, shape, n)
            assert step == 1 and flat.shape == (n,)
            assert flat.flags.c_contiguous and flat.flags.writeable
            assert not np.shares_memory(flat, a)
            assert flat.tobytes() == np.broadcast_to(view, shape).tobytes()
            checked += 1
    assert checked > 200


def _bad_count(a, lo=None, hi=None, lo_open=False, hi_open=False, allow_inf=False):
    """The refused elements by numpy's masks, written from check_range's documented rule."""
    bad = np.isnan(a) | np.isneginf(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= ((a >= hi) if hi_open else (a > hi)) & ~(np.isposinf(a) & allow_inf)
    if not allow_inf:
        bad |= np.isposinf(a)
    return int(bad.sum())


def _large(seed=0, n=70_000):
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 1.5, n)
    a[rng.integers(0, n, 40)] = rng.choice(VALUES, 40)
    return a


@pytest.mark.parametrize("kw", BOUNDS)
def test_refused_count_compiled_as_written_and_as_numpy(kw):
    from agglomtool import _validate

    a = _large()
    full = dict(lo=None, hi=None, lo_open=False, hi_open=False, allow_inf=False) | kw
    want = _bad_count(a, **full)
    assert want > 0
    assert _validate._refused(a, **full) == want
    lo, hi = full["lo"], full["hi"]
    plain = _validate._count_refused(  # the plain Python loop, as written
        a[:5000], -math.inf if lo is None else lo, math.inf if hi is None else hi,
        full["lo_open"] and lo is not None, full["hi_open"] and hi is not None,
        full["allow_inf"])
    assert plain == _bad_count(a[:5000], **full)


@pytest.mark.parametrize("kw", BOUNDS)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_large_arrays_counted_in_one_pass_as_the_reductions(monkeypatch, kw, seed):
    """A large C-contiguous array is checked by the compiled count; the same values in a
    strided array by numpy's reductions: the same verdict and message (index included)."""
    from agglomtool import _validate

    calls = []
    real = _validate._refused

    def counted(*args):
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(_validate, "_refused", counted)
    a = _large(seed)
    if seed == 2:  # every value allowed (for these bounds): the array itself returned
        a = np.clip(np.nan_to_num(a, nan=0.5), 0.25, 0.75)
    strided = np.empty(2 * a.size)[::2]
    strided[...] = a
    got = _verdict(lambda: check_range("x", a, **kw))
    assert len(calls) == 1
    ref = _verdict(lambda: check_range("x", strided, **kw))
    assert len(calls) == 1  # (not C-contiguous: numpy's reductions)
    assert got == ref
    if got[0] == "ok":
        assert check_range("x", a, **kw) is a
