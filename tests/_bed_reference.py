"""The bed's pair matrices by the per-block path that the batched pass replaced: one
Scene-level evaluation (``u0*``, then the propensity) per pair of components, classes as
array axes; blocks of two different components computed once and the swapped block filled
by the symmetry ``(a, b, s) = (b, a, -s)``, blocks of one component computed in both
orders. Kept here as the reference the batched pass is tested against."""

from __future__ import annotations

import numpy as np

from agglomtool.bed.propensity import _classes, direction_nodes
from agglomtool.scene import Resolved, critical_outputs, sticking_probability


def reference_pairs(scene, comps, directions, *, nodes=16, Umf, points=None,
                    h0_c=None):
    """``u_star`` and the sticking probability ``P`` (G, K, K, D) of the points ``points``
    (fields -> arrays of G values; none: the scene's one point) with the bed's ``Umf``
    (G,) and the components' coatings ``h0_c`` (G, C)."""
    base = scene.values()
    points = points or {}
    Umf = np.atleast_1d(np.asarray(Umf, dtype=float))
    G = Umf.size
    cidx, d = _classes(comps)[:2]
    K = d.size
    beta = direction_nodes(directions)[1]
    D = beta.size
    if h0_c is None:
        h0_c = np.array([[base["h0"] if c.h0 is None else c.h0 for c in comps]] * G)
    pts = {k: np.asarray(v, dtype=float).reshape(G, 1, 1, 1) for k, v in points.items()}
    u_star = np.empty((G, K, K, D))
    prob = np.empty((G, K, K, D))
    for a, ca in enumerate(comps):
        ia = np.flatnonzero(cidx == a)
        for b in range(a, len(comps)):
            cb = comps[b]
            ib = np.flatnonzero(cidx == b)
            vals = {**base, **pts, "solid_i": ca.name, "solid_j": cb.name,
                    "d_i": d[ia].reshape(1, -1, 1, 1), "d_j": d[ib].reshape(1, 1, -1, 1),
                    "h0": h0_c[:, a].reshape(G, 1, 1, 1),
                    "h0_j": h0_c[:, b].reshape(G, 1, 1, 1),
                    "ha_i": ca.ha, "ha_j": cb.ha, "beta_deg": beta.reshape(1, 1, 1, D)}
            r = Resolved(vals, Umf=Umf.reshape(G, 1, 1, 1))
            us = critical_outputs(r)["u_star"]
            shape = (G, ia.size, ib.size, D)
            us = np.broadcast_to(us, shape)
            p = sticking_probability(r.speeds, us, r.collide, nodes=nodes, shape=shape,
                                     collide_on=r.collide_on, pair=r.sticking_pair)
            u_star[:, ia[:, None], ib[None, :], :] = us
            prob[:, ia[:, None], ib[None, :], :] = p
            if b != a:
                for m in (u_star, prob):
                    m[:, ib[:, None], ia[None, :], :] = np.swapaxes(
                        m[:, ia[:, None], ib[None, :], :], 1, 2)[..., ::-1]
    return u_star, prob
