"""A map's block at the kernel's pace (strong scaling of a map over threads): an input given twice
flattened once, the loops' blocks spread over the threads
(:func:`agglomtool.collision.fused.launch_blocks`), every group of a block read from one
resolved scene: the same numbers in every case."""

from __future__ import annotations

import math
import warnings

import numba
import numpy as np
import pytest

import agglomtool as at
from agglomtool.collision import fused
from agglomtool.collision.fused import (
    BLOCK,
    BLOCKS_PER_THREAD,
    INPUT_NAMES,
    TIER_PAPER,
    TIER_RELATIVE,
    flat_inputs,
    launch_blocks,
)
from agglomtool.pair import wet_mass


def _bits(a):
    a = np.ascontiguousarray(a)
    return a.dtype, a.shape, a.tobytes()


def test_an_input_given_twice_is_flattened_once():
    """``h0`` and ``h0_j`` (the same array: a pair of one coating) share one flat copy."""
    rng = np.random.default_rng(3)
    shape = (6, 50, 4)
    h0 = rng.uniform(1e-6, 1e-5, (6, 50, 1))
    other = rng.uniform(size=(1, 50, 1))
    values = [0.5] * len(INPUT_NAMES)
    values[2] = values[6] = h0
    values[8] = other
    ins, steps = flat_inputs(tuple(values), shape)
    assert ins[2] is ins[6]
    assert steps[2] == steps[6] == steps[8] == 1
    assert _bits(ins[2]) == _bits(np.broadcast_to(h0, shape).ravel())
    assert _bits(ins[8]) == _bits(np.broadcast_to(other, shape).ravel())


def test_launch_blocks_give_every_thread_several_blocks():
    threads = numba.get_num_threads()
    for n in (2000, 4096, 58 * 4096, 240_000, 10**7):
        block, lanes = launch_blocks(n)
        nb = -(-n // block)
        assert 1 <= lanes <= threads and lanes <= nb
        assert block <= BLOCK
        assert block >= fused.MIN_BLOCK or block == BLOCK
        if n >= threads * BLOCKS_PER_THREAD * BLOCK:
            assert block == BLOCK  # large launches keep the full blocks
        elif n >= threads * BLOCKS_PER_THREAD * fused.MIN_BLOCK:
            assert nb >= threads * BLOCKS_PER_THREAD  # several blocks for each thread
    # the propensity's blocks: of collisions, at most ``full``, at least ``least``
    for n in (100, 1200, 50_000):
        block, lanes = launch_blocks(n, 20, 1)
        assert 1 <= block <= 20 and 1 <= lanes <= min(threads, -(-n // block))
        if n >= threads * BLOCKS_PER_THREAD * 20:
            assert block == 20


def _batch(rng, n):
    """``n`` random collisions as the fused kernels take them, some of them not
    approaching (rule 3 of the speed checks) so that the first offender is tested too."""
    d = rng.uniform(1e-4, 2e-3, n)
    u0 = rng.uniform(0.01, 3.0, n)
    u0_j = np.where(rng.random(n) < 0.002, -u0 - 0.1, np.nan)  # a few not approaching
    values = (d, 2650.0, rng.uniform(1e-6, 5e-5, n), 1e-6, d[::-1].copy(), 2650.0,
              rng.uniform(1e-6, 5e-5, n), 1e-6, 10 ** rng.uniform(-3.0, 2.0, n), 0.07,
              1000.0, rng.uniform(0.0, 80.0, n), 1.8e-5, 1.2, 0.45, np.nan,
              rng.uniform(0.0, 360.0, n), 0.9, u0, u0_j)
    return flat_inputs(values, (n,))


@pytest.mark.parametrize("tier", [TIER_RELATIVE, TIER_PAPER])
def test_fused_loop_gives_the_same_numbers_however_its_blocks_are_dealt(tier):
    rng = np.random.default_rng(26)
    n = 9000
    ins, steps = _batch(rng, n)

    def run(parallel, *how):
        out = (np.empty(n), np.empty(n, dtype=np.int8), np.empty(n, dtype=np.int8),
               np.empty(n), np.empty((n, 0)))
        first = fused._FUSED_ENTRY[tier, parallel](ins, steps, (True, None, True), out, *how)
        return [_bits(o) for o in out], tuple(int(f) for f in first)

    ref = run(False)
    assert ref[1][2] < n  # some collision breaks rule 3: its first offender is compared
    for block, lanes in ((4096, 1), (4096, 2), (256, 2), (256, 3), (1000, 7), (1, 5),
                         launch_blocks(n)):
        assert run(True, block, lanes) == ref, (block, lanes)


def test_map_block_gives_the_same_numbers_at_every_thread_count():
    """A whole map (u0*, the collisions at the typical speed, the propensity) is bitwise
    the same on 1 thread and on all, whatever the launches' blocks."""
    scene = at.Scene(liquid="water", T=298.15, d_i=300e-6)
    axes = dict(T=np.linspace(283.15, 363.15, 5), h0=np.geomspace(1e-6, 30e-6, 40),
                U_Umf=np.linspace(1.2, 8.0, 60))
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = at.sweep(scene, **axes)
        numba.set_num_threads(before)
        every = at.sweep(scene, **axes)
    finally:
        numba.set_num_threads(before)
    for name in one.data_vars:
        assert _bits(one[name].values) == _bits(every[name].values), name


def test_propensity_loop_gives_the_same_numbers_however_its_blocks_are_dealt():
    from test_sticking_exact import _random_pairs

    from agglomtool.collision import sticking

    rng = np.random.default_rng(5)
    pairs = _random_pairs(11, 3, angles=60)
    for pr in pairs:
        ins, steps, cshape, tier, body, slip = pr.pair(pr.u_star)
        n = int(np.prod(cshape))
        us = np.ascontiguousarray(np.broadcast_to(pr.u_star, cshape)).ravel()
        inner = 7
        finite = np.where(np.isfinite(us) & (us > 0.0), us, 1.0)
        p1 = (finite[:, None] * 10 ** rng.uniform(-0.5, 2.0, (n, inner))).ravel()
        args = ((ins, steps, us, 1 if us.size > 1 else 0), (int(tier), bool(body),
                True if slip else None), inner, (2, p1, 1, np.ones(1), 0))
        ref = np.empty(n * inner)
        sticking._propensity_serial(*args, ref)
        for per, lanes in ((20, 1), (1, 2), (3, 3), (7, 16), launch_blocks(n, 4096 // inner, 1)):
            got = np.full(n * inner, -1.0)
            sticking._propensity_parallel(*args, got, per, lanes)
            assert _bits(got) == _bits(ref), (per, lanes)


def _grids():
    water = at.Scene(liquid="water", T=298.15, d_i=300e-6)
    yield water, dict(U_Umf=np.linspace(1.5, 6.0, 7), T=np.linspace(290.0, 350.0, 4),
                      h0=np.geomspace(2e-6, 2e-5, 5))
    yield water, dict(T=np.linspace(290.0, 350.0, 3), solid_i=["silica-sand", "ilmenite"],
                      U_Umf=np.linspace(1.5, 6.0, 4))
    slag = at.Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6, speed="lognormal",
                    u0=0.1, sigma_ln=0.5)
    yield slag, dict(h0=np.geomspace(0.12e-6, 2e-6, 5), u0=np.geomspace(0.01, 2.0, 6),
                     T=np.linspace(900.0, 1300.0, 3))


@pytest.mark.parametrize("case", range(3))
def test_a_block_resolves_its_scene_once_for_all_groups(case, monkeypatch):
    """Every group of a block read from one resolved scene: the same numbers as each group
    evaluated on its own (the block function over the group's dimensions), bitwise, with
    the grid's axes in any order and a swept name; the gas properties evaluated once per
    map (over its whole T and P axes, at its first block), not once per block or per group
    that needs them."""
    from agglomtool import scene as scene_module
    from agglomtool.maps.layout import GROUPS, _block_function
    from agglomtool.maps.plan import _compat, _plan

    sc, grid = list(_grids())[case]
    plan = _plan(sc, "auto", 16, grid)
    calls = []
    real = scene_module.gas_properties
    monkeypatch.setattr(scene_module, "gas_properties",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    for n, (idx, sl) in enumerate(plan.blocks()):
        before = len(calls)
        got = plan.evaluate(sl, plan.lazy_names)
        assert len(calls) - before == (1 if n == 0 else 0), idx
        ref = {}
        for group, (_, outs, _) in GROUPS.items():
            dims = plan.group_dims[group]
            if not dims:
                continue
            args = [_compat(plan.grid[d][sl[d]], (d,), dims) for d in dims]
            if group == "collision":
                args.append(_compat(np.asarray(ref["u_star"]), plan.group_dims["critical"],
                                    dims))
            ref.update(zip(outs, _block_function(plan.base, dims, group, 16)(*args),
                           strict=True))
        for name in plan.lazy_names:
            assert _bits(got[name]) == _bits(ref[name]), (idx, name)
        plan._memo.last = None  # the next block's u0* computed again, counted again


def test_compiled_passes_give_numpys_numbers():
    """The one-pass forms of the excess-gas law, the Maxwellian median, the Stokes number
    and the margin give bitwise numpy's formulas, broadcasting as they do, with the
    edge values (an infinite or zero u0*, NaN, a negative excess refused as before)."""
    from agglomtool.bed.speed_models import IMPACT_SPEED_MODELS
    from agglomtool.bed.speeds import SpeedModel
    from agglomtool.scene import Resolved, _margin_of

    rng = np.random.default_rng(11)
    U = rng.uniform(0.2, 3.0, (5, 1, 7))
    Umf = rng.uniform(0.01, 0.15, (1, 4, 1))
    ratio = rng.uniform(0.05, 0.5, (1, 4, 7))
    law = IMPACT_SPEED_MODELS["excess-gas"].law
    theta = law({"U": U, "Umf": Umf, "fluctuation_ratio": ratio}).theta
    assert _bits(theta) == _bits((ratio * (U - Umf)) ** 2)
    with_nan = U.copy()
    with_nan[2, 0, 3] = np.nan  # numpy's formula lets NaN through; so does the pass
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nor a warning that numpy does not give
        theta = law({"U": with_nan, "Umf": Umf, "fluctuation_ratio": 0.3}).theta
    assert _bits(theta) == _bits((np.asarray(0.3) * (with_nan - Umf)) ** 2)
    low = U.copy()
    low[1, 0, 2] = 0.005  # below every U_mf: refused, naming the value
    with pytest.raises(ValueError, match="U = 0.005 m/s does not exceed U_mf"):
        law({"U": low, "Umf": Umf, "fluctuation_ratio": 0.3})
    th = rng.uniform(1e-5, 2.0, (3, 1, 6))
    got = SpeedModel("maxwellian", granular_temperature=th).median()
    assert _bits(got) == _bits(np.sqrt(th * np.log(2.0)))
    out = np.full(th.shape, 3.0)
    assert SpeedModel("maxwellian", granular_temperature=th).median(out=out) is out
    assert _bits(out) == _bits(np.sqrt(th * np.log(2.0)))
    assert _bits(SpeedModel("maxwellian", granular_temperature=0.02).median()) == _bits(
        np.sqrt(np.asarray(0.02) * np.log(2.0)))
    r = Resolved(dict(at.Scene(liquid="water", T=298.15, d_i=300e-6).values(),
                      h0=rng.uniform(2e-6, 2e-5, (3, 4, 1)), T=rng.uniform(290, 340, (3, 1, 1))))
    p_i, p_j = r.particles
    m_i, m_j = wet_mass(p_i, r.liquid.rho), wet_mass(p_j, r.liquid.rho)
    m_r, rad = m_i * m_j / (m_i + m_j), 2.0 / (2.0 / p_i.d + 2.0 / p_j.d)
    for u0 in (rng.uniform(0.01, 2.0, (1, 1, 6)), rng.uniform(0.01, 2.0, (3, 4, 6)), 0.3,
               rng.uniform(0.01, 2.0, (4, 1))):
        ref = m_r * 2.0 * u0 / (1.5 * math.pi * r.liquid.mu * rad * rad)
        assert _bits(r.stokes(u0)) == _bits(ref)
    u_typ = rng.uniform(0.01, 2.0, (3, 4, 6))
    u_star = rng.uniform(0.01, 2.0, (3, 4, 1))
    u_star[0, 1, 0], u_star[1, 2, 0], u_star[2, 3, 0] = np.inf, 0.0, np.nan
    with np.errstate(divide="ignore", invalid="ignore"):
        ref = np.where(np.isinf(u_star), 0.0, u_typ / u_star)
        out = np.full(u_typ.shape, 7.0)
        _margin_of(u_typ, u_star, out=out)
    assert _bits(out) == _bits(ref)


def test_an_in_memory_map_faults_its_result_in_on_every_thread(monkeypatch):
    """The result's arrays of a map in memory are touched page by page in a compiled
    parallel launch before the blocks are computed (the first write of a page costs a
    fault, which was the calling thread's), and the map is the same as without."""
    from agglomtool.maps import grid

    scene = at.Scene(liquid="water", T=298.15, d_i=300e-6)
    axes = dict(T=np.linspace(283.15, 363.15, 4), h0=np.geomspace(1e-6, 30e-6, 30),
                U_Umf=np.linspace(1.2, 8.0, 5000))  # 6e5 points: arrays of 4.8 MB
    touched = []
    real = grid.prefault

    def counted(arrays):
        arrays = list(arrays)
        touched.append(sum(a.nbytes for a in arrays))
        real(arrays)

    monkeypatch.setattr(grid, "prefault", counted)
    got = at.sweep(scene, **axes)
    assert touched and touched[0] >= 6e5 * 8 * 6  # the map's float outputs at least
    monkeypatch.setattr(grid, "prefault", lambda arrays: None)
    ref = at.sweep(scene, **axes)
    for name in ref.data_vars:
        assert _bits(got[name].values) == _bits(ref[name].values), name
    buf = np.full(3 * grid.PAGE + 5, 7, dtype=np.uint8)
    grid._touch(buf, grid.PAGE)
    assert [int(i) for i in np.flatnonzero(buf == 0)] == [0, grid.PAGE, 2 * grid.PAGE,
                                                          3 * grid.PAGE]


@pytest.mark.parametrize("law", [{}, {"speed": "fixed", "u0": 0.1}])
def test_typical_speed_and_stokes_number_are_computed_into_the_result(law):
    """``collision_outputs`` with ``out`` computes u_typical (where the median is
    computed: a Maxwellian's), St and the propensity (the compiled sticking set's one
    pass) in the given arrays, which it returns: the same numbers, bit for bit, as
    without."""
    from agglomtool.scene import Resolved, collision_outputs

    scene = at.Scene(**{**at.Scene(liquid="water", T=298.15, d_i=300e-6).values(), **law})
    axes = dict(T=np.linspace(290.0, 340.0, 3), h0=np.geomspace(2e-6, 2e-5, 4))
    axes.update(dict(U_Umf=np.linspace(1.5, 6.0, 9)) if not law else
                dict(u0=np.geomspace(0.01, 1.0, 9)))
    # each axis along its own dimension (numpy's open mesh), as a map's block
    r = Resolved({**scene.values(), **dict(zip(axes, np.ix_(*axes.values()), strict=True))})
    u_star = np.array(r.u_star, dtype=float)
    ref = collision_outputs(r, u_star, 16)
    out = {k: np.full(ref[k].shape, np.nan) for k in ("u_typical", "St", "propensity")}
    got = collision_outputs(r, u_star, 16, out=dict(out))
    assert got["St"] is out["St"] and got["propensity"] is out["propensity"]
    assert (got["u_typical"] is out["u_typical"]) == (not law)  # a fixed speed is u0
    for name in ref:
        assert _bits(got[name]) == _bits(ref[name]), name
