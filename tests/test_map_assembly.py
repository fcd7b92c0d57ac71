"""A map computed in memory is assembled without block-sized copies, and it is the same map,
bit for bit, as the one its blocks give when each is computed on its own (the lazy Dataset
of ``build``, whose blocks are new arrays) and as one block over the whole grid."""

import numpy as np
import pytest
import xarray as xr
from _map_laws import LAWS

from agglomtool.maps import build, sweep
from agglomtool.maps.layout import GROUPS, _block_function
from agglomtool.maps.plan import _compat, _plan
from agglomtool.scene import Scene

WATER = Scene(liquid="water", T=298.15, d_i=300e-6)
SLAG = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
AXES = {
    "water": (WATER, dict(T=np.linspace(283.15, 363.15, 5), h0=np.geomspace(1e-6, 30e-6, 4))),
    "slag": (SLAG, dict(T=np.linspace(900.0, 1300.0, 5), h0=np.geomspace(0.12e-6, 2e-6, 4))),
}
CASES = [(m, law) for m in AXES for law in LAWS]


def _case(mat, law):
    scene, axes = AXES[mat]
    fields, axis = LAWS[law]
    return Scene(**{**scene.values(), **fields}), {**axes, **axis}


def _bits(a):
    a = np.ascontiguousarray(a)
    return a.view(np.uint8) if a.dtype.kind == "f" else a


def _same_bits(a: xr.Dataset, b: xr.Dataset):
    xr.testing.assert_identical(a, b)
    for name in a.variables:
        x, y = a[name].values, b[name].values
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert np.array_equal(_bits(x), _bits(y)), name  # NaN and -0.0 included


@pytest.mark.parametrize("mat, law", CASES)
def test_in_memory_map_equals_its_blocks_computed_alone(mat, law):
    scene, axes = _case(mat, law)
    # blocks that split every axis: a block's part of a result array is not contiguous
    chunks = {"T": 2, "h0": 3, list(LAWS[law][1])[0]: 4}
    here = sweep(scene, chunks=chunks, **axes)
    lazy = build(scene, chunks=chunks, **axes).compute(scheduler="synchronous")
    _same_bits(here, lazy)
    _same_bits(sweep(scene, chunks=None, **axes), here)


@pytest.mark.parametrize("mat, law", [("water", "excess-gas"), ("slag", "lognormal")])
def test_in_memory_map_equals_one_block_over_the_grid(mat, law):
    """The collision group as one call of its block function (new arrays) on the whole
    grid, against the sweep's arrays, which its blocks wrote in place."""
    scene, axes = _case(mat, law)
    ds = sweep(scene, chunks={"T": 2, "h0": 1}, **axes)
    plan = _plan(scene, None, 16, axes)
    dims = plan.group_dims["collision"]
    args = [_compat(plan.grid[d], (d,), dims) for d in dims]
    u_star = _compat(ds["u_star"].values, plan.group_dims["critical"], dims)
    vals = _block_function(plan.base, dims, "collision", 16)(*args, u_star)
    for name, v in zip(GROUPS["collision"][1], vals, strict=True):
        if name in ds.data_vars:
            assert np.array_equal(_bits(ds[name].values), _bits(v)), name


def test_blocks_are_written_in_place():
    """With ``out`` a block's variables are computed into the result's arrays: what
    ``evaluate`` returns is the result's memory, not a copy of it."""
    scene, axes = _case("slag", "fixed")
    plan = _plan(scene, {"T": 2, "h0": 2, "u0": 3}, 16, axes)
    out = {k: np.full(plan.var_shape(k), 7, dtype=plan.variables[k][1])
           for k in plan.lazy_names}
    for idx, sl in plan.blocks():
        got = plan.evaluate(sl, plan.owned(idx), out)
        assert set(got) == set(plan.owned(idx))
        for name, a in got.items():
            block = out[name][tuple(sl[d] for d in plan.variables[name][0])]
            assert np.shares_memory(a, block), name
            assert np.array_equal(_bits(a), _bits(block)), name
    ref = sweep(scene, chunks={"T": 2, "h0": 2, "u0": 3}, **axes)
    for name in plan.lazy_names:
        assert np.array_equal(_bits(out[name]), _bits(ref[name].values)), name


@pytest.mark.parametrize("mode", ["relative", "paper"])
def test_one_pass_propensity_equals_windows_then_integration(mode):
    """The sticking sets and their integration in one launch (collisions constant along
    trailing axes: a map's speed axes) give bitwise the propensity of the two steps
    (``sticking_windows`` per collision, then ``propensity_from_windows`` per element),
    on random pairs of which some stick again above u0* (the test fails if none does),
    every speed family, body forces on and off the axis (the quadrature's NaN where no
    set is proven)."""
    import math

    from test_sticking_exact import Pairs, _random_pairs

    from agglomtool.collision.sticking import (
        propensity_exact,
        propensity_from_windows,
        sticking_windows,
    )

    rng = np.random.default_rng(26)
    windows = fallback = 0
    for pairs in _random_pairs(11, 100, angles=25):  # test_sticking_exact's set
        if mode != "relative":
            k = pairs.kw
            pairs = Pairs(k["p_i"], k["p_j"], k["liquid"], k["gas"], k["beta_deg"], k["e"],
                          mode=mode)
        ins, steps, cshape, tier, body, slip = pairs.pair(pairs.u_star)
        n = int(np.prod(cshape))
        us = np.ascontiguousarray(np.broadcast_to(pairs.u_star, cshape)).ravel()
        sets = sticking_windows(ins, steps, n, tier, us, body=body, particle_slip=slip)
        count, status = sets.counts, sets.status
        windows += int(np.count_nonzero(count > 0))
        fallback += int(np.count_nonzero(status != 0))
        inner = 9  # speeds per collision, trailing
        finite = np.where(np.isfinite(us) & (us > 0.0), us, 1.0)
        speeds = (finite[:, None] * np.geomspace(0.3, 300.0, inner)[None, :]).ravel()
        idx = np.repeat(np.arange(n, dtype=np.int64), inner)
        for family, p1, p2 in ((0, speeds, np.ones(1)),
                               (1, speeds, rng.uniform(0.05, 1.5, n * inner)),
                               (2, speeds**2 / math.log(2.0), np.ones(1))):
            ref = propensity_from_windows(idx, family, p1, p2, us, sets)
            got = propensity_exact(ins, steps, n, tier, us, inner, body=body,
                                   particle_slip=slip, family=family, p1=p1, p2=p2)
            assert np.array_equal(got.view(np.uint64), ref.view(np.uint64)), family
        # a parameter per position along the speed axis, or per collision, read in place
        # of its copy over every element (PER_TRAILING, PER_COLLISION): the same numbers
        along = np.geomspace(0.01, 2.0, inner)
        per_c = finite * 3.0
        for family in (0, 1, 2):
            for part, how, full in ((along, 3, np.tile(along, n)),
                                    (per_c, 2, np.repeat(per_c, inner))):
                ref = propensity_from_windows(idx, family, full, np.full(1, 0.5), us, sets)
                got = propensity_exact(ins, steps, n, tier, us, inner, body=body,
                                       particle_slip=slip, family=family, p1=part,
                                       p2=np.full(1, 0.5), how=(how, 0))
                assert np.array_equal(got.view(np.uint64), ref.view(np.uint64)), (family, how)
    assert windows > 0
    if mode == "paper":
        assert fallback > 0  # body forces off the axis: sets left to the quadrature


def test_a_sweep_run_again_is_not_warmed_up_again(monkeypatch):
    """The estimate's warm-up (every group on a sample of points, to load the kernels
    before blocks are timed) runs once per process for a scene and its swept fields; a
    different scene is warmed up in its turn."""
    from agglomtool.maps.plan import SweepPlan

    calls = []
    real = SweepPlan.sample
    monkeypatch.setattr(SweepPlan, "sample",
                        lambda self, *a, **k: calls.append(1) or real(self, *a, **k))
    scene, axes = _case("slag", "fixed")
    scene = scene.replace(e=0.8123)  # a scene no other test sweeps
    axes = {**axes, "T": np.linspace(900.0, 1300.0, 100), "h0": np.geomspace(1e-7, 2e-6, 50),
            "u0": np.geomspace(0.01, 2.0, 30)}  # 1.5e5 points: timed, so warmed up
    first = sweep(scene, chunks=40_000, **axes)
    assert calls
    calls.clear()
    again = sweep(scene, chunks=40_000, **axes)
    assert not calls
    _same_bits(first, again)
    sweep(scene.replace(e=0.8124), chunks=40_000, **axes)
    assert calls


@pytest.mark.parametrize("mat, law", [("water", "excess-gas"), ("slag", "fixed")])
def test_margin_is_computed_into_the_result(mat, law):
    """``collision_outputs`` with ``out`` computes the margin in the given array (no
    block-sized temporaries): the same numbers, bit for bit, as without, inf u0* included
    (margin 0)."""
    from agglomtool.scene import Resolved, collision_outputs

    scene, axes = _case(mat, law)
    # each axis along its own dimension (numpy's open mesh), as a map's block
    r = Resolved({**scene.values(), **dict(zip(axes, np.ix_(*axes.values()), strict=True))})
    u_star = np.array(r.u_star, dtype=float)
    u_star.flat[::3] = np.inf  # above the ceiling
    ref = collision_outputs(r, u_star, 16)
    target = np.full(ref["margin"].shape, np.nan)
    got = collision_outputs(r, u_star, 16, out={"margin": target})
    assert got["margin"] is target
    assert np.array_equal(_bits(target), _bits(ref["margin"]))
    assert np.all(target[np.broadcast_to(np.isinf(u_star), target.shape)] == 0.0)
    for name in ref:
        assert np.array_equal(_bits(got[name]), _bits(ref[name])), name
