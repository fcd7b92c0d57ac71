"""Agglomeration propensity of a bed: a mixture of solids and sizes, not one pair.

Weighting
---------
Classes ``a`` (a component's size class) have number densities ``n_a`` proportional to
``w_a / (rho_a d_a**3)`` (mass fraction in the bed, solid density, solid diameter). By the
kinetic theory of granular mixtures the collision frequency per unit volume between classes
``a`` and ``b`` is::

    Z_ab = n_a n_b pi d_ab**2 g0_ab sqrt(16 Theta / pi)     (halved for a = b)

with ``d_ab = (D_a + D_b) / 2`` (``D`` the wet diameter: the films touch first) and ``Theta``
the granular temperature [m2/s2], the variance of one velocity component (Gidaspow (1994),
Multiphase Flow and Fluidization, Academic Press, ISBN 0-12-282470-9, ch. 9; Jenkins and
Mancini (1989), Phys. Fluids A 1:2050, doi:10.1063/1.857479, for binary mixtures of spheres).
Assumed: one granular temperature (velocity variance) shared by all classes, so the mean
relative speed ``sqrt(16 Theta / pi)`` and the distribution of impact speeds are the same for
every pair and cancel from the fractions; ``g0 = 1`` (no crowding correction: the radial
distribution function at contact would raise all rates in a dense bed, and a
size-dependent one would favour large pairs). The collision-rate weight of the ordered pair
``(a, b)`` is ``W_ab = n_a n_b (D_a + D_b)**2 / sum_cd n_c n_d (D_c + D_d)**2``: the
fraction of all collisions between ``a`` and ``b`` is ``W_ab + W_ba`` for ``a != b`` and
``W_aa`` for ``a = b``, so the sum over ordered pairs counts every collision once.

Directions: the axis ``i -> j`` of a collision has the isotropic distribution, so
``s = sin(beta)`` (``beta`` its elevation from the horizontal) is uniform on [-1, 1]. The
sticking probability ``P_ab(s)`` under the scene's speed distribution is averaged with
``directions`` Gauss-Legendre nodes in ``s`` (weights / 2). ``beta`` enters only through the
body forces' component along the axis, linear in ``s``, so ``P_ab(s)`` is smooth except
where a bridge outcome switches (a kink); 8 nodes integrate polynomials of degree 15
exactly, and on a 70 % sand (gsd 1.6) + 30 % ilmenite bed at the paper's water and slag
conditions they are within 0.03 % (water) and 1e-5 absolute (slag) of 32 nodes (2 nodes:
2 %). The nodes come in pairs ``+-s``, and ``(a, b)`` at ``beta`` is ``(b, a)`` at
``-beta``: with a speed distribution shared by every pair, each collision is computed once
(``a < b`` in every direction, ``a = b`` in half of them) and copied to its mirror, so
``E_ab = E_ba`` exactly. The kernel itself is symmetric to a few units in the last place
(its arithmetic runs in another order when the particles swap; the tests hold it to
1e-12). A speed law read from particle i's size or density (the bubble and
collisional-balance models) differs between the orders: there both orders of a component's
classes are computed and only the pairs of two components mirrored. All the distinct
collisions of a block of operating points go through one u0* pass and one propensity
pass (:func:`agglomtool.bed.speeds.sticking_probability`).
The coalescence efficiency ``E_ab = sum_k (w_k / 2) P_ab(s_k)``, and the bed's
propensity ``P_bed = sum_ab W_ab E_ab``: the fraction of all collisions that stick.

One bed, one gas velocity: ``U_mf`` is that of the mixture, by the scene's ``umf_method``
(Wen-Yu by default) with the Sauter mean wet diameter ``sum n D**3 / sum n D**2`` and the
mean wet particle density (total wet mass over total wet volume); for a one-component
monodisperse bed it is the scene's own ``U_mf``. Every pair then shares ``U``, the emulsion
velocity of the drag and the speed distribution.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import warnings

import numpy as np
import xarray as xr

from .. import materials
from .._fields import MAX_NODES
from .._validate import check_int, check_range, check_typed
from .._version import __version__
from ..inputs import Particle
from ..maps.meta import call_text, cf_units, global_attrs, provenance_attr
from ..pair import wet_mass
from ..plausibility import bed_findings, warn_findings
from ..properties import umf
from ..scene import (
    FIELD_META,
    NUMERIC_FIELDS,
    Resolved,
    Scene,
    assumed_inputs,
    critical_outputs,
    provenance,
    swept_without_effect,
)
from ..units import to_si_array
from .mixture import Component
from .speed_models import IMPACT_SPEED_MODELS, SPEED_FLAGS, NoImpactSpeedWarning
from .speeds import sticking_probability

__all__ = ["bed_propensity", "bed_sweep", "direction_nodes", "BED_GRID_FIELDS",
           "DEFAULT_DIRECTIONS"]

#: Gauss-Legendre nodes in sin(beta) of the direction average (see the module docstring).
DEFAULT_DIRECTIONS = 8

#: Scene fields a bed takes from its components (not sweepable in a bed sweep).
_OWN = ("d_i", "d_j", "h0_j", "ha_i", "ha_j", "beta_deg")
#: Fields a bed sweep may take: the scene's numbers (h0: the coating of every component
#: that follows the scene) and ``fraction`` (the mass fraction of the component ``mix``).
BED_GRID_FIELDS = tuple(f for f in NUMERIC_FIELDS if f not in _OWN) + ("fraction",)

#: Distinct collisions of a block of operating points evaluated together (at least one
#: point): one u0* pass and one propensity pass each; memory about 30 float arrays of this
#: size, plus the block's (points, classes, classes, directions) matrix.
_BLOCK_COLLISIONS = 2**17


def direction_nodes(n: int = DEFAULT_DIRECTIONS):
    """``(sin_beta, beta_deg, weight)``: Gauss-Legendre nodes of the isotropic direction
    average, weights summing to 1."""
    if not isinstance(n, int | np.integer) or not 1 <= n <= 64:
        raise ValueError(f"directions = {n!r} is outside the allowed range 1-64 (an integer)")
    return tuple(a.copy() for a in _direction_nodes(int(n)))


@functools.lru_cache(maxsize=64)
def _direction_nodes(n: int):
    """:func:`direction_nodes` computed once per ``n`` (numpy's leggauss solves an
    eigenvalue problem each call: about 0.1 ms, 1 % of a small bed point)."""
    s, w = np.polynomial.legendre.leggauss(n)
    return s, np.degrees(np.arcsin(s)), w / 2.0


def _check_components(components) -> tuple[Component, ...]:
    if isinstance(components, Component):
        raise ValueError(f"components = {components!r} is one Component; allowed: a list of "
                         "them, e.g. [component] for a bed of one")
    try:
        comps = tuple(components)
    except TypeError:
        comps = ()
    if not comps or not all(isinstance(c, Component) for c in comps):
        raise ValueError(f"components = {components!r} must be a non-empty list of "
                         "agglomtool.bed.Component")
    total = math.fsum(float(c.fraction) for c in comps)
    if abs(total - 1.0) > 1e-9:
        raise ValueError(f"fraction: the components' mass fractions "
                         f"{[c.fraction for c in comps]} sum to {total:.12g}; allowed: a sum "
                         "of 1 within 1e-9")
    for k, c in enumerate(comps):
        for m in range(k):
            if all(getattr(c, f.name) == getattr(comps[m], f.name)
                   for f in dataclasses.fields(c) if f.name != "fraction"):
                raise ValueError(f"components: component {k} repeats component {m} "
                                 f"({c.name}, the same sizes and coating); allowed: each "
                                 "once, with the sum of their fractions")
    return comps


def _classes(comps):
    """Per class (flattened over components): component index, diameter, mass fraction
    within its component, edges."""
    rows = [c.size_classes() for c in comps]
    idx = np.concatenate([np.full(len(r[0]), k) for k, r in enumerate(rows)])
    d, w, lo, hi = (np.concatenate([r[m] for r in rows]) for m in range(4))
    return idx, d, w, lo, hi


def _grid_arrays(grid: dict) -> dict:
    out = {}
    for name, values in grid.items():
        if name not in BED_GRID_FIELDS:
            raise ValueError(f"{name!r} cannot be swept in a bed; allowed: "
                             f"{', '.join(BED_GRID_FIELDS)}")
        if name == "fraction":
            arr = np.atleast_1d(check_range("fraction", values, 0.0, 1.0))
        else:
            unit, long_name = FIELD_META[name]
            arr = np.atleast_1d(check_typed(name, values, to_si_array(name, values, unit,
                                                                      long_name)))
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError(f"grid {name} = {values!r} must be a non-empty 1-D list")
        uniq, counts = np.unique(arr, return_counts=True)
        if uniq.size != arr.size:
            raise ValueError(f"grid {name} = {values!r} repeats the value "
                             f"{float(uniq[counts > 1][0])!r}; allowed: unique values")
        out[name] = arr
    return out


def _mix_index(comps, mix) -> int:
    if isinstance(mix, int | np.integer) and 0 <= mix < len(comps):
        return int(mix)
    names = [c.name for c in comps]
    if isinstance(mix, str):
        from .. import materials

        try:
            key = materials.solid(mix).name
        except ValueError:
            key = None
        if names.count(key) > 1:  # one solid in several components (a bimodal sand)
            which = [k for k, n in enumerate(names) if n == key]
            raise ValueError(f"mix = {mix!r} names {len(which)} components "
                             f"({', '.join(map(str, which))}) of the same solid; give the "
                             f"index of the one the fraction sets, e.g. mix = {which[0]}")
        if key in names:
            return names.index(key)
    raise ValueError(f"mix = {mix!r} is not a component of the bed; allowed: an index "
                     f"0-{len(comps) - 1} or one of {names}")


def check_fraction_axis(comps) -> None:
    """A ``fraction`` axis sets one component's mass fraction against the others': a bed
    of one component has none (its fraction is 1 whatever the axis says)."""
    if len(comps) < 2:
        raise ValueError(f"fraction: the bed has one component ({comps[0].name}), whose "
                         "mass fraction is 1 whatever the axis says; a fraction axis needs "
                         "two or more components")


def _fractions(comps, frac, mix):
    """Component mass fractions (G, C) with component ``mix`` at ``frac`` (G,) and the others
    scaled in proportion."""
    base = np.array([c.fraction for c in comps], dtype=float)
    if frac is None:
        return base[None, :]
    check_fraction_axis(comps)
    rest = 1.0 - base[mix]
    if rest <= 0.0 and len(comps) > 1:
        raise ValueError(f"mix = {mix!r} holds the whole bed (fraction 1): the other "
                         "components have no proportions to scale; give them fractions")
    scale = (1.0 - frac)[:, None] / rest if rest > 0 else np.zeros((frac.size, 1))
    out = base[None, :] * scale
    out[:, mix] = frac
    return out


def _pair_table(K: int, cidx, D: int, symmetric: bool):
    """The (class i, class j, direction k) the batch computes and where each result goes.

    ``(i, j, k)`` and ``(j, i, D - 1 - k)`` are one collision seen from either particle (the
    nodes are +-s pairs), so with a speed law shared by every pair (``symmetric``) the
    batch takes ``i < j`` in every direction and ``i = j`` in the first half of the
    directions, and fills both places: ``K (K - 1) / 2 D + K ceil(D / 2)`` collisions.
    A law read from particle i (its size or density) is not symmetric: there every order
    within a component is computed, and only the blocks of two components are mirrored.
    Returns the index arrays ``i, j, k`` and the flat targets ``first, mirror`` in a
    ``(K, K, D)`` matrix."""
    i, j, k = (x.reshape(-1) for x in np.meshgrid(np.arange(K), np.arange(K), np.arange(D),
                                                   indexing="ij"))
    if symmetric:
        keep = (i < j) | ((i == j) & (k <= D - 1 - k))
    else:
        keep = (cidx[i] < cidx[j]) | (cidx[i] == cidx[j])
    i, j, k = i[keep], j[keep], k[keep]
    first = (i * K + j) * D + k
    mirror = (j * K + i) * D + (D - 1 - k)
    if not symmetric:  # mirrors only across components
        across = cidx[i] != cidx[j]
        mirror = np.where(across, mirror, first)
    return i, j, k, first, mirror


def _symmetric_law(base: dict) -> bool:
    """True where the impact-speed law is the same for every pair of the bed (it reads no
    property of particle i)."""
    model = IMPACT_SPEED_MODELS.get(base["speed"])
    return model is None or not {"d_p", "rho_p"} & set(model.needs)


class _PairBatch(Resolved):
    """A :class:`~agglomtool.scene.Resolved` whose two particles are arrays over the pairs of
    a bed (solids given by their database values, not by name), over operating points that
    share the properties already found for the bed (``liquid``, ``gas``)."""

    def __init__(self, values: dict, *, Umf, particles, e, rho_p, liquid, gas_arrays,
                 gas_source):
        super().__init__(values, Umf=Umf)
        self.__dict__.update(particles=particles, e=e, liquid=liquid,
                             _gas_arrays=gas_arrays)
        self._gas_source = gas_source
        self._rho_p = rho_p

    def _speed_inputs(self) -> dict:
        get = super()._speed_inputs()
        get["rho_p"] = lambda: self._rho_p
        return get


def _one_snapshot(what: str):
    """Decorator: the function with every materials look-up answered from one snapshot of
    the files, read once per call (:func:`agglomtool.materials.pinned`): no file is looked
    at per look-up, and a bed never mixes two versions of a file. A call that took the
    snapshot says at its end which files changed while it ran
    (:class:`~agglomtool.materials.MaterialsChangedWarning`, as a map does), ``what``
    naming the run."""

    def decorate(func):
        @functools.wraps(func)
        def pinned(*args, **kwargs):
            from .. import materials

            outermost = materials.current() is None
            with materials.pinned() as snap:
                out = func(*args, **kwargs)
            if outermost:
                materials.warn_if_changed(snap, what)
            return out

        return pinned

    return decorate


def _evaluate(scene: Scene, comps, points: dict, frac_cg, nodes: int, directions: int,
              progress: bool = False, pairs: bool = True, partial: bool = False):
    """The bed at ``G`` operating points: the coalescence efficiency ``E`` (G, K, K), the
    rate weights ``W`` (G, K, K), ``U_mf``, ``U`` (G,) and the class table; with ``pairs``
    also ``u_star`` and the sticking probability ``prob`` per direction (G, K, K, D).
    ``progress``: a progress bar (tqdm) of the operating points on stderr.

    Every distinct collision of a block of points (:func:`_pair_table`) goes through one
    u0* pass and one :func:`~agglomtool.bed.speeds.sticking_probability` call; each element
    is the arithmetic of a Scene evaluation of that pair (the same inputs, broadcast).

    ``partial`` (a map of the bed): where the impact-speed model has no answer at a point,
    its sticking probabilities are NaN and ``speed_flag`` (G,) says why
    (:mod:`agglomtool.maps.speed_flag`); else (one operating point) the model's
    ``ValueError`` is raised."""
    from ..maps.progress import SweepBar
    from ..maps.speed_flag import _preset_speeds

    base = scene.values()
    G = frac_cg.shape[0]
    cidx, d, w_in, lo, hi = _classes(comps)
    K = d.size
    s, beta, wdir = direction_nodes(directions)
    D = s.size
    solids = [materials.solid(c.solid) for c in comps]  # once per component and call
    col = {k: np.asarray(v, dtype=float).reshape(G) for k, v in points.items()}
    h0_scene = col.get("h0", np.full(G, float(base["h0"])))
    h0_c = np.stack([h0_scene if c.h0 is None else np.full(G, float(c.h0)) for c in comps],
                    axis=1)                                          # (G, C)
    h0_k = h0_c[:, cidx]                                             # (G, K)
    rho_c = np.array([m.density for m in solids])
    rho_s = rho_c[cidx]                                              # (K,)
    w_bed = frac_cg[:, cidx] * w_in[None, :]                         # (G, K)
    n = w_bed / (rho_s * d**3)                                       # number density, scaled
    # One U_mf for the bed: Sauter mean wet diameter, mean wet density.
    fvals = {**base, **{k: v for k, v in col.items() if k in base}}
    r0 = Resolved(fvals)
    rho_l = np.broadcast_to(r0.liquid.rho, (G,))[:, None]
    D_wet = d[None, :] + 2.0 * h0_k
    m_wet = wet_mass(Particle(d=d[None, :], rho=rho_s[None, :], h0=h0_k, ha=0.0), rho_l)
    vol = (math.pi / 6.0) * D_wet**3
    d32 = (n * D_wet**3).sum(1) / (n * D_wet**2).sum(1)
    rho_mean = (n * m_wet).sum(1) / (n * vol).sum(1)
    Umf = np.broadcast_to(umf(d32, rho_mean, r0.gas, base["umf_method"]), (G,))
    # Collision-rate weights over ordered pairs of classes.
    W = n[:, :, None] * n[:, None, :] * (D_wet[:, :, None] + D_wet[:, None, :]) ** 2
    W = W / W.sum(axis=(1, 2), keepdims=True)
    # one granular temperature for every pair where the model reads the particle
    speed_flag = np.zeros(G, dtype=np.int8)
    speed_fields = _bed_speed(fvals, r0, comps, cidx, n, d, rho_s, W, Umf,
                              speed_flag if partial else None)
    # The distinct collisions and each class's database values.
    ii, jj, kk, first, mirror = _pair_table(K, cidx, D,
                                                  bool(speed_fields) or _symmetric_law(base))
    M = ii.size
    ha_c = np.array([m.asperity_height if c.ha is None else float(c.ha)
                     for c, m in zip(comps, solids, strict=True)])
    e_c = np.array([m.restitution_dry for m in solids])
    ci, cj = cidx[ii], cidx[jj]
    e_pair = 0.5 * (e_c[ci] + e_c[cj]) if base["e"] is None else r0.num("e")
    liq, (mu_g, rho_g) = r0.liquid, r0._gas_arrays

    def at_points(a, g):  # a value of the G points (or a scalar) for the points g, (gn, 1)
        a = np.asarray(a, dtype=float)
        return a if a.ndim == 0 else np.broadcast_to(a, (G,))[g][:, None]

    E = np.empty((G, K, K))
    if pairs:
        u_star = np.empty((G, K, K, D))
        prob = np.empty((G, K, K, D))
    U = np.empty(G)
    step = max(1, _BLOCK_COLLISIONS // M)  # points per block
    chunk = min(M, _BLOCK_COLLISIONS)  # collisions per pass (a point may take several)
    bar = SweepBar(G, -(-G // step), "bed", progress)
    for g0 in range(0, G, step):  # blocks of operating points, each one batch of collisions
        g = slice(g0, min(G, g0 + step))
        gn = g.stop - g.start
        pts = {k: v[g][:, None] for k, v in col.items() if k in base}
        pts.update({k: v[g][:, None] for k, v in speed_fields.items()})
        h0_c_g = h0_c[g]
        liquid = dataclasses.replace(
            liq, **{f: at_points(getattr(liq, f), g) for f in ("mu", "gamma", "rho",
                                                               "theta_deg")})
        pm = np.empty((gn, K * K * D))
        um = u_star[g].reshape(gn, -1) if pairs else None
        for m0 in range(0, M, chunk):  # one pass unless a point has more collisions
            m = slice(m0, min(M, m0 + chunk))
            i_, j_, c_i, c_j = ii[m], jj[m], ci[m], cj[m]
            p_i = Particle(d=d[i_], rho=rho_c[c_i], h0=h0_c_g[:, c_i], ha=ha_c[c_i])
            p_j = Particle(d=d[j_], rho=rho_c[c_j], h0=h0_c_g[:, c_j], ha=ha_c[c_j])
            vals = {**base, **pts, "solid_i": solids[0].name, "solid_j": solids[0].name,
                    "d_i": d[i_], "d_j": d[j_], "h0": p_i.h0, "h0_j": p_j.h0,
                    "ha_i": p_i.ha, "ha_j": p_j.ha, "beta_deg": beta[kk[m]]}
            e = pts.get("e", e_pair if np.ndim(e_pair) == 0 else e_pair[m])
            r = _PairBatch(vals, Umf=Umf[g][:, None], particles=(p_i, p_j), e=e,
                           rho_p=rho_c[c_i], liquid=liquid,
                           gas_arrays=(at_points(mu_g, g), at_points(rho_g, g)),
                           gas_source=r0._gas_source)
            shape = (gn, m.stop - m.start)
            flag = _preset_speeds(r) if partial else None  # None: every point answers
            us = np.broadcast_to(critical_outputs(r)["u_star"], shape)
            p = sticking_probability(r.speeds, us, r.collide, nodes=nodes, shape=shape,
                                     collide_on=r.collide_on, pair=r.sticking_pair)
            if flag is not None:
                bad = np.broadcast_to(flag, shape)
                p = np.where(bad != 0, np.nan, p)
                speed_flag[g] = np.maximum(speed_flag[g], bad.max(axis=1))
            elif partial and speed_flag[g].any():  # the bed-mean temperature has none
                p = np.where((speed_flag[g] != 0)[:, None], np.nan, p)
            pm[:, first[m]] = p
            pm[:, mirror[m]] = p
            if um is not None:
                um[:, first[m]] = us
                um[:, mirror[m]] = us
        pm = pm.reshape(gn, K, K, D)
        E[g] = np.einsum("gabk,k->gab", pm, wdir)
        if pairs:
            prob[g] = pm
        U[g] = np.broadcast_to(r.U, (gn, 1)).reshape(gn)
        bar.update(gn)
    bar.close()
    out = dict(E=E, W=W, Umf=Umf, U=U, n=n, w_bed=w_bed, cidx=cidx, d=d, lo=lo, hi=hi,
               D_wet=D_wet, h0_c=h0_c, s=s, beta=beta, wdir=wdir, d32=d32,
               rho_mean=rho_mean, names=[m.name for m in solids], resolved=r0,
               speed_flag=speed_flag)
    if pairs:
        out.update(u_star=u_star, prob=prob)
    return out


def _bed_speed(fvals, r0, comps, cidx, n, d, rho_s, W, Umf, flag=None) -> dict:
    """Scene fields that give every pair of classes one granular temperature where the
    scene's speed model depends on the particle (:data:`.speed_models.PER_PARTICLE`): the
    model's Maxwellian for the bed's mean particle (:func:`.speed_models.bed_mean_particle`)
    at each operating point, ``{"speed": "maxwellian", "granular_temperature": (G,)}``;
    else nothing. With ``flag`` (an int8 array (G,), a map's), the points where the model
    has no answer are written there and get a stand-in temperature (their results are
    NaN), instead of the model's ``ValueError``."""
    from .. import materials
    from .speed_models import PER_PARTICLE, bed_mean_particle, speed_law, speed_law_partial

    if fvals["speed"] not in PER_PARTICLE:
        return {}
    e_c = np.array([materials.solid(c.name).restitution_dry for c in comps])[cidx]
    e_pair = (np.asarray(fvals["e"], float).reshape(-1, 1, 1) if fvals.get("e") is not None
              else 0.5 * (e_c[:, None] + e_c[None, :])[None])
    d_p, rho_p, e = bed_mean_particle(n, d, rho_s, e_pair, W)
    r = Resolved(dict(fvals), Umf=Umf)
    inputs = {"U": r.U, "Umf": Umf, "d_p": d_p, "rho_p": rho_p, "rho_g": r0.rho_g,
              "eps": r0.num("eps"), "e": e}
    G = Umf.shape[0]
    if flag is None:
        theta = speed_law(fvals["speed"], inputs).theta
    else:
        law, bad = speed_law_partial(fvals["speed"], inputs)
        theta = law.theta
        if bad is not None:
            flag[...] = np.broadcast_to(bad, (G,))
            theta = np.where(flag != 0, 1.0, theta)  # a stand-in: the results are NaN
    return {"speed": np.full(G, "maxwellian"),
            "granular_temperature": np.broadcast_to(theta, (G,))}


def _attrs(units, long_name, description=None):
    """Variable attributes; ``units`` in CF spelling, ``None`` for names (no units)."""
    out = {} if units is None else {"units": cf_units(units)}
    out["long_name"] = long_name
    if description:
        out["description"] = description
    return out


def _contributions(ev):
    E = ev["E"]
    WE = ev["W"] * E
    by_class = WE.sum(axis=2)                    # (G, K): half of each collision per partner
    C = int(ev["cidx"].max()) + 1
    by_comp = np.stack([by_class[:, ev["cidx"] == c].sum(1) for c in range(C)], axis=1)
    return E, by_class, by_comp, by_class.sum(1)


def _class_coords(ev, dim):
    names = np.array(ev["names"])[ev["cidx"]]
    idx = np.arange(ev["d"].size, dtype=np.int32)
    return {dim: xr.Variable([dim], idx, attrs=_attrs("1", "size class (all components)")),
            f"component_{dim}": xr.Variable([dim], names, attrs=_attrs(
                None, "component (solid name) of the class")),
            f"d_{dim}": xr.Variable([dim], ev["d"], attrs=_attrs(
                "m", "solid diameter of the class")),
            f"d_lo_{dim}": xr.Variable([dim], ev["lo"], attrs=_attrs(
                "m", "lower edge of the class")),
            f"d_hi_{dim}": xr.Variable([dim], ev["hi"], attrs=_attrs(
                "m", "upper edge of the class"))}


@_one_snapshot("the bed point")
def bed_propensity(scene: Scene, components, *, nodes: int = 16,
                   directions: int = DEFAULT_DIRECTIONS) -> xr.Dataset:
    """Agglomeration propensity of a bed of one or more components at one operating point.

    Parameters
    ----------
    scene : Scene
        The operating point (temperature, gas, fluidization, liquid, speed model, tier...).
        Its ``solid_*``, ``d_*``, ``h0_j``, ``ha_*`` and ``beta_deg`` are replaced by the
        components' and by the direction average; its ``h0`` is the coating of every
        component whose ``h0`` is ``None``.
    components : sequence of Component
        The bed; mass fractions summing to 1 within 1e-9.
    nodes : int
        Nodes of the impact-speed quadrature (:func:`agglomtool.bed.speeds.sticking_probability`).
    directions : int
        Gauss-Legendre nodes in ``sin(beta)`` of the direction average, 1-64.

    Returns
    -------
    xarray.Dataset
        Every variable with a ``long_name`` and every number with CF ``units`` (names have
        none); global attributes as a map's (CF-1.8, the provenance of every input, the
        assumed database values, the materials' sources; see :func:`agglomtool.sweep`) and
        the components. Classes are numbered over all components along ``cls`` (pair
        dimensions ``cls_i``, ``cls_j``), each with its component, diameter and edges;
        ``direction`` holds ``sin_beta``, ``beta_deg`` and ``direction_weight``. Pair
        matrix: ``u_star`` (per direction), ``u_star_min`` (its minimum over directions:
        the lowest speed at which the pair rebounds in some direction),
        ``sticking_probability`` (per direction), ``efficiency`` (the direction average:
        the coalescence efficiency), ``rate_weight`` (``W_ab``). Bed:
        ``propensity``, ``propensity_by_class``, ``propensity_by_component`` (both sum to
        ``propensity``; a collision's share goes half to each partner), ``mass_fraction``,
        ``number_fraction``, ``collision_share`` (of each class), ``Umf``, ``U``,
        ``d_sauter``, ``rho_bed``.

    Notes
    -----
    The weighting and its assumptions (kinetic theory of granular mixtures, one granular
    temperature, ``g0 = 1``; isotropic collision normals) are written out in the module
    docstring of :mod:`agglomtool.bed.propensity`. The pair model is that of Shabanian et
    al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397.
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene = {scene!r} must be an agglomtool.Scene")
    check_int("nodes", nodes, 1, MAX_NODES)
    direction_nodes(directions)
    comps = _check_components(components)
    warn_findings(bed_findings(scene.values(), comps), stacklevel=3)
    ev = _evaluate(scene, comps, {}, _fractions(comps, None, None), nodes, directions)
    E, by_class, by_comp, total = _contributions(ev)
    coords = {**_class_coords(ev, "cls"), **_class_coords(ev, "cls_i"),
              **_class_coords(ev, "cls_j")}
    coords["direction"] = xr.Variable(["direction"], np.arange(ev["s"].size, dtype=np.int32),
                                      attrs=_attrs("1", "collision direction"))
    coords["sin_beta"] = xr.Variable(["direction"], ev["s"], attrs=_attrs(
        "1", "sine of the elevation of the axis i -> j (Gauss-Legendre node)"))
    coords["beta_deg"] = xr.Variable(["direction"], ev["beta"], attrs=_attrs(
        "degree", "elevation of the axis i -> j from the horizontal"))
    coords["direction_weight"] = xr.Variable(["direction"], ev["wdir"], attrs=_attrs(
        "1", "weight of the direction (isotropic normals)"))
    coords["component"] = xr.Variable(["component"], ev["names"],
                                      attrs=_attrs(None, "component (solid name)"))
    pair4, pair2 = ("cls_i", "cls_j", "direction"), ("cls_i", "cls_j")
    n0 = ev["n"][0]
    W0 = ev["W"][0]
    data = {
        "u_star": (pair4, ev["u_star"][0], _attrs(
            "m/s", "critical impact speed u0*", "per direction; inf: sticks up to u_ceiling")),
        "u_star_min": (pair2, ev["u_star"][0].min(axis=-1), _attrs(
            "m/s", "critical impact speed u0*, minimum over directions")),
        "sticking_probability": (pair4, ev["prob"][0], _attrs(
            "1", "sticking probability per direction",
            "over the scene's impact-speed distribution")),
        "efficiency": (pair2, E[0], _attrs(
            "1", "coalescence efficiency",
            "sticking probability averaged over isotropic collision directions")),
        "rate_weight": (pair2, W0, _attrs(
            "1", "collision-rate weight of the ordered pair of classes",
            "n_i n_j (D_i + D_j)**2, normalised to sum 1 over ordered pairs")),
        "propensity": ((), total[0], _attrs(
            "1", "bed agglomeration propensity",
            "fraction of all collisions in the bed that stick")),
        "propensity_by_class": (("cls",), by_class[0], _attrs(
            "1", "contribution of the class to the bed propensity",
            "half of each sticking collision to each partner; sums to propensity")),
        "propensity_by_component": (("component",), by_comp[0], _attrs(
            "1", "contribution of the component to the bed propensity",
            "sums to propensity")),
        "mass_fraction": (("cls",), ev["w_bed"][0], _attrs(
            "1", "mass fraction of the class in the bed")),
        "number_fraction": (("cls",), n0 / n0.sum(), _attrs(
            "1", "number fraction of the class in the bed")),
        "collision_share": (("cls",), W0.sum(axis=1), _attrs(
            "1", "share of the collisions the class takes part in",
            "sum_j rate_weight; half of each collision to each partner")),
        "h0_component": (("component",), ev["h0_c"][0], _attrs(
            "m", "coating thickness of the component")),
        "Umf": ((), ev["Umf"][0], _attrs("m/s", "minimum fluidization velocity of the bed")),
        "U": ((), ev["U"][0], _attrs("m/s", "superficial gas velocity")),
        "d_sauter": ((), ev["d32"][0], _attrs("m", "Sauter mean wet diameter of the bed")),
        "rho_bed": ((), ev["rho_mean"][0], _attrs("kg/m**3", "mean wet particle density")),
    }
    ds = xr.Dataset({k: xr.Variable(dims, v, attrs) for k, (dims, v, attrs) in data.items()},
                    coords=coords)
    ds.attrs.update(_bed_attrs(scene, comps, nodes, directions, call_text(
        "agglomtool.bed_propensity", {}, ("scene", "components"), nodes=nodes,
        directions=directions), names=ev["names"], resolved=ev["resolved"]))
    return ds


def _bed_attrs(scene, comps, nodes, directions, call, grid=None, names=None,
               resolved=None) -> dict:
    """Global attributes of a bed: what a map's carry (CF's, the provenance of every input,
    the database values that are assumptions, the materials' sources) and the bed's own
    (components, quadrature nodes, weighting). ``resolved``: a Resolved of the first point
    whose liquid and gas sources to take (their properties already found)."""
    import json

    grid = grid or {}
    base = scene.values()
    first = {**base, **{k: float(v[0]) for k, v in grid.items() if k in base}}
    names = names or [materials.solid(c.solid).name for c in comps]
    pairs = [{**first, "solid_i": a, "solid_j": b, "ha_i": ca.ha, "ha_j": cb.ha}
             for a, ca in zip(names, comps, strict=True)
             for b, cb in zip(names, comps, strict=True)]
    assumed = []
    for values in pairs:
        assumed += [t for t in assumed_inputs(values) if t not in assumed]
    # The liquid's and the gas's sources are those of the first point, whatever the solids:
    # found once (each Resolved evaluates the properties), the solids' added in bed order.
    r = Resolved(pairs[0]) if resolved is None else resolved
    sources = {f"solid {names[0]}": " ".join(materials.solid(names[0]).source.split())}
    sources.update({k: " ".join(t.split()) for k, t in r.sources.items()
                    if not k.startswith("solid ")})
    for name in names[1:]:
        sources.setdefault(f"solid {name}", " ".join(materials.solid(name).source.split()))
    return {
        **global_attrs("agglomtool bed propensity", call),
        "assumed_inputs": "; ".join(assumed) if assumed else "none",
        "provenance": provenance_attr(_bed_provenance(first, comps, grid, names)),
        "agglomtool_version": __version__,
        "model_tier": str(base["mode"]),
        "scene": json.dumps(base),
        "components": json.dumps([c.__dict__ for c in comps]),
        "speed_nodes": nodes, "direction_nodes": directions,
        "weighting": "collision rate n_i n_j pi d_ij**2 g0 sqrt(16 Theta/pi), one granular "
                     "temperature, g0 = 1 (Gidaspow 1994; Jenkins and Mancini 1989, "
                     "doi:10.1063/1.857479); isotropic normals, Gauss-Legendre in sin(beta)",
        "material_sources": json.dumps(sources),
    }


def _bed_provenance(first: dict, comps, grid: dict, names) -> dict:
    """:func:`agglomtool.scene.provenance` of a bed: the scene's inputs that the components
    and the grid do not set, and per solid the database values the bed uses (density,
    asperity height where a component gives none, dry restitution where the scene gives
    none), keyed ``"<solid> <field>"``. The components' own values are in the
    ``components`` attribute."""
    own = {*_OWN, "solid_i", "solid_j", "rho_i", "rho_j"}
    if first["e"] is None:
        own.add("e")  # each pair: the mean of its two solids' dry restitution
    out = {k: v for k, v in provenance({**first, "solid_i": names[0]}).items()
           if k not in own and k not in grid}
    for c, name in zip(comps, names, strict=True):
        p = provenance({**first, "solid_i": name, "solid_j": name, "ha_i": c.ha,
                        "ha_j": c.ha})
        out[f"{name} density"] = p["rho_i"]
        if c.ha is None:
            out[f"{name} asperity_height"] = p["ha_i"]
        if first["e"] is None:
            value, units, _, conf = p["e"]
            out[f"{name} restitution_dry"] = (
                value, units, f"database: solid {name}.restitution_dry (a pair takes the "
                "mean of its two solids')", conf)
    return out


@_one_snapshot("the bed sweep")
def bed_sweep(scene: Scene, components, *, mix=None, nodes: int = 16,
              directions: int = DEFAULT_DIRECTIONS, matrix: bool = False,
              progress: bool = False, **grid) -> xr.Dataset:
    """The bed propensity over a grid of operating conditions.

    Parameters
    ----------
    scene, components, nodes, directions
        As for :func:`bed_propensity`.
    mix : int or str, optional
        The component (index or solid name) whose mass fraction the grid axis ``fraction``
        sets; the others keep their proportions.
    matrix : bool
        Also return the coalescence-efficiency matrix ``efficiency`` over the grid.
    progress : bool
        Show a progress bar (tqdm) on stderr: operating points done, rate, time left.
    **grid
        1-D axes: the scene's numeric fields (``T``, ``U_Umf``, ``h0`` - the coating of
        every component that follows the scene -, ...; not ``d_*``, ``h0_j``, ``ha_*``,
        ``beta_deg``, which the components and the direction average set) and
        ``fraction`` [-]. Quantities and unit strings are accepted as in
        :func:`agglomtool.sweep`.

    Returns
    -------
    xarray.Dataset
        Over the grid's dimensions (in the order given): ``propensity``,
        ``propensity_by_component`` (+ ``component``), ``propensity_by_class`` (+ ``cls``),
        ``Umf``, ``U``, ``speed_flag`` (where nonzero the impact-speed model has no
        answer at the point, the propensities are NaN and a warning says how many points:
        :mod:`agglomtool.maps.speed_flag`) and, with ``matrix``, ``efficiency`` (+
        ``cls_i``, ``cls_j``); a
        long_name on every variable and coordinate, CF units on every number; global
        attributes as :func:`bed_propensity`'s. Where ``U`` is swept, ``ds["U"]`` is its
        coordinate (no output repeats it).

    Notes
    -----
    The operating points are evaluated in blocks of about 2**17 distinct collisions, each
    block one batch over its points, pairs of classes and directions.
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene = {scene!r} must be an agglomtool.Scene")
    check_int("nodes", nodes, 1, MAX_NODES)
    direction_nodes(directions)
    comps = _check_components(components)
    axes = _grid_arrays(grid)
    found = swept_without_effect(scene.values(), axes)
    if found:
        raise ValueError(found[1])
    warn_findings(bed_findings(scene.values(), comps, axes), stacklevel=3)
    if "fraction" in axes and mix is None:
        raise ValueError("grid fraction needs mix = the component (index or solid name) whose "
                         "mass fraction it sets")
    mix_i = None if mix is None else _mix_index(comps, mix)
    names = list(axes)
    shape = tuple(axes[k].size for k in names)
    mesh = np.meshgrid(*[axes[k] for k in names], indexing="ij") if names else []
    points = {k: m.reshape(-1) for k, m in zip(names, mesh, strict=True)}
    G = int(np.prod(shape)) if names else 1
    frac = points.pop("fraction", None)
    fr = _fractions(comps, frac, mix_i)
    fr = np.broadcast_to(fr, (G, len(comps)))
    ev = _evaluate(scene, comps, points, fr, nodes, directions, progress, pairs=False,
                   partial=True)
    E, by_class, by_comp, total = _contributions(ev)
    flag = ev["speed_flag"]  # where nonzero, E and so the propensities are NaN
    coords = {}
    for k in names:
        if k == "fraction":
            attrs = _attrs("1", f"mass fraction of {ev['names'][mix_i]} in the bed")
        else:
            attrs = _attrs(*FIELD_META[k])
        coords[k] = xr.Variable([k], axes[k], attrs=attrs)
    coords.update(_class_coords(ev, "cls"))
    coords["component"] = xr.Variable(["component"], ev["names"],
                                      attrs=_attrs(None, "component (solid name)"))
    dims = tuple(names)
    data = {
        "propensity": (dims, total.reshape(shape), _attrs(
            "1", "bed agglomeration propensity",
            "fraction of all collisions in the bed that stick")),
        "propensity_by_component": (dims + ("component",), by_comp.reshape(shape + (-1,)),
                                    _attrs("1", "contribution of the component "
                                           "to the bed propensity", "sums to propensity")),
        "propensity_by_class": (dims + ("cls",), by_class.reshape(shape + (-1,)), _attrs(
            "1", "contribution of the class to the bed propensity",
            "sums to propensity")),
        "Umf": (dims, ev["Umf"].reshape(shape), _attrs(
            "m/s", "minimum fluidization velocity of the bed")),
        "U": (dims, ev["U"].reshape(shape), _attrs("m/s", "superficial gas velocity")),
        "speed_flag": (dims, flag.reshape(shape), {
            **_attrs("1", "whether the impact-speed model has an answer at this point"),
            "flag_values": np.array(sorted(SPEED_FLAGS), dtype=np.int8),
            "flag_meanings": " ".join(v[0] for _, v in sorted(SPEED_FLAGS.items()))}),
    }
    for k in ("propensity", "propensity_by_component", "propensity_by_class"):
        data[k][2]["ancillary_variables"] = "speed_flag"
    if "U" in coords:  # swept: the coordinate is the superficial gas velocity
        del data["U"]
    if matrix:
        coords.update(_class_coords(ev, "cls_i"))
        coords.update(_class_coords(ev, "cls_j"))
        data["efficiency"] = (dims + ("cls_i", "cls_j"), E.reshape(shape + E.shape[1:]),
                              _attrs("1", "coalescence efficiency",
                                     "sticking probability averaged over directions"))
    ds = xr.Dataset({k: xr.Variable(d_, v, a) for k, (d_, v, a) in data.items()},
                    coords=coords)
    options = {"mix": ev["names"][mix_i]} if mix_i is not None else {}
    ds.attrs.update(_bed_attrs(scene, comps, nodes, directions, call_text(
        "agglomtool.bed_sweep", axes, ("scene", "components"), **options, nodes=nodes,
        directions=directions, matrix=bool(matrix)), grid=axes, names=ev["names"]))
    if mix_i is not None:
        ds.attrs["mix"] = ev["names"][mix_i]
    from ..maps.speed_flag import flag_text

    text = flag_text(flag, "the bed map")
    if text:
        warnings.warn(text, NoImpactSpeedWarning, stacklevel=2)
    return ds
