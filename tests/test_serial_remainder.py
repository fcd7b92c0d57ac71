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
