"""Impact-speed distributions and the agglomeration propensity.

Impact speed ``u0`` follows the package's head-on convention: each particle moves towards
the other at ``u0`` in the lab frame, so the relative normal speed is ``w = 2 u0``.

Families
--------
``"fixed"``
    Every collision at ``u0``.
``"lognormal"``
    ``ln u0`` normal with median ``u0`` and standard deviation ``sigma_ln``.
``"maxwellian"``
    Particle velocities Maxwellian with granular temperature ``Theta`` [m2/s2] (variance of
    each velocity component). The relative velocity of two particles is then Gaussian with
    variance ``2 Theta`` per component; weighting by the collision rate (proportional to
    the normal approach speed ``w``) gives ``p(w) ~ w exp(-w^2 / (4 Theta))`` for the
    normal relative speed of colliding pairs, so ``u0 = w/2`` is Rayleigh-distributed with
    ``F(u) = 1 - exp(-u^2 / Theta)`` and median ``sqrt(Theta ln 2)``. (Kinetic theory of
    granular flow, e.g. Gidaspow (1994), Multiphase Flow and Fluidization, Academic Press,
    ch. 9.)
``"excess-gas"`` (the default estimate)
    One of the models of :mod:`agglomtool.bed.speed_models`, beside ``"bubble-darton"``,
    ``"bubble-mori-wen"`` and ``"collisional-balance"``. The Maxwellian with
    ``sqrt(Theta) = k (U - U_mf)``, ``k = fluctuation_ratio`` (1 by
    default): the r.m.s. particle velocity per component is taken equal to the excess gas
    velocity that drives the bubbles. This is an order-of-magnitude assumption, not a
    fitted correlation: measured r.m.s. particle velocities in bubbling beds are of the
    order of 0.1 m/s at excess velocities of the order of 0.1 m/s. Replace it by a
    measured or simulated granular temperature when one is available.

Propensity
----------
:func:`sticking_probability` integrates the sticking indicator over the distribution. It
is *not* ``P(u0 < u0*)``: ``e_w(u0)`` need not be monotonic, and a pair may stick again
above ``u0*`` (the paper's Fig. 6b). Below ``u0*`` every collision sticks (``u0*`` is the
first rebound speed), so that mass ``F(u0*)`` is exact; the rest is integrated with ``N``
equal-probability nodes placed at the quantile midpoints of the part above ``u0*``::

    P = F(u0*) + (1 - F(u0*)) / N * sum_k stick(Q(F(u0*) + (1 - F(u0*)) (k - 1/2) / N))

When ``e_w`` is monotonic the sum is zero and ``P = F(u0*)`` exactly, whatever ``N``;
a sticking window above ``u0*`` is resolved to ``(1 - F(u0*)) / (2N)`` in probability.

Given the collisions as the fused kernels take them (``pair``, as scenes, maps and beds
pass it), the set of speeds above ``u0*`` at which the pair sticks again is found instead
and the CDF integrated over it::

    P = F(u0*) + sum_k F(b_k) - F(max(a_k, u0*))

- modes ``"relative"`` and ``"paper"`` without body forces on the axis: in compiled code
  from the tier's structure (``agglomtool.collision.sticking``), each end to 1e-13 of
  ``sqrt(Ca)``;
- mode ``"stokes"``: the set is empty (Ennis' criterion sticks below one speed only),
  ``P = F(u0*)`` with no collision evaluated;
- the other tiers and flags (``"ode"``, ``"ode_selfconsistent"``, ``"auto"``, ``"paper"``
  with a body force on the axis, ``drag_slip="particle"``): bracketed with the tier's own
  kernel between candidate speeds that include the ``N`` nodes above and mode
  ``"relative"``'s windows, each end bisected to 1e-12 of the speed
  (``agglomtool.collision.sticking_numeric``, whose docstring states what is proven and
  what is not: a window narrower than the candidates' spacing and away from the seeds);
- fixed speeds: the verdict at the speed itself (exact, as the one node).

Elements without a proven bracket (no verdict, a bisection that did not settle) keep the
quadrature above, which is also the reference the sets are tested against.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ndtr, ndtri

__all__ = ["SPEED_FAMILIES", "SpeedModel", "sticking_probability"]

#: The impact-speed names a scene may take: the three distributions given by their own
#: parameters, then the models of :mod:`agglomtool.bed.speed_models` (the tests check that
#: the two lists agree).
SPEED_FAMILIES = ("fixed", "lognormal", "maxwellian", "excess-gas", "bubble-darton",
                  "bubble-mori-wen", "collisional-balance")


#: ln 2 as numpy gives it (the Maxwellian median's factor).
_LN2 = float(np.log(2.0))


class SpeedModel:
    """A resolved impact-speed distribution (parameters are broadcasting arrays).

    Parameters
    ----------
    family : {"fixed", "lognormal", "maxwellian"}
    u0 : array_like, optional
        Fixed speed, or lognormal median [m/s].
    sigma_ln : array_like, optional
        Lognormal shape [-].
    granular_temperature : array_like, optional
        Maxwellian granular temperature [m2/s2].
    """

    def __init__(self, family, *, u0=None, sigma_ln=None, granular_temperature=None):
        if family not in ("fixed", "lognormal", "maxwellian"):
            raise ValueError(f"speed family {family!r} is not one of fixed, lognormal, "
                             "maxwellian")
        self.family = family
        self.u0 = None if u0 is None else np.asarray(u0, dtype=float)
        self.sigma_ln = None if sigma_ln is None else np.asarray(sigma_ln, dtype=float)
        self.theta = (None if granular_temperature is None
                      else np.asarray(granular_temperature, dtype=float))

    def median(self, out=None) -> np.ndarray:
        """Median impact speed [m/s] (the fixed value for ``"fixed"``). ``out``: a float64
        array of the parameters' shape into which a computed median is written (then
        returned), e.g. a map's result; ignored where the median is a parameter."""
        if self.family == "maxwellian":
            # np.sqrt(theta * ln 2) with one array, the product's, rooted in place (a new
            # array costs more than the arithmetic: its memory is mapped at first write)
            if not (out is not None and out.shape == self.theta.shape
                    and out.dtype == np.float64):
                out = None
            med = np.multiply(self.theta, _LN2, out=out)
            return np.sqrt(med, out=med) if isinstance(med, np.ndarray) else np.sqrt(med)
        return self.u0

    def cdf(self, u) -> np.ndarray:
        """``F(u) = P(u0 < u)`` [-]; ``u`` may be ``inf``."""
        u = np.asarray(u, dtype=float)
        if self.family == "fixed":
            return np.where(u > self.u0, 1.0, 0.0)
        if self.family == "lognormal":
            with np.errstate(divide="ignore"):
                z = np.log(u / self.u0) / self.sigma_ln
            return ndtr(z)
        return -np.expm1(-(u * u) / self.theta)

    def at(self, mask, shape) -> SpeedModel:
        """The same law at the elements ``mask`` (a boolean array of ``shape``) only: each
        parameter that varies becomes the 1-D array of its values there (a scalar stays)."""

        def pick(a):
            if a is None or a.ndim == 0:
                return a
            return np.broadcast_to(a, shape)[mask]

        return SpeedModel(self.family, u0=pick(self.u0), sigma_ln=pick(self.sigma_ln),
                          granular_temperature=pick(self.theta))

    def quantile(self, q) -> np.ndarray:
        """``Q(q)`` [m/s] for ``q`` in [0, 1)."""
        q = np.asarray(q, dtype=float)
        if self.family == "fixed":
            return self.u0 * np.ones_like(q)
        if self.family == "lognormal":
            return self.u0 * np.exp(self.sigma_ln * ndtri(q))
        return np.sqrt(-self.theta * np.log1p(-q))


def sticking_probability(speeds: SpeedModel, u_star, collide, *, nodes: int = 16,
                         shape=None, collide_on=None, pair=None, report=None,
                         out=None) -> np.ndarray:
    """Probability that a collision sticks when ``u0`` follows ``speeds`` [-].

    Parameters
    ----------
    speeds : SpeedModel
        The impact-speed distribution.
    u_star : array_like
        Critical impact speed ``u0*`` [m/s] (``inf``: sticks at every speed).
    collide : callable
        ``collide(u0)`` -> a :class:`~agglomtool.CollisionResult` of the scene.
    nodes : int
        ``N``, the number of equal-probability nodes above ``u0*`` (1 for ``"fixed"``).
    shape : tuple, optional
        Shape of the result (default: the broadcast of ``u_star`` and the parameters).
    collide_on : callable, optional
        ``collide_on(mask)`` -> ``f(u0)``, the collisions of the elements where ``mask`` is
        true (``u0`` 1-D, there only). Given, the nodes are evaluated only where probability
        lies above ``u0*`` (elsewhere ``P = 1`` without a collision); the same numbers.
    pair : callable, optional
        ``pair(u_star)`` -> ``(ins, steps, shape, tier, body, particle_slip)``, the
        collisions as the fused kernels take them (``agglomtool.collision.fused``;
        ``tier`` the fused tier's code, or the mode's name for the other tiers), or None.
        Given (and not None), the set of speeds above ``u0*`` at which the pair sticks
        again is found as the module docstring says, per tier, and the law's CDF
        integrated over it. Elements whose set has no proven bracket are integrated by
        the ``nodes`` quadrature as without ``pair``.
    report : dict, optional
        Filled with ``"exact"`` (elements whose ``P`` came from a compiled or proven
        sticking set: modes relative and paper on the axis, stokes, fixed speeds),
        ``"bracketed"`` (elements bracketed with the tier's kernel) and ``"quadrature"``
        (elements integrated by the nodes).
    out : numpy.ndarray, optional
        A C-contiguous float64 array of ``shape`` (a map's result) into which the compiled
        sticking set's ``P`` is written; it is then the array returned.

    Returns
    -------
    numpy.ndarray
        ``P`` in [0, 1]; see the module docstring for the rule and its accuracy.
    """
    if nodes < 1:
        raise ValueError(f"nodes = {nodes!r} must be >= 1")
    u_star = np.asarray(u_star, dtype=float)
    fused = None if pair is None else pair(u_star)
    if fused is not None:
        found = _with_pair(speeds, u_star, fused, shape, out, nodes)
        if found is not None:
            p, left, counts = found
            if left is not None and left.any():
                p[left] = _quadrature(speeds, u_star, collide, nodes, p.shape, collide_on,
                                      within=left)[left]
            if report is not None:
                report.update(counts, quadrature=int(0 if left is None
                                                      else np.count_nonzero(left)))
            return p
    p = _quadrature(speeds, u_star, collide, nodes, shape, collide_on)
    if report is not None:
        report.update(exact=0, bracketed=0, quadrature=int(p.size))
    return p


def _with_pair(speeds: SpeedModel, u_star, fused, shape, out, nodes):
    """``(P, left, counts)`` from the tier's sticking set (``fused``: what ``pair``
    returned): the compiled set of :mod:`agglomtool.collision.sticking` (modes "relative"
    and "paper"), the empty set of mode "stokes", the bracketing of
    :mod:`agglomtool.collision.sticking_numeric` (the other tiers, and the collisions of
    the compiled tiers without a proven set); ``left`` (None where it would hold no True)
    where the quadrature must fill ``P`` in; ``counts`` the elements whose ``P`` is exact
    (``"exact"``) and bracketed (``"bracketed"``). None where the collisions' shape does
    not broadcast to ``shape``."""
    tier = fused[3]
    shape = _element_shape(speeds, u_star, fused[2], shape)
    if shape is None:
        return None
    if tier == "stokes":
        # Ennis' criterion: nothing above a rebounding u0* sticks (sticking_numeric's
        # docstring): P = F(u0*), as the quadrature's sum of zeros gives it
        f_star = np.broadcast_to(speeds.cdf(u_star), shape)
        p = np.where(1.0 - f_star > 1e-12, f_star, 1.0)
        return p, None, {"exact": int(p.size), "bracketed": 0}
    if isinstance(tier, str):
        p, left = np.empty(shape), np.ones(shape, dtype=bool)
    else:
        p, left = _exact(speeds, u_star, fused, shape, out)
    counts = {"exact": int(p.size - (0 if left is None else np.count_nonzero(left))),
              "bracketed": 0}
    if left is not None:
        exact, bracketed, left = _bracketed(speeds, u_star, fused, shape, left, p, nodes)
        counts["exact"] += exact
        counts["bracketed"] = bracketed
    return p, left, counts


def _element_shape(speeds: SpeedModel, u_star, cshape, shape):
    """The elements' shape (``shape``, or the broadcast of ``u_star``, the collisions'
    ``cshape`` and the law), None where the collisions do not broadcast to it."""
    cshape = tuple(cshape)
    if shape is None:
        shape = np.broadcast_shapes(u_star.shape, cshape, np.shape(speeds.median()))
    shape = tuple(shape)
    try:
        if np.broadcast_shapes(shape, cshape) != shape:
            return None
    except ValueError:
        return None
    return shape


#: Family codes of the compiled integration (``agglomtool.collision.sticking``).
_FAMILY_CODES = {"fixed": 0, "lognormal": 1, "maxwellian": 2}


def _flat_param(a, shape):
    """A law parameter as a float64 array of length 1 or of ``shape``'s size."""
    a = np.asarray(a, dtype=float)
    if a.size == 1:
        return a.reshape(1)
    return np.ascontiguousarray(np.broadcast_to(a, shape)).reshape(-1)


def _exact(speeds: SpeedModel, u_star, fused, shape, out=None):
    """``(P, left)``: ``P`` from the compiled sticking sets, ``left`` (a boolean array, None
    where it would hold no True) where a collision's set was not proven (``shape``: the
    elements', to which the collisions broadcast).
    ``out``: as for :func:`sticking_probability` (used where the elements are one pass's)."""
    from ..collision.sticking import (
        propensity_exact,
        propensity_from_windows,
        sticking_windows,
    )

    ins, steps, cshape, tier, body, particle_slip = fused
    cshape = tuple(cshape)
    n_c = int(np.prod(cshape, dtype=np.int64))
    us = np.ascontiguousarray(np.broadcast_to(u_star, cshape), dtype=float).reshape(-1)
    fam = speeds.family
    p1, p2 = _law_params(speeds)
    lead = _trailing(cshape, shape)
    if lead is not None:  # each collision's elements consecutive: one pass, no index
        inner = int(np.prod(shape[lead:], dtype=np.int64))
        (p1, h1), (p2, h2) = (_part_param(a, shape, lead) for a in (p1, p2))
        into = None
        if (out is not None and out.shape == shape and out.dtype == np.float64
                and out.flags.c_contiguous and out.flags.writeable):
            into = out.reshape(-1)  # a view: P is written into ``out``
        p = propensity_exact(ins, steps, n_c, tier, us, inner, body=body,
                             particle_slip=particle_slip, family=_FAMILY_CODES[fam], p1=p1,
                             p2=p2, how=(h1, h2), out=into)
        if into is not None:
            p = out
    else:
        p1, p2 = _flat_param(p1, shape), _flat_param(p2, shape)
        windows = sticking_windows(ins, steps, n_c, tier, us, body=body,
                                   particle_slip=particle_slip)
        idx = np.ascontiguousarray(_collision_of(cshape, shape)).reshape(-1)
        p = propensity_from_windows(idx, _FAMILY_CODES[fam], p1, p2, us, windows)
    if p is not out:
        p = p.reshape(shape)
    # one reduction decides the common case (no NaN: the minimum is NaN exactly when some
    # element is); the mask only where the quadrature has elements to fill in
    return p, (np.isnan(p) if p.size and math.isnan(p.min()) else None)


def _law_params(speeds: SpeedModel):
    """``(p1, p2)`` of a law as the compiled integration reads them
    (:class:`agglomtool.collision.sticking.SpeedLaw`): the fixed speed, the lognormal
    median or the granular temperature, and the lognormal ``sigma_ln`` (1 otherwise)."""
    if speeds.family == "maxwellian":
        return speeds.theta, 1.0
    if speeds.family == "lognormal":
        return speeds.u0, speeds.sigma_ln
    return speeds.u0, 1.0


def _collision_of(cshape, shape) -> np.ndarray:
    """The collision (flat index into ``cshape``) of each element of ``shape``, to which
    the collisions broadcast: a read-only broadcast view."""
    cshape = tuple(cshape)
    n_c = int(np.prod(cshape, dtype=np.int64))
    return np.broadcast_to(np.arange(n_c, dtype=np.int64).reshape(cshape), shape)


def _column(speeds: SpeedModel) -> SpeedModel:
    """The law of 1-D elements (:meth:`SpeedModel.at`) with each varying parameter as a
    column, so that it broadcasts against ``(elements, speeds)`` arrays."""

    def col(a):
        return a if a is None or a.ndim == 0 else a[:, None]

    return SpeedModel(speeds.family, u0=col(speeds.u0), sigma_ln=col(speeds.sigma_ln),
                      granular_temperature=col(speeds.theta))


def bracket_elements(speeds: SpeedModel, u_star, fused, shape, within, nodes=16):
    """The sticking sets of the elements ``within`` (a boolean array of ``shape``, the
    elements where probability lies above ``u0*``) by the bracketing of
    :mod:`agglomtool.collision.sticking_numeric` with ``nodes`` of the law's quantile
    nodes among the candidates. Returns ``(law, cand, stuck, cross, ok)``: the elements'
    law (:func:`_column`), their candidate speeds and verdicts, the crossings and where
    they are proven (:func:`~agglomtool.collision.sticking_numeric.bracket`)."""
    from ..collision.sticking_numeric import (
        TAIL,
        bracket,
        candidate_rows,
        collision_candidates,
        relative_seeds,
        stick_indicator,
    )

    ins, steps, cshape, tier, body, particle_slip = fused
    cshape = tuple(cshape)
    n_c = int(np.prod(cshape, dtype=np.int64))
    us_c = np.ascontiguousarray(np.broadcast_to(u_star, cshape), dtype=float).reshape(-1)
    where = np.flatnonzero(within)
    coll = _collision_of(cshape, shape).reshape(-1)[where]
    us = us_c[coll]
    law = _column(speeds.at(within, shape))
    f_o = law.cdf(us[:, None])
    r_o = 1.0 - f_o
    q = f_o + r_o * ((np.arange(nodes) + 0.5) / nodes)[None, :]
    q_top = np.maximum(1.0 - TAIL, q[:, -1:])
    node_u = np.broadcast_to(law.quantile(q), q.shape)
    top = np.broadcast_to(law.quantile(q_top), (where.size, 1))[:, 0]
    sticks = stick_indicator(ins, steps, tier, body, particle_slip)
    # the collision's own candidates once per collision, the law's nodes per element
    colls, inv = np.unique(coll, return_inverse=True)
    seeds = relative_seeds(ins, steps, n_c, us_c, body)[colls]
    col_speeds, col_pre = collision_candidates(sticks, colls, us_c[colls], seeds)
    cand, pre = candidate_rows(col_speeds[inv], col_pre[inv], node_u, top)
    stuck, cross, ok = bracket(sticks, coll, cand, pre)
    return law, cand, stuck, cross, ok


def _bracketed(speeds: SpeedModel, u_star, fused, shape, left, p, nodes):
    """``P`` into ``p`` at the elements ``left`` by bracketing, the law's ``nodes`` among
    the candidates (fixed speeds: the verdict at the speed itself, exact). Returns
    ``(exact, bracketed, still_left)``: the elements done each way, and those left to the
    quadrature (None where none)."""
    f_star = np.broadcast_to(speeds.cdf(u_star), shape)
    rest = 1.0 - f_star
    open_ = left & (rest > 1e-12)
    p[left & ~open_] = 1.0
    exact = int(np.count_nonzero(left & ~open_))
    if not open_.any():
        return exact, 0, None
    from ..collision.sticking_bracketed import kind_of

    if kind_of(fused[3]) is not None:
        val, ok = _bracketed_compiled(speeds, u_star, fused, shape, open_, nodes)
        done = _put(p, open_, val, ok)
        if speeds.family == "fixed":  # the verdict at the speed itself: exact
            return exact + done, 0, _unproven(open_, ok)
        return exact, done, _unproven(open_, ok)
    if speeds.family == "fixed":
        from ..collision.sticking_numeric import stick_indicator

        ins, steps, cshape, tier, body, particle_slip = fused
        where = np.flatnonzero(open_)
        coll = _collision_of(cshape, shape).reshape(-1)[where]
        u = np.broadcast_to(speeds.u0, shape).reshape(-1)[where]
        positive = u > 0.0  # a speed of 0 cannot collide: sticks, as the quadrature says
        s, known = stick_indicator(ins, steps, tier, body, particle_slip)(
            coll[positive], u[positive])
        stuck = np.ones(where.size)
        stuck[positive] = s
        ok = np.ones(where.size, dtype=bool)
        ok[positive] = known
        val = f_star[open_] + rest[open_] * stuck  # the one node's sum, P exactly
        return exact + _put(p, open_, val, ok), 0, _unproven(open_, ok)
    law, cand, stuck, cross, ok = bracket_elements(speeds, u_star, fused, shape, open_,
                                                   nodes)
    f_c = law.cdf(cand)
    f_x = law.cdf(cross)
    s = stuck.astype(float)
    val = (f_c[:, 0] + np.sum(s[:, :-1] * (f_x - f_c[:, :-1])
                              + s[:, 1:] * (f_c[:, 1:] - f_x), axis=1)
           + s[:, -1] * (1.0 - f_c[:, -1]))
    return exact, _put(p, open_, np.minimum(val, 1.0), ok), _unproven(open_, ok)


def _bracketed_compiled(speeds: SpeedModel, u_star, fused, shape, within, nodes):
    """``(P, ok)`` at the elements ``within`` (in their order) by the compiled bracketing
    of :mod:`agglomtool.collision.sticking_bracketed`: the method of
    :func:`bracket_elements` and :func:`_bracketed` in one pass per block."""
    from ..collision.sticking_bracketed import bracketed_propensity, kind_of
    from ..collision.sticking_numeric import TAIL

    ins, steps, cshape, tier, body, particle_slip = fused
    cshape = tuple(cshape)
    us_c = np.ascontiguousarray(np.broadcast_to(u_star, cshape), dtype=float).reshape(-1)
    coll = _collision_of(cshape, shape).reshape(-1)[np.flatnonzero(within)]
    law = speeds.at(within, shape)
    fam = law.family
    p1, p2 = _law_params(law)

    def lognormal(idx):
        # the nodes, the top speed and F(u0*) of the elements idx, as bracket_elements
        # makes them
        part = _column(SpeedModel(fam, u0=_rows(law.u0, idx),
                                  sigma_ln=_rows(law.sigma_ln, idx)))
        f_o = np.broadcast_to(part.cdf(us_c[coll[idx]][:, None]), (idx.size, 1))
        q = f_o + (1.0 - f_o) * ((np.arange(nodes) + 0.5) / nodes)[None, :]
        q = np.concatenate([q, np.maximum(1.0 - TAIL, q[:, -1:])], axis=1)
        return np.concatenate([np.broadcast_to(part.quantile(q), q.shape), f_o], axis=1)

    return bracketed_propensity(ins, steps, kind_of(tier), us_c, coll, _FAMILY_CODES[fam],
                                np.asarray(p1, dtype=float), np.asarray(p2, dtype=float),
                                body=body, particle_slip=particle_slip, nodes=nodes,
                                lognormal=lognormal)


def _rows(a, idx):
    """Elements ``idx`` (an index array) of a parameter of :meth:`SpeedModel.at` (a scalar
    stays)."""
    return a if a.ndim == 0 else a[idx]


def _put(p, mask, val, ok):
    """``p[mask] = val`` where ``ok`` (``val``, ``ok``: one per element of ``mask``, in
    its order); returns how many were written."""
    sub = p[mask]
    sub[ok] = val[ok]
    p[mask] = sub
    return int(np.count_nonzero(ok))


def _unproven(mask, ok):
    """The elements of ``mask`` where not ``ok``, as a boolean array (None where none)."""
    if ok.all():
        return None
    still = np.zeros(mask.shape, dtype=bool)
    still[mask] = ~ok
    return still


def _trailing(cshape: tuple, shape: tuple):
    """``m`` where the collisions (``cshape``, broadcasting to ``shape``) vary along the
    first ``m`` axes of ``shape`` only, all of them (element ``k`` is collision
    ``k // inner``, ``inner`` the size of the trailing axes); None where they do not."""
    if 0 in shape:
        return None
    cshape = (1,) * (len(shape) - len(cshape)) + tuple(cshape)
    m = len(shape)
    while m > 0 and cshape[m - 1] == 1:
        m -= 1
    if cshape[:m] != shape[:m]:
        return None
    return m


def _part_param(a, shape, lead):
    """A law parameter as :func:`agglomtool.collision.sticking.propensity_exact` reads it:
    ``(float64 array, how)``, one value, one per collision (the first ``lead`` axes of
    ``shape``), one per position along the others, or one per element; no array of the
    block's size where the parameter varies along one kind of axis only."""
    from ..collision.sticking import ONE, PER_COLLISION, PER_ELEMENT, PER_TRAILING

    a = np.asarray(a, dtype=float)
    if a.size == 1:
        return a.reshape(1), ONE
    ashape = (1,) * (len(shape) - a.ndim) + a.shape
    if all(x == 1 for x in ashape[lead:]):
        part = np.broadcast_to(a.reshape(ashape[:lead]), shape[:lead])
        return np.ascontiguousarray(part).reshape(-1), PER_COLLISION
    if all(x == 1 for x in ashape[:lead]):
        part = np.broadcast_to(a.reshape(ashape[lead:]), shape[lead:])
        return np.ascontiguousarray(part).reshape(-1), PER_TRAILING
    return _flat_param(a, shape), PER_ELEMENT


def _quadrature(speeds: SpeedModel, u_star, collide, nodes, shape, collide_on, within=None):
    """The node quadrature of the module docstring (the reference), over the elements
    ``within`` only where given (elsewhere the result is meaningless)."""
    f_star = speeds.cdf(u_star)
    if shape is None:
        shape = np.broadcast_shapes(f_star.shape, np.shape(speeds.median()))
    f_star = np.broadcast_to(f_star, shape)
    rest = 1.0 - f_star
    # Below 1e-12 of probability left above u0*, P = 1 to that accuracy (and a quantile
    # node would round to q = 1, an infinite speed).
    open_ = rest > 1e-12
    if within is not None:
        open_ = open_ & within
    n = 1 if speeds.family == "fixed" else int(nodes)
    stuck = np.zeros(shape)
    if open_.any():
        if collide_on is not None:
            run = collide_on(open_)  # the open elements' inputs, cut once for every node

            def sticks(u_open):
                return run(u_open).agglomerated
        else:

            def sticks(u_open):  # every element collides; the open ones are kept
                u = np.ones(shape)
                u[open_] = u_open
                return np.broadcast_to(collide(u).agglomerated, shape)[open_]

        f_o, r_o = f_star[open_], rest[open_]
        speeds_o = speeds.at(open_, shape)  # the quantiles of the open elements only
        stuck_o = np.zeros(f_o.shape)
        for k in range(n):  # a loop over quadrature nodes, each vectorised over the grid
            u = np.broadcast_to(speeds_o.quantile(f_o + r_o * ((k + 0.5) / n)), f_o.shape)
            positive = u > 0.0  # a node speed of 0 (degenerate law) cannot collide: sticks
            stuck_o += sticks(np.where(positive, u, 1.0)) | ~positive
        stuck[open_] = stuck_o
    return np.where(open_, f_star + rest * stuck / n, 1.0)
