"""A bed point as one batch: every distinct pair of classes and direction in one
kernel pass, the pair symmetry ``(a, b, s) = (b, a, -s)`` used within components too, no
collision at the typical speed, and the outputs of the per-block path kept."""

import warnings

import numpy as np
import pytest
from _bed_reference import reference_pairs

import agglomtool as at
from agglomtool import materials
from agglomtool import scene as scene_mod
from agglomtool.bed import Component, bed_propensity, bed_sweep

WATER = dict(T=298.15, liquid="water", h0=5e-6, U_Umf=2.0)
SLAG = dict(T=1073.15, liquid="hypothetical-slag", h0=0.15e-6, U_Umf=2.0)
SPEEDS = {"excess-gas": {}, "lognormal": dict(u0=0.05, sigma_ln=0.9),
          "fixed": dict(u0=0.1), "maxwellian": dict(granular_temperature=4e-3),
          "collisional-balance": {}}


def _comps():
    return [Component("silica-sand", 0.5, d50=700e-6, gsd=1.5, classes=4),
            Component("ilmenite", 0.3, d50=300e-6, gsd=1.3, classes=3, ha=0.2e-6),
            Component("olivine", 0.2, d=[350e-6, 500e-6], h0=2e-6)]


def _computed(K, D):
    """The (i, j, k) the batch computes: i < j in every direction, i = j in the first half
    of the directions (the rest are their mirrors)."""
    i, j, k = np.meshgrid(np.arange(K), np.arange(K), np.arange(D), indexing="ij")
    return (i < j) | ((i == j) & (k <= D - 1 - k))


def _pairs(cond, mode="relative", speed="excess-gas", directions=5):
    scene = at.Scene(**cond, mode=mode, speed=speed, **SPEEDS[speed])
    comps = _comps()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        ds = bed_propensity(scene, comps, directions=directions)
        ref = reference_pairs(scene, comps, directions, Umf=float(ds.Umf),
                              h0_c=ds.h0_component.values[None, :])
    return ds, ref


def test_the_kernel_is_symmetric_under_swap_and_reversed_direction():
    """What the batch relies on, checked on the code: the pair (j, i) at -beta is the pair
    (i, j) at beta. Measured: not bitwise (the arithmetic runs in another order; 246 of
    1152 u0* of a 12-class sand bed in water differ, by at most 1.1e-15 relative), so the
    test holds u0*, e_w and the outcome to 1e-12 relative."""
    rng = np.random.default_rng(7)
    n = 400
    d_i, d_j = rng.uniform(150e-6, 1500e-6, (2, n))
    h_i, h_j = rng.uniform(0.5e-6, 20e-6, (2, n))
    beta = rng.uniform(-90.0, 90.0, n)
    sand, ilm = materials.solid("silica-sand"), materials.solid("ilmenite")
    a = at.Particle(d=d_i, rho=sand.density, h0=h_i, ha=sand.asperity_height)
    b = at.Particle(d=d_j, rho=ilm.density, h0=h_j, ha=ilm.asperity_height)
    for cond, mode in ((WATER, "relative"), (WATER, "paper"), (SLAG, "relative"),
                       (WATER, "auto")):
        r = scene_mod.Resolved(at.Scene(**cond).values())
        kw = dict(liquid=r.liquid, gas=r.gas, bed=at.Bed(U=0.2), e=0.8, mode=mode)
        us1 = at.critical_impact_speed(a, b, beta_deg=beta, **kw)
        us2 = at.critical_impact_speed(b, a, beta_deg=-beta, **kw)
        # speeds about each pair's u0*, where the outcome turns
        u0 = np.where(np.isfinite(us1) & (us1 > 0), us1, 0.1) * rng.uniform(0.5, 2.0, n)
        r1 = at.collide(a, b, u0=u0, beta_deg=beta, details=False, **kw)
        r2 = at.collide(b, a, u0=u0, beta_deg=-beta, details=False, **kw)
        np.testing.assert_allclose(us2, us1, rtol=1e-12)
        np.testing.assert_allclose(r2.e_w, r1.e_w, rtol=1e-12, atol=0.0)
        np.testing.assert_array_equal(r2.agglomerated, r1.agglomerated)
        fin = np.isfinite(us1) & (us1 > 0)
        assert fin.sum() > n // 4, mode  # the comparison is not all inf or 0
        assert 0 < r1.agglomerated.sum() < n, mode  # both outcomes occur


@pytest.mark.parametrize("cond", [WATER, SLAG], ids=["water", "slag"])
@pytest.mark.parametrize("mode", ["relative", "paper"])
def test_batch_equals_the_per_block_path(cond, mode):
    """Bitwise where the batch computes the same collision as the per-block path; its
    mirrors within 1e-12 (the kernel's symmetry, above)."""
    ds, (u_ref, p_ref) = _pairs(cond, mode)
    K, D = ds.sizes["cls"], ds.sizes["direction"]
    same = _computed(K, D)
    for name, ref in (("u_star", u_ref[0]), ("sticking_probability", p_ref[0])):
        got = ds[name].values
        np.testing.assert_array_equal(got[same], ref[same], err_msg=name)
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-15, err_msg=name)
        # the batch's own matrix is exactly symmetric: mirrors are copies
        np.testing.assert_array_equal(got, np.transpose(got, (1, 0, 2))[:, :, ::-1])
    assert 0.0 < float(ds.propensity) < 1.0


@pytest.mark.parametrize("mode", ["auto", "stokes"])
def test_batch_of_the_vectorised_search_tiers(mode):
    """Tiers without a compiled u0* solver bisect the whole batch until every element has
    converged, so an element may be narrowed further in a larger batch: u0* within the
    search's documented rtol (1e-6) of the per-block path, the propensity within what that
    moves (measured here: 4e-16 and 0)."""
    ds, (u_ref, p_ref) = _pairs(SLAG, mode, directions=4)
    got = ds.u_star.values
    np.testing.assert_array_equal(np.isinf(got), np.isinf(u_ref[0]))
    fin = np.isfinite(got)
    assert fin.any()
    np.testing.assert_allclose(got[fin], u_ref[0][fin], rtol=1e-6)
    np.testing.assert_allclose(ds.sticking_probability.values, p_ref[0], rtol=0,
                               atol=1e-6)


@pytest.mark.parametrize("speed", ["lognormal", "fixed", "maxwellian"])
def test_batch_equals_the_per_block_path_for_every_speed_law(speed):
    ds, (u_ref, p_ref) = _pairs(WATER, speed=speed, directions=4)
    same = _computed(ds.sizes["cls"], 4)
    got = ds.sticking_probability.values
    np.testing.assert_array_equal(got[same], p_ref[0][same])
    np.testing.assert_allclose(got, p_ref[0], rtol=1e-12, atol=1e-15)
    assert got.min() < got.max()  # not one value everywhere


def test_a_speed_law_of_the_particle_gets_one_temperature_and_mirrors():
    """A speed law read from the particle's size and density (collisional-balance) is
    evaluated once per point for the bed's mean particle (tests/test_bed_speed_models.py),
    so every pair shares it and the batch mirrors as for the other laws: u0* (which no speed
    law enters) within 1e-12 of the per-block path, and both matrices exactly symmetric."""
    ds, (u_ref, _) = _pairs(WATER, speed="collisional-balance", directions=4)
    np.testing.assert_allclose(ds.u_star.values, u_ref[0], rtol=1e-12, atol=1e-15)
    for name in ("u_star", "sticking_probability"):
        got = ds[name].values
        np.testing.assert_array_equal(got, np.transpose(got, (1, 0, 2))[:, :, ::-1])
    assert 0.0 < float(ds.propensity) < 1.0


def test_one_kernel_pass_per_point_and_no_typical_collide(monkeypatch):
    """One u0* call over the distinct pairs (K (K - 1) / 2 D + K ceil(D / 2) of them), and
    no collision beyond the propensity's own nodes (the per-block path made one u0* call
    per pair of components and a collision at the typical speed in each)."""
    calls = {"u_star": [], "collide": []}
    real_u, real_c = scene_mod.critical_impact_speed, scene_mod.collide

    def u_star(*a, **k):
        out = real_u(*a, **k)
        calls["u_star"].append(np.size(out))
        return out

    def collide(*a, **k):
        out = real_c(*a, **k)
        calls["collide"].append(np.size(out.e_w))
        return out

    monkeypatch.setattr(scene_mod, "critical_impact_speed", u_star)
    monkeypatch.setattr(scene_mod, "collide", collide)
    comps, D, nodes = _comps(), 5, 6
    ds = bed_propensity(at.Scene(**WATER), comps, directions=D, nodes=nodes)
    K = ds.sizes["cls"]
    distinct = K * (K - 1) // 2 * D + K * ((D + 1) // 2)
    assert calls["u_star"] == [distinct]
    assert len(calls["collide"]) <= nodes
    assert all(n <= distinct for n in calls["collide"])
    # a sweep: one pass per block of points, the points side by side
    calls["u_star"].clear()
    sw = bed_sweep(at.Scene(**WATER), comps, directions=D, nodes=nodes, U_Umf=[1.5, 2, 3])
    assert calls["u_star"] == [3 * distinct]
    assert float(sw.propensity.sel(U_Umf=2.0)) == pytest.approx(float(ds.propensity),
                                                                rel=1e-12)


def test_sweep_equals_the_per_block_path():
    scene = at.Scene(**WATER)
    comps = _comps()
    grid = dict(T=np.array([298.15, 328.15]), U_Umf=np.array([1.5, 2.5]))
    ds = bed_sweep(scene, comps, directions=3, matrix=True, **grid)
    T, U_Umf = (m.reshape(-1) for m in np.meshgrid(grid["T"], grid["U_Umf"], indexing="ij"))
    ref_u, ref_p = reference_pairs(scene, comps, 3, Umf=ds.Umf.values.reshape(-1),
                                   points=dict(T=T, U_Umf=U_Umf))
    w = np.polynomial.legendre.leggauss(3)[1] / 2.0
    E = np.einsum("gabk,k->gab", ref_p, w).reshape(2, 2, *ref_p.shape[1:3])
    np.testing.assert_allclose(ds.efficiency.values, E, rtol=1e-12, atol=1e-15)
    assert len({round(float(x), 9) for x in ds.propensity.values.ravel()}) == 4


def test_materials_looked_up_per_component_not_per_class(monkeypatch):
    """The database is read once per component and call, whatever the number of classes
    (the class table looked each class's solid up three times)."""
    counts = []
    real = materials.solid

    def solid(*a, **k):
        counts[-1] += 1
        return real(*a, **k)

    scene = at.Scene(**WATER)
    for classes in (2, 12):
        comps = [Component("silica-sand", 0.7, d50=700e-6, gsd=1.5, classes=classes),
                 Component("ilmenite", 0.3, d50=300e-6, gsd=1.3, classes=classes)]
        monkeypatch.setattr(materials, "solid", solid)
        counts.append(0)
        bed_propensity(scene, comps, directions=2)
        monkeypatch.setattr(materials, "solid", real)
    assert counts[0] == counts[1]


def test_properties_evaluated_once_whatever_the_components(monkeypatch):
    """The gas (and liquid) properties of a bed point are found a fixed number of times, not
    once per pair of components (the sources attribute evaluated a Resolved per pair); the
    sources are still every pair's."""
    calls = []
    real = scene_mod.gas_properties

    def gas_properties(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(scene_mod, "gas_properties", gas_properties)
    scene = at.Scene(**WATER)
    counts = []
    for comps in ([Component("silica-sand", 1.0, d50=700e-6)], _comps()):
        calls.clear()
        ds = bed_propensity(scene, comps, directions=2)
        counts.append(len(calls))
    assert counts[0] == counts[1]
    import json

    expected = {}
    for a in comps:
        for b in comps:
            vals = {**scene.values(), "solid_i": a.name, "solid_j": b.name}
            expected.update({k: " ".join(t.split())
                             for k, t in scene_mod.Resolved(vals).sources.items()})
    assert json.loads(ds.attrs["material_sources"]) == expected
    assert list(json.loads(ds.attrs["material_sources"])) == list(expected)


def test_direction_nodes_are_the_callers_own():
    """The nodes are computed once per count; a caller that changes its arrays changes no
    later call's."""
    from agglomtool.bed.propensity import direction_nodes

    s, beta, w = direction_nodes(4)
    ref_s, ref_w = np.polynomial.legendre.leggauss(4)
    np.testing.assert_array_equal(s, ref_s)
    np.testing.assert_array_equal(w, ref_w / 2.0)
    np.testing.assert_array_equal(beta, np.degrees(np.arcsin(ref_s)))
    s[:] = 0.0
    w[:] = 0.0
    np.testing.assert_array_equal(direction_nodes(4)[0], ref_s)
    np.testing.assert_array_equal(direction_nodes(4)[2], ref_w / 2.0)


def test_a_point_larger_than_a_block_is_cut_into_passes(monkeypatch):
    """A bed whose distinct collisions exceed the block size (many components of many
    classes) takes several passes per point, each at most a block, so memory stays bounded;
    the values are those of one pass, bitwise (each collision is computed alone)."""
    from agglomtool.bed import propensity

    scene = at.Scene(**WATER)
    comps = _comps()
    whole = bed_propensity(scene, comps, directions=3)
    sweep = bed_sweep(scene, comps, directions=3, matrix=True, U_Umf=[1.5, 2.0])
    sizes = []
    real = scene_mod.critical_impact_speed

    def u_star(*a, **k):
        out = real(*a, **k)
        sizes.append(np.size(out))
        return out

    monkeypatch.setattr(scene_mod, "critical_impact_speed", u_star)
    monkeypatch.setattr(propensity, "_BLOCK_COLLISIONS", 50)
    cut = bed_propensity(scene, comps, directions=3)
    K = whole.sizes["cls"]
    distinct = K * (K - 1) // 2 * 3 + K * 2
    assert max(sizes) <= 50 and sum(sizes) == distinct and len(sizes) == -(-distinct // 50)
    for name in ("u_star", "sticking_probability", "efficiency", "propensity"):
        np.testing.assert_array_equal(cut[name].values, whole[name].values, err_msg=name)
    cut_sweep = bed_sweep(scene, comps, directions=3, matrix=True, U_Umf=[1.5, 2.0])
    np.testing.assert_array_equal(cut_sweep.efficiency.values, sweep.efficiency.values)
    np.testing.assert_array_equal(cut_sweep.propensity.values, sweep.propensity.values)
