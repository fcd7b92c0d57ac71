"""Monte Carlo over a :class:`~agglomtool.Scene`: uncertain inputs named as the Scene names
them (``h0``, ``d_i``, ``T``, ``ha_j``, ``u0``, ...), properties re-derived for every draw.

This is the designer's question "how uncertain is this operating point?" asked of the Scene
they already have. The low-level path (:func:`agglomtool.monte_carlo` with Particle, Liquid,
... inputs and the core's names ``h0_i``, ``mu_l``, ``gamma``, ...) stays for the collision
core's own inputs.

One vocabulary, clashes resolved once: a Scene name that is also a core name draws from the
same random stream (``h0`` is the core's ``h0_i``; the others are spelled alike), so the same
seed gives the same draws on both paths.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from .._fields import FIELD_META, NUMERIC_FIELDS
from .._version import __version__
from ..collision.outcome import Stage
from ..plausibility import scene_findings, warn_findings
from ..scene import FIELD_RANGES, Resolved, Scene, provenance
from ._sampling import _SAMPLING, _attrs, _ChunkedDraws, _summary, resolve_seed
from .distributions import Distribution, to_si

__all__ = ["scene_monte_carlo", "scene_e_w", "field_law", "check_fields", "SCENE_TO_CORE"]

#: Scene name -> the core input name whose random stream it shares (where they differ).
SCENE_TO_CORE = {"h0": "h0_i"}

#: Scene fields that may be uncertain: every numeric field but the reporting ceiling.
UNCERTAIN_FIELDS = tuple(f for f in NUMERIC_FIELDS if f != "u_ceiling")


def check_fields(uncertain) -> None:
    """Raise ``ValueError`` naming any key of ``uncertain`` that is not an uncertain field."""
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise ValueError("uncertain must be a non-empty mapping of Scene field -> "
                         "distribution")
    for name in uncertain:
        if name not in UNCERTAIN_FIELDS:
            raise ValueError(f"uncertain input {name!r} is not a numeric Scene field; "
                             f"fields: {', '.join(UNCERTAIN_FIELDS)}")


def field_law(name: str, dist: Distribution):
    """``(dist in SI, lo, hi, lo_open, hi_open, range text)``: the law of Scene field
    ``name`` and the range its draws are truncated to (the Scene's valid range)."""
    unit = FIELD_META[name][0]
    d_si = to_si(name, dist, {"m**2/s**2": "m^2/s^2"}.get(unit, unit))
    lo, hi, lo_open, hi_open = FIELD_RANGES[name]
    lo, hi = -np.inf if lo is None else lo, np.inf if hi is None else hi
    text = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'} {unit}"
    return d_si, lo, hi, lo_open, hi_open, text


def scene_e_w(base: dict, draws: dict):
    """``(e_w, stage)`` of the scene ``base`` with the fields in ``draws`` replaced (1-D
    arrays of one length), at its impact speed (``u0`` if drawn or fixed, else the median
    of its speed distribution)."""
    r = Resolved({**base, **draws})
    u0 = draws["u0"] if "u0" in draws else r.u_typical
    res = r.collide(u0, details=False)
    shape = np.broadcast_shapes(*[np.shape(v) for v in draws.values()])
    return np.broadcast_to(res.e_w, shape), np.broadcast_to(res.stage, shape)


def scene_monte_carlo(scene: Scene, *, uncertain: Mapping[str, Distribution], n: int,
                      seed, chunk_size: int, quantiles, bins, keep_samples: bool
                      ) -> xr.Dataset:
    """The Scene path of :func:`agglomtool.monte_carlo` (see there for the parameters).

    Every draw is a Scene with the uncertain fields replaced; its properties (gas and
    liquid at the drawn T and P, ``U_mf``, the database values it does not override) are
    derived as for a map, and ``e_w`` is evaluated at the scene's impact speed: ``u0``
    (fixed, or drawn if uncertain) or the median of its speed distribution.
    """
    check_fields(uncertain)
    base = scene.values()
    entropy, chosen = resolve_seed(seed)
    chunk = int(min(chunk_size, n))
    draws = _ChunkedDraws(uncertain, n, entropy, chunk, law=field_law,
                          stream_name=lambda name: SCENE_TO_CORE.get(name, name))
    resampled, dists = draws.resampled, draws.dists
    before = set(scene_findings(base))

    # Memory as on the core path: e_w of every sample, the samples only when kept.
    e_w = np.empty(n)
    stage = np.empty(n, dtype=np.int8) if keep_samples else None
    values = {k: np.empty(n) for k in dists} if keep_samples else {}
    e_max = -np.inf if "e" in dists else float(np.max(Resolved(base).e))
    findings = []
    for sl, chunk_values in draws.chunks(out=values if keep_samples else None):
        # Draws that are valid but implausible (a lognormal given a log-space spread as
        # its standard deviation, ...) are said, as for a Scene.
        findings += [f for f in scene_findings({**base, **chunk_values})
                     if f not in before and f not in findings]
        e_w[sl], st = scene_e_w(base, chunk_values)
        if keep_samples:
            stage[sl] = st
        if "e" in chunk_values:
            e_max = max(e_max, float(np.max(chunk_values["e"])))
    warn_findings(findings, stacklevel=3)
    nominal = {k: np.atleast_1d(d.nominal) for k, d in dists.items()}
    e_w_nominal = float(scene_e_w(base, nominal)[0][0])
    edges = (np.linspace(0.0, max(e_max, float(e_w.max())), int(bins) + 1)
             if np.ndim(bins) == 0 else np.asarray(bins, dtype=float))
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise ValueError("bins must be a positive integer or increasing bin edges")
    ds = _summary(e_w, np.asarray(quantiles, dtype=float), edges, e_w_nominal, chunk,
                  scratch=not keep_samples)
    if keep_samples:
        ds["e_w"] = ("sample", e_w, _attrs("dimensionless", "wet restitution coefficient "
                                           "at the scene's impact speed"))
        ds["agglomerated"] = ("sample", e_w == 0.0, _attrs("dimensionless",
                                                           "the pair sticks (e_w = 0)"))
        ds["stage"] = ("sample", stage, _attrs(
            "dimensionless", "stage where the outcome was decided",
            flag_values=np.array([int(s) for s in Stage], dtype=np.int8),
            flag_meanings=" ".join(s.name.lower() for s in Stage)))
        for name, x in values.items():
            unit, long_name = FIELD_META[name]
            ds[name] = ("sample", x, _attrs(unit, long_name, distribution=repr(dists[name]),
                                            n_resampled=resampled[name]))
    prov = {f"provenance: {k}": f"{v} {u}; {o}; {c}"
            for k, (v, u, o, c) in provenance(base).items() if k not in dists}
    ds.attrs.update(
        title="Monte Carlo propagation of scene uncertainty to e_w",
        agglomtool_version=__version__,
        mode=str(base["mode"]),
        seed=entropy,
        seed_chosen_by_user=int(chosen),
        sampling=(f"{_SAMPLING}; Scene names share the core's streams "
                  f"({', '.join(f'{a} = {b}' for a, b in SCENE_TO_CORE.items())})"),
        n_samples=n,
        uncertain_inputs=" ".join(dists),
        distributions="; ".join(f"{k} = {dists[k]!r} [{FIELD_META[k][0]}]" for k in dists),
        n_resampled_total=int(sum(resampled.values())),
        scene=repr(scene),
        references="Shabanian et al. (2024), Heliyon 10:e29397, "
                   "doi:10.1016/j.heliyon.2024.e29397, Section 3.4",
        **prov,
    )
    return ds
