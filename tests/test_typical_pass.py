"""A map's typical speed, margin and St: one compiled pass over each block, written into
the map's result (agglomtool.scene._typical_pass), equal bit for bit to the numpy passes
that compute them elsewhere (agglomtool.scene.evaluate of the same points, no map)."""

import warnings

import numpy as np
import pytest
from _map_laws import LAWS

import agglomtool.scene as scene_mod
from agglomtool.maps import sweep
from agglomtool.scene import Scene, evaluate

WATER = Scene()
SLAG = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
BASE = {"water": (WATER, dict(T=np.linspace(283.15, 363.15, 4), h0=np.geomspace(1e-6, 30e-6, 5))),
        "slag": (SLAG, dict(T=np.linspace(900.0, 1300.0, 4), h0=np.geomspace(0.12e-6, 2e-6, 5)))}
OUTPUTS = ("u_typical", "margin", "St")


def _reference(sc: Scene, axes: dict) -> dict:
    """The outputs of ``evaluate`` (numpy passes, no map result to write into) at the
    grid's points, broadcast over the grid's axes in their order."""
    names = list(axes)
    values = dict(sc.values())
    for d, name in enumerate(names):
        shape = [1] * len(names)
        shape[d] = len(axes[name])
        values[name] = np.asarray(axes[name], dtype=float).reshape(shape)
    grid_shape = tuple(len(axes[n]) for n in names)
    out = evaluate(values)
    return {k: np.broadcast_to(out[k], grid_shape) for k in OUTPUTS}


@pytest.mark.parametrize("law", list(LAWS))
@pytest.mark.parametrize("material", list(BASE))
def test_map_equals_numpy_passes_bitwise(material, law, monkeypatch):
    scene, base = BASE[material]
    fields, axis = LAWS[law]
    sc = Scene(**{**scene.values(), **fields})
    axes = {**base, **axis}
    launches = []
    real = scene_mod._typical_pass

    def counted(*args):
        launches.append(args[1])  # median_of
        return real(*args)

    monkeypatch.setattr(scene_mod, "_typical_pass", counted)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sweep(sc, chunks=37, **axes)  # several blocks, split along the outer axes
        ref = _reference(sc, axes)
    assert len(launches) > 1  # every block in one pass
    if law == "excess-gas":  # theta varies with every axis: the median computed in the pass
        assert any(launches)
    for k in OUTPUTS:
        got = ds[k].transpose(*axes).values
        assert got.dtype == np.float64, k
        assert np.array_equal(got, ref[k], equal_nan=True), k
        assert got.tobytes() == np.ascontiguousarray(ref[k]).tobytes(), k


def test_no_sticking_speed_margin_zero_and_below_umf_nan():
    """``u0* = inf`` (no collision sticks) gives a margin of 0, as the numpy pass; a point
    below U_mf (speed_flag) has NaN speed outputs, as before."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sweep(WATER, T=np.linspace(290.0, 350.0, 3), h0=np.array([1e-9, 1e-6, 30e-6]),
                   U=np.array([0.001, 0.2, 1.0]))
    inf = np.isinf(ds.u_star.broadcast_like(ds.margin)).values
    flag = (ds.speed_flag != 0).values
    assert flag.any() and (~flag).any()
    assert np.all(np.isnan(ds.margin.values[flag]))
    assert np.all(np.isnan(ds.St.values[flag]))
    ok = ~flag
    assert np.all(ds.margin.values[ok & inf] == 0.0)
    assert np.all(np.isfinite(ds.St.values[ok]))
