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
from typing import Any

import numpy as np
import xarray as xr

from .._fields import FIELD_META, NUMERIC_FIELDS
from .._validate import check_memory_for
from .._version import __version__
from ..collision.outcome import Stage
from ..plausibility import scene_findings, warn_findings
from ..scene import (
    COMPOSITION_KEY,
    FIELD_RANGES,
    Resolved,
    Scene,
    _about_default,
    collision_outputs,
    critical_outputs,
    provenance,
)
from ._sampling import _SAMPLING, _attrs, _ChunkedDraws, _summary, resolve_seed
from .assumed import ASSUMED, assumed_draws, chosen_fields, scene_fields
from .distributions import Distribution, to_si

__all__ = ["scene_monte_carlo", "scene_e_w", "field_law", "check_fields", "SCENE_TO_CORE",
           "SceneDraws", "uncertain_without_effect"]

#: Scene name -> the core input name whose random stream it shares (where they differ).
SCENE_TO_CORE = {"h0": "h0_i"}

#: Scene fields that may be uncertain: every numeric field but the reporting ceiling.
UNCERTAIN_FIELDS = tuple(f for f in NUMERIC_FIELDS if f != "u_ceiling")


def drawn_speeds(scene, uncertain) -> tuple[str, ...]:
    """The impact-speed models that draws of ``scene`` under ``uncertain`` may take in place
    of the scene's speed: those valid at the scene (:func:`.assumed.speed_model_weights`)
    where the database's assumed values are drawn and the scene does not name its speed
    (it derives it: an assumption), else none. ``uncertain=None``: none."""
    if uncertain is None or chosen_fields(scene) or not split_uncertain(uncertain)[1]:
        return ()
    from .assumed import speed_model_weights

    return tuple(speed_model_weights(scene.values()))


def uncertain_without_effect(scene, uncertain, speeds=(), drawn=None) -> tuple[str, str] | None:
    """The first field of the caller's laws in ``uncertain`` that no speed computing on
    the draws of ``scene`` reads, and why, as ``(field, message)``; ``None`` if each is read
    (:func:`agglomtool.scene.swept_without_effect`, for draws). The speeds: ``speeds`` where
    a comparison or a map sets them (its options or its axis), else the scene's, and
    ``drawn`` (default: :func:`drawn_speeds`). A law that nothing reads leaves every draw
    alike: its spread would be reported as none."""
    from ..scene import swept_without_effect

    fields, _ = split_uncertain(uncertain)
    if not fields:
        return None
    swept: dict[str, Any] = {"speed": [str(v) for v in speeds]} if len(speeds) else {}
    swept.update({k: [float(field_law(k, d)[0].nominal)] for k, d in fields.items()})
    if drawn is None:
        drawn = drawn_speeds(scene, uncertain)
    return swept_without_effect(scene.values(), swept, drawn, what="uncertain ", act="draw")


def split_uncertain(uncertain) -> tuple[dict, bool]:
    """``(fields, with_assumed)``: the caller's laws by Scene field, and whether the
    database's assumed values are drawn too.

    ``uncertain`` is a mapping of Scene field -> distribution, the word ``"assumed"``
    (every assumed value of the database, nothing else), or a mapping that also holds
    ``"assumed": True``. A ``ValueError`` names any key that is not an uncertain field.
    """
    if isinstance(uncertain, str):
        if uncertain != ASSUMED:
            raise ValueError(f"uncertain = {uncertain!r}: the one word allowed is "
                             f"{ASSUMED!r} (every value the materials database assumes); "
                             "else a mapping of Scene field -> distribution")
        return {}, True
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise ValueError(f"uncertain = {uncertain!r} is not allowed: a non-empty mapping of "
                         f"Scene field -> distribution, or {ASSUMED!r}")
    fields = dict(uncertain)
    flag = fields.pop(ASSUMED, False)
    if not isinstance(flag, bool):
        raise ValueError(f"uncertain[{ASSUMED!r}] = {flag!r} must be True or False")
    for name in fields:
        if name not in UNCERTAIN_FIELDS:
            raise ValueError(f"uncertain input {name!r} is not a numeric Scene field; "
                             f"fields: {', '.join(UNCERTAIN_FIELDS)}, or {ASSUMED!r}")
    if not fields and not flag:
        raise ValueError(f"uncertain = {uncertain!r} names no uncertain input")
    return fields, flag


def check_fields(uncertain) -> None:
    """Raise ``ValueError`` naming any key of ``uncertain`` that is not an uncertain field."""
    split_uncertain(uncertain)


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


class SceneDraws:
    """The uncertain inputs of the scene ``base``: the caller's laws (Scene fields) and,
    with ``"assumed"``, the database's assumed values, drawn ``n`` at a time in chunks of
    ``chunk`` from the streams of ``entropy`` (:class:`._sampling._ChunkedDraws`). What the
    Scene Monte Carlo and robust maps (:mod:`agglomtool.maps.robust`) both draw from.

    Attributes: ``fields`` (Scene field -> law), ``assumed`` (stream key ->
    :class:`.assumed.AssumedInput`), ``not_drawn`` (assumed values with no law), ``draws``.
    ``where`` names the scene in the error raised when there is nothing to draw;
    ``chosen`` the fields the user chose (:func:`.assumed.chosen_fields`: a speed model
    named is given, not drawn).
    """

    def __init__(self, base: dict, uncertain, n: int, entropy: int, chunk: int,
                 where: str = "this scene", chosen=()):
        self.fields, with_assumed = split_uncertain(uncertain)
        self.assumed, self.not_drawn = (assumed_draws(base, given=self.fields, chosen=chosen)
                                        if with_assumed else ({}, []))
        if not self.fields and not self.assumed:
            raise ValueError(
                f"uncertain = {ASSUMED!r}: {where} uses no assumed database value that can "
                "be drawn (the values it sets itself are not drawn)"
                + (f"; assumed but not drawn: {'; '.join(self.not_drawn)}"
                   if self.not_drawn else ""))
        laws = {**self.fields, **{k: a.dist for k, a in self.assumed.items()}}
        self.draws = _ChunkedDraws(laws, n, entropy, chunk, law=self._law,
                                   stream_name=lambda name: SCENE_TO_CORE.get(name, name))

    def _law(self, name, dist):
        if name in self.assumed:
            a = self.assumed[name]
            return (a.dist, *a.bounds, a.range_text)
        return field_law(name, dist)

    def scene_values(self, base: dict, chunk_values: dict) -> dict:
        """The Scene fields a chunk of draws sets: the caller's fields as drawn, and those
        the assumed values set (:func:`.assumed.scene_fields`)."""
        out = {k: v for k, v in chunk_values.items() if k in self.fields}
        out.update(scene_fields(base, {k: v for k, v in chunk_values.items()
                                       if k in self.assumed}))
        return out


def scene_monte_carlo(scene: Scene, *, uncertain, n: int, seed, chunk_size: int, quantiles,
                      bins, keep_samples: bool, nodes: int = 16) -> xr.Dataset:
    """The Scene path of :func:`agglomtool.monte_carlo` (see there for the parameters).

    Every draw is a Scene with the uncertain fields replaced; its properties (gas and
    liquid at the drawn T and P, ``U_mf``, the database values it does not override) are
    derived as for a map, and each draw answers the map's questions: its critical impact
    speed ``u_star``, its ``propensity`` (the probability that a collision sticks, over the
    draw's impact-speed law, as on a map) and ``e_w`` at its impact speed (``u0`` fixed or
    drawn, else the median of its speed law).

    ``uncertain="assumed"`` (or ``"assumed": True`` in the mapping) draws every value the
    materials database marks as assumed, from the law it states
    (:mod:`agglomtool.uncertainty.assumed`); each has its own stream named after the entry
    and the field, so options sharing a material share its draws.
    """
    base = scene.values()
    entropy, chosen = resolve_seed(seed)
    chunk = int(min(chunk_size, n))
    sd = SceneDraws(base, uncertain, n, entropy, chunk, chosen=chosen_fields(scene))
    fields, assumed, not_drawn, draws = sd.fields, sd.assumed, sd.not_drawn, sd.draws
    resampled, dists = draws.resampled, draws.dists
    # the Scene's own findings were said when it was made, but for those about its
    # defaults: said below where the draws use them (not where a draw replaces them)
    before = set(scene_findings(base)) - set(getattr(scene, "_deferred_findings", ()))

    # Memory as on the core path: the outputs of every sample, the samples only when kept.
    check_memory_for("n", n, 24 + (1 + 8 * len(dists) if keep_samples else 0))
    e_w, propensity, u_star = np.empty(n), np.empty(n), np.empty(n)
    stage = np.empty(n, dtype=np.int8) if keep_samples else None
    values = {k: np.empty(n) for k in dists} if keep_samples else {}
    scene_values: dict[str, np.ndarray] = {}
    compositions: dict[str, np.ndarray] = {}
    e_max = -np.inf
    findings = []
    for sl, chunk_values in draws.chunks(out=values if keep_samples else None):
        drawn = sd.scene_values(base, chunk_values)
        # Draws that are valid but implausible (a lognormal given a log-space spread as
        # its standard deviation, ...) are said, as for a Scene.
        findings += [f for f in scene_findings({**base, **drawn})
                     if f not in before and f not in findings]
        try:
            out = _map_outputs(base, drawn, nodes)
        except ValueError as exc:  # a draw outside what a property model takes: whose
            if not fields:
                raise
            laws = "; ".join(f"{k} = {dists[k]!r} [{FIELD_META[k][0]}]" for k in fields)
            bare = [k for k, d in fields.items() if not d._with_units()]
            hint = (f"; {', '.join(bare)} given without a unit, so in SI "
                    f"({', '.join(FIELD_META[k][0] for k in bare)}): if another unit was "
                    "meant, write it (\"25 degC\", \"5 um\")" if bare else "")
            raise ValueError(f"uncertain {', '.join(fields)}: a draw is refused: {exc} (the "
                             f"law in SI: {laws}{hint})") from None
        e_w[sl], propensity[sl], u_star[sl] = out["e_w"], out["propensity"], out["u_star"]
        if stage is not None:  # keep_samples
            stage[sl] = out["stage"]
            for k in ("e", "ha_i", "ha_j", "theta_deg", "fluctuation_ratio", "wake_fraction"):
                if k in drawn and k not in fields:
                    scene_values.setdefault(k, np.empty(n))[sl] = drawn[k]
            for oxide, wt in drawn.get(COMPOSITION_KEY, {}).items():
                compositions.setdefault(oxide, np.empty(n))[sl] = wt
            if "speed" in drawn:  # the impact-speed model drawn (uncertain="assumed")
                scene_values.setdefault("speed", np.empty(n, dtype="U32"))[sl] = drawn["speed"]
        e_max = max(e_max, float(np.max(out["e"])))
    warn_findings(findings, stacklevel=3)
    nominal = _map_outputs(base, _nominal_values(base, sd.fields, dists), nodes)
    e_w_nominal = float(nominal["e_w"][0])
    edges = (np.linspace(0.0, max(e_max, float(e_w.max())), int(bins) + 1)
             if np.ndim(bins) == 0 else np.asarray(bins, dtype=float))
    if edges.ndim != 1 or edges.size < 2 or np.any(np.diff(edges) <= 0.0):
        raise ValueError("bins must be a positive integer or increasing bin edges")
    q = np.asarray(quantiles, dtype=float)
    ds = _summary(e_w, q, edges, e_w_nominal, chunk, scratch=not keep_samples)
    _map_summary(ds, propensity, u_star, q, nominal)
    if keep_samples:
        ds["e_w"] = ("sample", e_w, _attrs("dimensionless", "wet restitution coefficient "
                                           "at the scene's impact speed"))
        ds["agglomerated"] = ("sample", e_w == 0.0, _attrs("dimensionless",
                                                           "the pair sticks (e_w = 0)"))
        ds["stage"] = ("sample", stage, _attrs(
            "dimensionless", "stage where the outcome was decided",
            flag_values=np.array([int(s) for s in Stage], dtype=np.int8),
            flag_meanings=" ".join(s.name.lower() for s in Stage)))
        ds["propensity"] = ("sample", propensity, _attrs(
            "dimensionless", "sticking probability over the draw's impact-speed law"))
        ds["u_star"] = ("sample", u_star, _attrs("m/s", "critical impact speed u0*"))
        for name, x in values.items():
            if name in assumed:
                a = assumed[name]
                if a.field.startswith("composition_wt "):  # an oxide's factor
                    unit, what = "dimensionless", (f"drawn factor on the {a.field.split()[1]} "
                                                   "share of the composition")
                else:
                    unit = (FIELD_META[_SCENE_FIELD_OF[a.field]][0]
                            if _SCENE_FIELD_OF.get(a.field) in FIELD_META else "1")
                    what = f"drawn {a.field}"
                ds[name.replace(" ", "_")] = ("sample", x, _attrs(
                    unit, f"{what} of {a.kind} {a.entry} (assumed in the database)",
                    distribution=repr(dists[name]), law=f"{a.law.law} {a.law.params}",
                    reason=a.law.reason, n_resampled=resampled[name]))
                continue
            unit, long_name = FIELD_META[name]
            ds[name] = ("sample", x, _attrs(unit, long_name, distribution=repr(dists[name]),
                                            n_resampled=resampled[name]))
        for name, x in scene_values.items():
            unit, long_name = FIELD_META.get(name, ("1", "impact-speed model"))
            ds[name] = ("sample", x, _attrs(unit, long_name + " (from the assumed draws)"))
        for oxide, x in compositions.items():
            ds[f"composition_wt_{oxide}"] = ("sample", x, _attrs(
                "percent", f"{oxide} share of the drawn melt composition, wt % (from the "
                "assumed draws)"))
    ones: dict[str, Any] = {k: 1.0 for k in assumed}  # factors of 1: a valid composition
    set_by_draws = set(fields) | set(scene_fields(base, ones))
    prov = {f"provenance: {k}": f"{v} {u}; {o}; {c}"
            for k, (v, u, o, c) in provenance(base).items() if k not in set_by_draws}
    ds.attrs.update(
        title="Monte Carlo propagation of scene uncertainty to u0*, propensity and e_w",
        agglomtool_version=__version__,
        mode=str(base["mode"]),
        seed=entropy,
        seed_chosen_by_user=int(chosen),
        sampling=(f"{_SAMPLING}; Scene names share the core's streams "
                  f"({', '.join(f'{a} = {b}' for a, b in SCENE_TO_CORE.items())}); an "
                  "assumed database value has the stream '<kind> <entry> <field>'"),
        n_samples=n,
        nodes=int(nodes),
        uncertain_inputs=" ".join(dists),
        distributions="; ".join(
            f"{k} = {dists[k]!r} [{FIELD_META[k][0] if k in FIELD_META else 'SI'}]"
            for k in dists),
        assumed_drawn="; ".join(f"{a.key}: {a.law.law} {a.law.params}"
                                for a in assumed.values()),
        assumed_not_drawn="; ".join(not_drawn),
        n_resampled_total=int(sum(resampled.values())),
        scene=repr(scene),
        references="Shabanian et al. (2024), Heliyon 10:e29397, "
                   "doi:10.1016/j.heliyon.2024.e29397, Section 3.4",
        **prov,
    )
    return ds


#: database field -> the Scene field whose unit its draws carry
_SCENE_FIELD_OF = {"asperity_height": "ha_i", "restitution_dry": "e", "theta_deg": "theta_deg",
                   "fluctuation_ratio": "fluctuation_ratio", "wake_fraction": "wake_fraction"}


def _map_outputs(base: dict, drawn: dict, nodes: int) -> dict:
    """The map's outputs of the scene ``base`` with the fields in ``drawn`` replaced (1-D
    arrays of one length; none: the nominal scene), flattened to 1-D."""
    r = Resolved({**base, **drawn})
    out = critical_outputs(r)
    out.update(collision_outputs(r, out["u_star"], nodes))
    n = max([np.size(v) for v in drawn.values()], default=1)
    res = {k: np.broadcast_to(out[k], np.broadcast_shapes(np.shape(out[k]), (n,))).ravel()
           for k in ("e_w", "stage", "propensity", "u_star")}
    res["e"] = np.atleast_1d(r.e)
    return res


def _nominal_values(base: dict, fields, dists) -> dict:
    """The nominal inputs where they differ from the scene's values: a field the user drew
    but left at the Scene's default (a water scene's 1073.15 K T, drawn around 320 K) takes
    its law's nominal value; a field the user set keeps it (the map's value at the scene)."""
    return {k: np.array([dists[k].nominal]) for k in fields
            if k in dists and _about_default(k, base)}


def _map_summary(ds: xr.Dataset, propensity, u_star, q, nominal) -> None:
    """Mean, standard error and quantiles of the propensity and of u0* over the draws."""
    n = propensity.size
    mean = float(propensity.mean())
    sd = float(propensity.std(ddof=1)) if n > 1 else 0.0
    ds["propensity_mean"] = ((), mean, _attrs(
        "dimensionless", "mean over the draws of the sticking probability (the map's "
        "propensity)"))
    ds["propensity_se"] = ((), sd / np.sqrt(n), _attrs(
        "dimensionless", "standard error of propensity_mean"))
    ds["propensity_quantile"] = ("quantile", np.quantile(propensity, q), _attrs(
        "dimensionless", "quantile of the propensity over the draws"))
    ds["propensity_nominal"] = ((), float(nominal["propensity"][0]), _attrs(
        "dimensionless", "propensity at the nominal inputs (the map's value)"))
    # u0* may be inf (the pair sticks at every bed speed): quantiles that pick a sample
    # (inverted CDF) rather than interpolate between an inf and a finite value.
    ds["u_star_quantile"] = ("quantile", np.quantile(u_star, q, method="inverted_cdf"),
                             _attrs("m/s", "quantile of the critical impact speed u0* over "
                                    "the draws (a sample value: inverted CDF)"))
    ds["u_star_nominal"] = ((), float(nominal["u_star"][0]), _attrs(
        "m/s", "u0* at the nominal inputs (the map's value)"))
