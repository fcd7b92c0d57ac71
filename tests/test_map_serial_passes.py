"""A map block's per-point work off the calling thread: the excess-gas estimate's granular
temperature (agglomtool.bed.speed_models._excess_pass) and ``U = U_Umf U_mf`` written into
the map's block (agglomtool.scene._product_pass) are compiled parallel passes, equal bit for
bit to numpy's formulas, with the same errors."""

import warnings

import numpy as np
import pytest

import agglomtool.scene as scene_mod
from agglomtool.bed import speed_models as sm
from agglomtool.maps import sweep
from agglomtool.scene import Resolved, Scene


def _counted(monkeypatch, module, name):
    """Replace ``module.name`` (a kernel launched from Python) by a wrapper that counts."""
    calls = []
    real = getattr(module, name)

    def wrapper(*args):
        calls.append(args)
        return real(*args)

    monkeypatch.setattr(module, name, wrapper)
    return calls


def _excess_inputs(seed=0, shape=(5, 30, 40)):
    """U over every axis, U_mf over the first two, the ratio a 0-d array: a map's block."""
    rng = np.random.default_rng(seed)
    Umf = rng.uniform(0.05, 0.4, shape[:2] + (1,))
    U = Umf * rng.uniform(1.05, 8.0, shape)
    return U, Umf, np.asarray(0.3)


def _formula(U, Umf, ratio):
    """The estimate's formula as numpy writes it: ``(ratio (U - U_mf))**2``."""
    return (ratio * (U - Umf)) ** 2


@pytest.mark.parametrize("layout", ["C", "strided", "broadcast ratio"])
def test_excess_gas_pass_equals_numpy_formula(monkeypatch, layout):
    U, Umf, ratio = _excess_inputs()
    if layout == "strided":  # U a non-contiguous view (a block of a larger result)
        big = np.empty(U.shape[:2] + (2 * U.shape[2],))
        big[:, :, ::2] = U
        U = big[:, :, ::2]
    elif layout == "broadcast ratio":  # the ratio along the first axis
        ratio = np.linspace(0.2, 0.5, U.shape[0]).reshape(-1, 1, 1)
    U[1, 2, 3] = np.nan  # NaN is no refusal: it stays NaN, as in numpy's formula
    calls = _counted(monkeypatch, sm, "_excess_pass")
    law = sm._excess_gas({"U": U, "Umf": Umf, "fluctuation_ratio": ratio})
    assert len(calls) == 1
    ref = _formula(U, Umf, ratio)
    assert law.family == "maxwellian" and law.theta.shape == ref.shape
    assert law.theta.tobytes() == ref.tobytes()


def test_excess_gas_small_inputs_take_the_ufunc(monkeypatch):
    U, Umf, ratio = _excess_inputs(shape=(2, 3, 4))  # below a map's size
    calls = _counted(monkeypatch, sm, "_excess_pass")
    law = sm._excess_gas({"U": U, "Umf": Umf, "fluctuation_ratio": ratio})
    assert not calls
    assert law.theta.tobytes() == _formula(U, Umf, ratio).tobytes()


@pytest.mark.parametrize("bad", [0.0, -1e-3])
def test_excess_gas_pass_refusal_names_the_first_value(monkeypatch, bad):
    """An element where U does not exceed U_mf: the plain path's error, naming the first
    such U in C order (the pass counts it; the numbers of the others do not matter)."""
    U, Umf, ratio = _excess_inputs()
    U[3, 7, 9] = Umf[3, 7, 0] + bad
    U[4, 0, 0] = Umf[4, 0, 0] - 0.01  # a later one
    calls = _counted(monkeypatch, sm, "_excess_pass")
    with pytest.raises(ValueError, match=rf"U = {U[3, 7, 9]:g} m/s does not exceed U_mf"):
        sm._excess_gas({"U": U, "Umf": Umf, "fluctuation_ratio": ratio})
    assert len(calls) == 1


def _resolved(n_T=6, n_h0=30, n_U=40):
    vals = {**Scene(liquid="water", T=298.15, d_i=300e-6).values(),
            "T": np.linspace(283.15, 363.15, n_T).reshape(-1, 1, 1),
            "h0": np.geomspace(1e-6, 30e-6, n_h0).reshape(1, -1, 1),
            "U_Umf": np.linspace(1.2, 8.0, n_U)}
    return vals, Resolved(vals)


@pytest.mark.parametrize("layout", ["C", "strided"])
def test_U_into_a_map_block_in_one_pass(monkeypatch, layout):
    vals, r = _resolved()
    ref = np.multiply(r.num("U_Umf"), r.Umf)  # numpy's product, as elsewhere
    shape = ref.shape
    if layout == "C":
        target = np.full(shape, -1.0)
    else:  # a block of a larger result, not contiguous
        target = np.full((shape[0] + 2, shape[1], shape[2] * 2), -1.0)[1:-1, :, 1::2]
    calls = _counted(monkeypatch, scene_mod, "_product_pass")
    r.U_into(target)
    assert len(calls) == 1
    assert r.U is target
    assert np.ascontiguousarray(target).tobytes() == ref.tobytes()


def test_a_map_launches_both_passes(monkeypatch):
    """Every block of a map with the default excess-gas speeds takes both passes."""
    product = _counted(monkeypatch, scene_mod, "_product_pass")
    excess = _counted(monkeypatch, sm, "_excess_pass")
    sc = Scene(liquid="water", T=298.15, d_i=300e-6)
    axes = dict(T=np.linspace(283.15, 363.15, 4), h0=np.geomspace(1e-6, 30e-6, 40),
                U_Umf=np.linspace(1.2, 8.0, 60))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sweep(sc, chunks=dict(T=2), progress=False, **axes)
    assert len(product) == 2 and len(excess) == 2
    U = ds["U"].transpose("T", "h0", "U_Umf").values
    Umf = ds["Umf"].transpose("T", "h0").values[:, :, None]
    assert U.tobytes() == np.multiply(axes["U_Umf"], Umf).tobytes()


@pytest.mark.parametrize("given", [False, True])
def test_agglomerated_of_many_collisions_in_one_pass(monkeypatch, given):
    """``agglomerated`` of a large collide: one compiled pass, numpy's ``e_w == 0`` bit for
    bit (NaN and -0.0 included), into the caller's array where one is given."""
    import agglomtool.api as api

    calls = _counted(monkeypatch, api, "_agglomerated_pass")
    e_w = np.random.default_rng(2).uniform(0.0, 1.0, 5000)
    e_w[::3] = 0.0
    e_w[1::7] = -0.0
    e_w[2::11] = np.nan
    out = np.ones(5000, dtype=bool) if given else None
    got = api._agglomerated(e_w.reshape(50, 100), None if out is None else out.reshape(50, 100))
    assert len(calls) == 1
    assert got.dtype == np.bool_ and got.shape == (50, 100)
    assert got.tobytes() == np.equal(e_w, 0.0).tobytes()
    if given:
        assert np.shares_memory(got, out)
    small = api._agglomerated(e_w[:10])  # a few collisions: numpy's comparison itself
    assert len(calls) == 1 and small.tobytes() == np.equal(e_w[:10], 0.0).tobytes()
    strided = np.ones(10000, dtype=bool)[::2]  # not contiguous: numpy's, into it
    got = api._agglomerated(e_w, strided)
    assert len(calls) == 1 and got is strided
    assert strided.tobytes() == np.equal(e_w, 0.0).tobytes()


def test_collide_agglomerated_is_e_w_zero(monkeypatch):
    import agglomtool as at
    import agglomtool.api as api

    calls = _counted(monkeypatch, api, "_agglomerated_pass")
    rng = np.random.default_rng(4)
    n = 6000
    p = at.Particle(d=rng.uniform(200e-6, 600e-6, n), rho=2650.0,
                    h0=rng.uniform(0.5e-6, 40e-6, n), ha=0.5e-6)
    res = at.collide(p, p, liquid=at.Liquid(mu=1e-3, gamma=0.072, rho=1000.0),
                     gas=at.Gas(mu=18.48e-6, rho=1.168), u0=rng.uniform(0.01, 2.0, n),
                     details=False)
    assert len(calls) == 1
    assert 0 < res.agglomerated.sum() < n  # both outcomes among them
    assert res.agglomerated.tobytes() == (res.e_w == 0.0).tobytes()
