"""The shortcuts of ``collide``'s Python-level input handling (small batches) agree with the
general paths they bypass: a Python float and the same value as a numpy scalar, a list or an
array of any layout give bitwise the same results, and a bad value the same message."""

import math

import numpy as np
import pytest
from numba import typeof

import agglomtool as at
from agglomtool._validate import as_float_array, check_range
from agglomtool.collision.fused import flat_inputs
from agglomtool.pair import broadcast_shape

# (lo, hi, lo_open, hi_open, allow_inf, unit) of the fields of the inputs and a few more.
RANGES = [
    (0.0, None, True, False, True, "m"),      # Particle.d
    (0.0, None, False, False, False, "m"),    # Particle.h0
    (0.0, 90.0, False, True, False, "deg"),   # Liquid.theta_deg
    (0.0, 1.0, True, True, False, "-"),       # Bed.eps
    (0.0, 1.0, False, False, False, "-"),     # e
    (None, None, False, False, False, ""),    # no bounds: only NaN and inf refused
    (None, 2.5, False, True, True, "m/s"),
]
VALUES = [0.0, -0.0, 1.0, 0.5, 90.0, 89.999, 2.5, -1e-300, 1e-300, 1e300, -3.0, 1.0 + 1e-16,
          math.inf, -math.inf, math.nan, 0, 1, 2, -1, 90, 3]


def outcome(fn, *args, **kw):
    """What ``fn`` gives: ``("ok", array)`` or ``("error", message)``."""
    try:
        return "ok", fn(*args, **kw)
    except ValueError as exc:
        return "error", str(exc)


def same_outcome(a, b):
    if a[0] != b[0]:
        return False
    if a[0] == "error":
        return a[1] == b[1]
    x, y = a[1], b[1]
    return (x.dtype == y.dtype == np.float64 and x.shape == y.shape
            and np.array_equal(x, y, equal_nan=True))


@pytest.mark.parametrize("bounds", RANGES)
@pytest.mark.parametrize("value", VALUES)
def test_check_range_of_a_python_number_is_that_of_a_numpy_scalar(bounds, value):
    lo, hi, lo_open, hi_open, allow_inf, unit = bounds
    kw = dict(lo_open=lo_open, hi_open=hi_open, allow_inf=allow_inf, unit=unit)
    fast = outcome(check_range, "x.f", value, lo, hi, **kw)
    general = outcome(check_range, "x.f", np.float64(value), lo, hi, **kw)
    listed = outcome(check_range, "x.f", [value], lo, hi, **kw)
    assert same_outcome(fast, general), (fast, general)
    assert listed[0] == fast[0]
    if fast[0] == "ok":
        assert fast[1].ndim == 0
        assert not np.isnan(fast[1])  # no silent NaN
    else:  # the same message, value and range named (a list's NaN also by its index)
        assert listed[1] == fast[1].replace("nan is", "nan at index (0,) is")


def test_as_float_array_keeps_a_float64_array_and_names_its_first_nan():
    a = np.linspace(0.0, 1.0, 7)
    assert as_float_array("u0", a) is a  # np.asarray's answer: no copy
    b = a.copy()
    b[4] = np.nan
    b[6] = np.nan
    with pytest.raises(ValueError, match=r"^u0 = nan at index \(4,\) is not a number"):
        as_float_array("u0", b)
    with pytest.raises(ValueError, match=r"^u0 = nan at index \(0, 1\) is not a number"):
        as_float_array("u0", b[2:6].reshape(2, 2).T)  # not contiguous
    # Other dtypes and subclasses still go through the conversion.
    assert as_float_array("u0", a.astype(np.float32)).dtype == np.float64
    assert type(as_float_array("u0", np.ma.masked_array(a))) is np.ndarray
    with pytest.raises(ValueError, match="is a boolean"):
        as_float_array("u0", np.array([True, False]))


@pytest.mark.parametrize("shapes", [
    [(5,), (5,), (), (5,)], [(1,), ()], [(3, 1), (4,)], [(3, 4), (3, 4), (1, 4)],
    [(2, 1, 3), (2, 1, 3)], [(7,)], [(0,), (0,)], [(0,), (1,)],
])
def test_broadcast_shape_is_numpys(shapes):
    values = [np.zeros(s) for s in shapes] + [math.nan, 0.5]
    assert broadcast_shape(["v"] * len(values), values) == np.broadcast_shapes(*shapes)


def test_broadcast_shape_names_the_fields_that_do_not_broadcast():
    values = (np.zeros(3), math.nan, np.zeros(4), np.zeros(()))
    with pytest.raises(ValueError, match=r"inputs do not broadcast together: a \(3,\), c \(4,\)"):
        broadcast_shape(("a", "b", "c", "d"), values)


def layouts(rng, shape):
    """The same values of ``shape`` in several memory layouts."""
    base = rng.uniform(0.1, 1.0, shape)
    readonly = base.copy()
    readonly.flags.writeable = False
    yield base
    yield readonly
    yield np.asfortranarray(base)
    yield np.repeat(base, 2, axis=-1)[..., ::2]  # strided view
    yield base.astype(np.float32)


@pytest.mark.parametrize("shape", [(6,), (2, 3), (3, 1), (1, 6)])
def test_flat_inputs_gives_contiguous_float64_rows_of_one_type(shape):
    rng = np.random.default_rng(3)
    n = math.prod(shape)
    ref_type = None
    for a in layouts(rng, shape):
        values = (a, np.array(0.25), math.nan, np.ones(1), np.ones((1, 1)))
        full = np.broadcast_shapes(shape, (1,), (1, 1))
        ins, steps = flat_inputs(values, full)
        assert list(steps) == [1, 0, 0, 0, 0]
        for arr in ins:
            assert arr.ndim == 1 and arr.dtype == np.float64
            assert arr.flags.c_contiguous and arr.flags.writeable
        assert ins[0].shape == (n,)
        assert np.array_equal(ins[0], np.broadcast_to(a, full).astype(np.float64).ravel())
        assert [x.shape for x in ins[1:]] == [(1,)] * 4
        assert ins[1][0] == 0.25 and math.isnan(ins[2][0]) and ins[3][0] == ins[4][0] == 1.0
        # One numba type for all, whatever the layout given (no other compiled variant).
        assert typeof(ins) == (ref_type := ref_type or typeof(ins))
    c = np.ascontiguousarray(rng.uniform(size=shape))
    assert np.shares_memory(flat_inputs((c,), shape)[0][0], c)  # used in place


def scene(rng, n, kind):
    """Keywords of a collision batch of ``n``, each field given as ``kind``."""
    def v(lo, hi):
        x = rng.uniform(lo, hi, n)
        return {
            "float": lambda: float(x[0]),
            "numpy scalar": lambda: np.float64(x[0]),
            "0-d": lambda: np.array(x[0]),
            "list": lambda: list(x),
            "array": lambda: x,
            "column": lambda: x.reshape(-1, 1)[:, 0],
            "readonly": lambda: np.frombuffer(x.tobytes()),
            "strided": lambda: np.repeat(x, 2)[::2],
            "float32 exact": lambda: x.astype(np.float32).astype(np.float64),
        }[kind]()
    return dict(
        p_i=at.Particle(d=v(3e-4, 1.5e-3), rho=v(2000, 4500), h0=v(1e-7, 9e-6), ha=v(5e-8, 2e-7)),
        p_j=at.Particle(d=v(3e-4, 1.5e-3), rho=v(2000, 4500), h0=v(1e-7, 9e-6), ha=v(5e-8, 2e-7)),
        liquid=at.Liquid(mu=v(1e-3, 10), gamma=v(0.05, 0.4), rho=v(900, 2500),
                         theta_deg=v(0, 60)),
        gas=at.Gas(mu=v(1.8e-5, 4.5e-5), rho=v(0.3, 1.2)),
        bed=at.Bed(eps=v(0.4, 0.7)), beta_deg=v(0, 360), u0=v(0.01, 2.0), e=v(0.5, 0.95),
    )


SCALAR_KINDS = ["float", "numpy scalar", "0-d"]
ARRAY_KINDS = ["list", "array", "column", "readonly", "strided"]


@pytest.mark.parametrize("mode", ["relative", "paper", "auto", "stokes"])
@pytest.mark.parametrize("kinds,n", [(SCALAR_KINDS, 1), (ARRAY_KINDS, 7), (ARRAY_KINDS, 100)])
def test_collide_gives_bitwise_the_same_whatever_the_input_kind(mode, kinds, n):
    results = []
    for kind in kinds:
        r = at.collide(**scene(np.random.default_rng(11), n, kind), mode=mode, details=False)
        results.append((kind, r))
    kind0, r0 = results[0]
    assert np.all(np.isfinite(r0.e_w)) and np.all(r0.stage >= 0)
    for kind, r in results[1:]:
        for name in ("e_w", "agglomerated", "stage", "path", "w"):
            a, b = getattr(r0, name), getattr(r, name)
            assert a.shape == b.shape and a.dtype == b.dtype, (kind0, kind, name)
            assert np.array_equal(a, b), (kind0, kind, name)


def test_mixed_scalars_and_arrays_broadcast_as_numpy_does():
    rng = np.random.default_rng(2)
    kw = scene(rng, 4, "array")
    kw["beta_deg"] = kw["beta_deg"].reshape(4, 1)  # (4, 1) with (4,): a (4, 4) batch
    kw["e"] = 0.8
    r = at.collide(**kw, details=False)
    assert r.e_w.shape == (4, 4)
    for i in range(4):
        one = at.collide(**{**kw, "beta_deg": float(kw["beta_deg"][i, 0])}, details=False)
        assert np.array_equal(r.e_w[i], one.e_w) and np.array_equal(r.w[i], one.w)


@pytest.mark.parametrize("field,value,message", [
    ("e", 1.5, "e = 1.5 is outside the allowed range [0, 1]"),
    ("e", math.nan, "e = nan is not a number; allowed: [0, 1]"),
    ("e", -math.inf, "e = -inf is outside the allowed range [0, 1]"),
    ("u0", math.nan, "u0 = nan is not a number; allowed: [-1e+12, 1e+12] m/s"),
    ("beta_deg", math.nan, "beta_deg = nan is not a number; allowed: [-3600, 3600] deg"),
    ("u0", -1.0, "u0 + u0_j = -2.0 m/s is outside the allowed range (0, inf)"),
    ("u0", math.inf, "u0 = inf is outside the allowed range [-1e+12, 1e+12] m/s"),
])
@pytest.mark.parametrize("kind", [float, np.float64, lambda x: [x]])
@pytest.mark.parametrize("mode", ["relative", "paper", "auto", "stokes"])
def test_bad_values_are_named_alike_through_every_path(field, value, message, kind, mode):
    kw = scene(np.random.default_rng(0), 1, "float")
    kw[field] = kind(value)
    with pytest.raises(ValueError) as err:
        at.collide(**kw, mode=mode)
    if kind not in (float, np.float64):  # a list's NaN is named by its index too
        message = message.replace("nan is", "nan at index (0,) is")
    assert message in str(err.value)


@pytest.mark.parametrize("value,message", [
    (-1.0, "Particle.d = -1.0 is outside the allowed range (0, 1e+10] m or inf"),
    (0.0, "Particle.d = 0.0 is outside the allowed range (0, 1e+10] m or inf"),
    (math.nan, "Particle.d = nan is not a number; allowed: (0, 1e+10] m or inf"),
    (-math.inf, "Particle.d = -inf is outside the allowed range (0, 1e+10] m or inf"),
])
@pytest.mark.parametrize("kind", [float, np.float64, np.array])
def test_bad_fields_are_named_alike_for_python_and_numpy_numbers(value, message, kind):
    with pytest.raises(ValueError) as err:
        at.Particle(d=kind(value), rho=2500.0)
    assert str(err.value) == message


@pytest.mark.parametrize("kind", [float, np.float64, np.array, lambda x: [x, x]])
def test_infinite_density_only_for_a_plate_whatever_the_kind(kind):
    assert np.all(at.Particle(d=kind(math.inf), rho=kind(math.inf)).is_plate)
    with pytest.raises(ValueError, match=r"^Particle.rho = inf is allowed only for a plate"):
        at.Particle(d=kind(1e-3), rho=kind(math.inf))
    # Broadcast against an array of diameters: the finite one has an infinite density.
    with pytest.raises(ValueError, match=r"^Particle.rho = inf is allowed only for a plate"):
        at.Particle(d=[math.inf, 1e-3], rho=kind(math.inf))
    mixed = at.Particle(d=[1e-3, math.inf], rho=[2500.0, math.inf], h0=kind(1e-6))
    assert list(mixed.is_plate) == [False, True]
