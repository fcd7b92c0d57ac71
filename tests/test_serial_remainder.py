"""A map block's serial work: results written where the map keeps them, not copied there.

``collide(out=...)`` writes ``e_w``, ``stage`` and ``agglomerated`` into the caller's arrays
(the fused tiers from their compiled loop), with the same values as without; a map in memory
hands its result's blocks to it, and ``U`` is computed into its block.
"""

from __future__ import annotations

import numpy as np
import pytest
from _random_pairs import as_inputs, random_arrays

import agglomtool as at
from agglomtool import api
from agglomtool.maps.plan import _plan
from agglomtool.scene import Scene

WATER = Scene(liquid="water", T=298.15, d_i=300e-6)


def _pairs(n=400, seed=3):
    a = random_arrays(n, seed)
    a["d_j"][::13] = np.inf
    return as_inputs(a), np.geomspace(0.01, 3.0, n)


def _tame(n):
    """Water-coated sand pairs (the ODE tier integrates them in few steps)."""
    rng = np.random.default_rng(5)
    p = at.Particle(d=rng.uniform(200e-6, 600e-6, n), rho=2650.0,
                    h0=rng.uniform(2e-6, 20e-6, n), ha=0.5e-6)
    kw = dict(p_i=p, p_j=p, liquid=at.Liquid(mu=1e-3, gamma=0.072, rho=1000.0),
              gas=at.Gas(mu=18.48e-6, rho=1.168), bed=at.Bed(eps=0.5))
    return kw, rng.uniform(0.01, 1.0, n)


@pytest.mark.parametrize("mode", at.MODES)
def test_collide_writes_into_out(mode):
    kw, u0 = _tame(40) if mode.startswith(("ode", "stokes")) else _pairs(400)
    ref = at.collide(u0=u0, mode=mode, details=False, **kw)
    n = u0.shape[0]
    out = {"e_w": np.full(n, -7.0), "stage": np.full(n, 99, dtype=np.int8),
           "agglomerated": np.ones(n, dtype=bool)}
    res = at.collide(u0=u0, mode=mode, details=False, out=out, **kw)
    for key in out:
        assert getattr(res, key) is out[key]
        assert out[key].tobytes() == getattr(ref, key).tobytes()
    assert res.path.tobytes() == ref.path.tobytes()


def test_collide_out_partial_and_large():
    kw, u0 = _pairs(5000)  # the parallel loop
    ref = at.collide(u0=u0, details=False, **kw)
    e_w = np.empty(5000)
    res = at.collide(u0=u0, details=False, out={"e_w": e_w}, **kw)
    assert res.e_w is e_w and e_w.tobytes() == ref.e_w.tobytes()
    assert res.stage.tobytes() == ref.stage.tobytes()
    assert res.agglomerated.tobytes() == ref.agglomerated.tobytes()


@pytest.mark.parametrize("bad, text", [
    ({"e_w": np.empty(3)}, r"out\['e_w'\] = float64 \(3,\)"),
    ({"stage": np.empty(400)}, r"out\['stage'\] = float64 \(400,\)"),
    ({"e_w": np.empty(800)[::2]}, r"out\['e_w'\] = float64 \(400,\)"),
    ({"w": np.empty(400)}, r"out\['w'\] is not allowed"),
    ([np.empty(400)], r"out = a list is not allowed"),
])
def test_collide_out_refused(bad, text):
    kw, u0 = _pairs()
    with pytest.raises(ValueError, match=text):
        at.collide(u0=u0, details=False, out=bad, **kw)


def test_map_block_written_in_place(monkeypatch):
    """A map in memory: collide gets the result's own blocks, U is computed into its block,
    and the block's values are those of the same block computed on its own."""
    axes = dict(T=np.linspace(283.15, 363.15, 4), h0=np.geomspace(1e-6, 30e-6, 5),
                U_Umf=np.linspace(1.2, 8.0, 6))
    plan = _plan(WATER, "auto", 16, axes)
    out = {k: np.full(plan.var_shape(k), 0, dtype=plan.variables[k][1])
           for k in plan.lazy_names}
    seen = {}
    real = api.collide

    def spy(*args, **kw):
        if kw.get("out"):
            seen.update(kw["out"])
        return real(*args, **kw)

    monkeypatch.setattr("agglomtool.scene.collide", spy)
    idx, sl = next(plan.blocks())
    got = plan.evaluate(sl, plan.owned(idx), out)
    block = tuple(sl[d] for d in plan.variables["e_w"][0])
    for key in ("e_w", "stage", "agglomerated"):
        assert seen[key].base is out[key] or seen[key] is out[key]
        assert np.shares_memory(seen[key], out[key][block])
        assert got[key].__array_interface__ == seen[key].__array_interface__
    monkeypatch.undo()
    alone = plan.evaluate(sl, plan.owned(idx))
    for key, value in alone.items():
        assert np.asarray(got[key]).tobytes() == np.asarray(value).tobytes(), key


def test_U_computed_into_its_block():
    from agglomtool.scene import Resolved

    vals = {**WATER.values(), "T": np.linspace(283.15, 363.15, 3).reshape(3, 1, 1),
            "h0": np.geomspace(1e-6, 30e-6, 4).reshape(1, 4, 1),
            "U_Umf": np.linspace(1.2, 8.0, 5)}
    ref = Resolved(vals).U
    r = Resolved(vals)
    target = np.empty((3, 4, 5))
    r.U_into(target)
    assert r.U is target and target.tobytes() == ref.tobytes()
    r2 = Resolved(vals)
    small = np.empty((3, 4, 1))  # not the product's shape: left alone, computed as before
    r2.U_into(small)
    assert r2.U is not small and r2.U.tobytes() == ref.tobytes()


def _broadcast_block(seed=0, shape=(3, 7, 5)):
    """Inputs of one collide over ``shape``, each varying along some of its axes only (as a
    map's block hands them), some not C-contiguous, a plate and an impossible speed among
    them on request."""
    rng = np.random.default_rng(seed)

    def along(*axes, lo=0.0, hi=1.0):
        s = [n if k in axes else 1 for k, n in enumerate(shape)]
        return rng.uniform(lo, hi, s)

    h0 = along(1, lo=2e-6, hi=20e-6)
    d = np.asfortranarray(along(0, 2, lo=200e-6, hi=600e-6))  # not C-contiguous
    kw = dict(
        p_i=at.Particle(d=d, rho=2650.0, h0=h0, ha=0.5e-6),
        p_j=at.Particle(d=along(0, lo=200e-6, hi=600e-6), rho=2500.0, h0=h0, ha=0.5e-6),
        liquid=at.Liquid(mu=along(0, lo=1e-3, hi=1e-1), gamma=along(0, lo=0.02, hi=0.07),
                         rho=1000.0, theta_deg=along(2, lo=0.0, hi=60.0)),
        gas=at.Gas(mu=18.48e-6, rho=along(0, 1, lo=0.3, hi=1.2)),
        bed=at.Bed(eps=0.5, U=along(0, 1, lo=0.05, hi=0.3)),
        beta_deg=along(1, 2, lo=0.0, hi=360.0), e=0.9)
    return kw, rng.uniform(0.01, 1.5, shape)


@pytest.mark.parametrize("mode", ["relative", "paper"])
@pytest.mark.parametrize("body", [True, False])
def test_broadcast_inputs_read_in_place(monkeypatch, mode, body):
    """A collide whose inputs vary along some axes only (a map's block) is computed by the
    parallel loop from their own values: no block-sized copy of any of them (numpy's copy
    ran on the calling thread: the map's serial remainder), bitwise the same outcomes as
    from copies."""
    from agglomtool.collision import fused

    kw, u0 = _broadcast_block(shape=(5, 40, 30))  # 6000 collisions: the parallel loop
    full = {k: v for k, v in kw.items()}
    shape = u0.shape

    def copied(x):
        return np.ascontiguousarray(np.broadcast_to(x, shape))

    full["p_i"] = at.Particle(d=copied(kw["p_i"].d), rho=2650.0, h0=copied(kw["p_i"].h0),
                              ha=0.5e-6)
    full["p_j"] = at.Particle(d=copied(kw["p_j"].d), rho=2500.0, h0=copied(kw["p_j"].h0),
                              ha=0.5e-6)
    full["liquid"] = at.Liquid(mu=copied(kw["liquid"].mu), gamma=copied(kw["liquid"].gamma),
                               rho=1000.0, theta_deg=copied(kw["liquid"].theta_deg))
    full["gas"] = at.Gas(mu=18.48e-6, rho=copied(kw["gas"].rho))
    full["bed"] = at.Bed(eps=0.5, U=copied(kw["bed"].U))
    full["beta_deg"] = copied(kw["beta_deg"])
    ref = at.collide(u0=u0, mode=mode, body_forces=body, details=True, **full)
    sizes = []
    real = fused._flat_input
    monkeypatch.setattr(fused, "_flat_input",
                        lambda a, s, n: (sizes.append(np.size(a)), real(a, s, n))[1])
    got = at.collide(u0=u0, mode=mode, body_forces=body, details=True, **kw)
    assert all(z in (1, u0.size) for z in sizes)  # only u0 itself, no broadcast copy
    for f in ("e_w", "stage", "path", "w", "agglomerated"):
        assert getattr(got, f).tobytes() == getattr(ref, f).tobytes(), f
    for k, v in ref.details.items():
        assert got.details[k].tobytes() == v.tobytes(), k


@pytest.mark.parametrize("shape", [(4, 1, 600), (2, 3, 1, 5, 70), (1100, 1, 2), (1, 2, 1100)])
def test_broadcast_layouts(shape):
    """The in-place reading over layouts: size-1 axes, axes merged; the
    outcomes those of the copies, bitwise."""
    from agglomtool.collision import fused

    kw, u0 = _broadcast_block(seed=len(shape), shape=shape)
    p_i, p_j, liq, gas, bed = kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"]
    values = (p_i.d, p_i.rho, p_i.h0, p_i.ha, p_j.d, p_j.rho, p_j.h0, p_j.ha, liq.mu,
              liq.gamma, liq.rho, liq.theta_deg, gas.mu, gas.rho, bed.eps, bed.U,
              kw["beta_deg"], np.float64(kw["e"]), u0, np.nan)
    values = tuple(np.asarray(v, dtype=float) for v in values)
    ins, steps = fused.flat_inputs(values, shape)
    lz, lsteps, layout = fused.flat_inputs(values, shape, lazy=True)
    assert layout is not None and (lsteps == fused.BROADCAST).any()
    own = [lz[q].size for q in np.flatnonzero(lsteps == fused.BROADCAST)]
    assert max(own) <= u0.size and min(own) < u0.size  # their own values, not copies
    back, bsteps = fused.materialize(lz, lsteps, layout, shape)
    for a, b in zip(back, ins, strict=True):
        assert a.tobytes() == b.tobytes()
    n = u0.size
    for tier in (fused.TIER_PAPER, fused.TIER_RELATIVE):
        a = fused.fused_batch(ins, steps, n, tier, body=True, particle_slip=False, check=True)
        b = fused.fused_batch(lz, lsteps, n, tier, body=True, particle_slip=False, check=True,
                              layout=layout, shape=shape)
        for x, y in zip(a[:5], b[:5], strict=True):
            assert x.tobytes() == y.tobytes()
        assert a[5] == b[5]


def test_broadcast_speed_error_names_the_collision():
    """A speed rule broken inside a block read in place: the same error, at the same
    index, as from copies (the first offender over the lanes' blocks)."""
    kw, u0 = _broadcast_block(shape=(5, 40, 30))
    u0 = u0.copy()
    u0[3, 17, 4] = -2.0  # not approaching
    u0[4, 39, 29] = -3.0
    with pytest.raises(ValueError, match=r"not approaching: .* at index \(3, 17, 4\)"):
        at.collide(u0=u0, details=False, **kw)


@pytest.mark.parametrize("liquid, T", [("water", np.linspace(283.15, 363.15, 12)),
                                       ("hypothetical-slag", np.linspace(900.0, 1300.0, 12))])
def test_properties_once_per_map(monkeypatch, liquid, T):
    """The gas's and the liquid's properties of a map's blocks are computed once over the
    grid's T (and P) axes, not once per block; every block's values as computed alone."""
    import agglomtool.scene as scene_mod

    sc = Scene(liquid=liquid, T=float(T[0]), d_i=300e-6 if liquid == "water" else 1e-3,
               h0=2e-6 if liquid == "water" else 0.3e-6)
    axes = dict(T=T, P=np.array([1.0e5, 1.5e5]), U_Umf=np.linspace(1.2, 4.0, 5))
    plan = _plan(sc, {"T": 3, "P": 1, "U_Umf": 5}, 16, axes)
    assert plan.n_blocks == 8
    calls = {"gas": 0, "liquid": 0}
    real_gas, real_liquid = scene_mod.gas_properties, scene_mod.materials.liquid

    def gas(*a, **k):
        calls["gas"] += 1
        return real_gas(*a, **k)

    def liq(*a, **k):
        calls["liquid"] += 1
        return real_liquid(*a, **k)

    monkeypatch.setattr(scene_mod, "gas_properties", gas)
    monkeypatch.setattr(scene_mod.materials, "liquid", liq)
    got = {idx: plan.evaluate(sl, plan.owned(idx)) for idx, sl in plan.blocks()}
    assert calls["gas"] == 1 and calls["liquid"] <= 1
    monkeypatch.undo()
    for idx, sl in plan.blocks():  # each block alone, its own properties
        alone = _plan(sc, {"T": 3, "P": 1, "U_Umf": 5}, 16, axes)
        alone.__dict__["_whole_properties"] = None
        ref = alone.evaluate(sl, alone.owned(idx))
        for k, v in ref.items():
            assert np.asarray(got[idx][k]).tobytes() == np.asarray(v).tobytes(), (idx, k)


def test_broadcast_read_only_inputs():
    """Read-only inputs (numpy's broadcast views, as a caller may pass them) are read in
    place as the others (the loops take one array type)."""
    kw, u0 = _broadcast_block(shape=(5, 40, 30))
    ref = at.collide(u0=u0, details=False, **kw)
    ro = np.broadcast_to(u0, u0.shape)  # read-only, C-contiguous, every collision
    h0 = np.broadcast_to(kw["p_i"].h0, (1, 40, 1))  # read-only, broadcast
    kw["p_i"] = at.Particle(d=kw["p_i"].d, rho=2650.0, h0=h0, ha=0.5e-6)
    kw["p_j"] = at.Particle(d=kw["p_j"].d, rho=2500.0, h0=h0, ha=0.5e-6)
    got = at.collide(u0=ro, details=False, **kw)
    for f in ("e_w", "stage", "path", "w"):
        assert getattr(got, f).tobytes() == getattr(ref, f).tobytes(), f
