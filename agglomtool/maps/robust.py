"""Robust operating maps: the propensity at every grid point under uncertain inputs.

``at.sweep(scene, ..., uncertain=..., samples=N)`` evaluates the map's propensity at every
grid point for each of ``N`` draws of the uncertain inputs and reports, per point, its mean,
its quantiles and the probability that it exceeds the designer's threshold (the "unsafe"
criterion). The draws are common random numbers across the grid: draw ``k`` is the same
plausible world at every point (the same asperity height of the same solid, the same
coating error), so the map is smooth and a difference between two points is a difference
of the points, not of their draws. A point is *undecided* where the probability of being
unsafe lies strictly between :data:`UNDECIDED` bounds.

Draws are made once per combination of the swept names (solids, liquids, ...), from the
named streams of :mod:`agglomtool.uncertainty.assumed` and of the Scene Monte Carlo, so the
draws of a material are the same in every panel where it appears, and the same as
:func:`agglomtool.monte_carlo` and :func:`agglomtool.compare` draw with the same seed.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import xarray as xr

from .._fields import CATEGORICAL_FIELDS, FIELD_META
from .._validate import check_memory_for
from ..plausibility import scene_findings, warn_findings
from ..scene import Resolved, Scene, critical_outputs
from .speed_flag import flagged_collision_outputs

__all__ = ["robust_sweep", "UNDECIDED", "ROBUST_BLOCK"]

#: Probabilities of being unsafe between these bounds mark a point as undecided.
UNDECIDED = (0.1, 0.9)
#: Point-draw evaluations per batch (bounded memory, as a map's block).
ROBUST_BLOCK = 2**16


def _check(name, value, ok, text):
    if not ok(value):
        raise ValueError(f"{name} = {value!r} must be {text}")


def check_robust_options(samples, threshold) -> None:
    """``samples`` (an integer >= 2) and ``threshold`` (in [0, 1)) of a robust map."""
    _check("samples", samples, lambda v: isinstance(v, int | np.integer)
           and not isinstance(v, bool) and v >= 2, "an integer >= 2")
    _check("threshold", threshold, lambda v: isinstance(v, int | float) and not isinstance(
        v, bool) and 0.0 <= v < 1.0, "a number in [0, 1): the propensity above which a "
           "point is unsafe")


def robust_sweep(scene: Scene, nominal: xr.Dataset, grid: tuple, *, uncertain,
                 samples: int = 256, seed: int | None = 0, threshold: float = 0.5,
                 nodes: int = 16, quantiles=(0.05, 0.5, 0.95)) -> xr.Dataset:
    """The nominal map ``nominal`` of :func:`agglomtool.sweep` over the dimensions ``grid``
    (in order), with the propensity's spread under ``uncertain`` at every point (see
    :func:`agglomtool.sweep`, which calls this, for the parameters)."""
    from ..uncertainty._sampling import resolve_seed
    from ..uncertainty.assumed import chosen_fields
    from ..uncertainty.scene_mc import SceneDraws, split_uncertain, uncertain_without_effect

    check_robust_options(samples, threshold)
    q = np.asarray(quantiles, dtype=float)
    _check("quantiles", quantiles, lambda v: q.ndim == 1 and q.size > 0 and bool(
        np.all((q >= 0.0) & (q <= 1.0))), "a non-empty sequence of numbers in [0, 1]")
    fields, with_assumed = split_uncertain(uncertain)
    both = sorted(set(fields) & set(grid))
    if both:
        raise ValueError(f"{both[0]} is both swept and uncertain: sweep it, or make it "
                         "uncertain, not both")
    gv = {k: nominal[k].values for k in grid}
    # a law that no speed of the map reads (its swept speeds, else the scene's and those
    # the draws may take) would be reported as no spread
    found = (uncertain_without_effect(scene, uncertain, gv["speed"], drawn=())
             if "speed" in gv else uncertain_without_effect(scene, uncertain))
    if found:
        raise ValueError(found[1])
    entropy, chosen = resolve_seed(seed)
    base = scene.values()
    # a speed model named by the scene or swept by the map is given, not drawn
    named = tuple(dict.fromkeys(chosen_fields(scene) + (("speed",) if "speed" in gv
                                                        else ())))
    cats = [k for k in gv if k in CATEGORICAL_FIELDS]
    nums = [k for k in gv if k not in CATEGORICAL_FIELDS]
    num_shape = tuple(len(gv[k]) for k in nums)
    n_points = math.prod(num_shape)
    mesh = [m.ravel() for m in np.meshgrid(*[gv[k] for k in nums], indexing="ij")]
    cat_shape = tuple(len(gv[k]) for k in cats)
    mean = np.empty(cat_shape + num_shape)
    quant = np.empty(cat_shape + num_shape + (q.size,))
    p_unsafe = np.empty(cat_shape + num_shape)
    drawn_text: dict[str, str] = {}
    not_drawn_all: list[str] = []
    findings: list = []
    per_batch = max(1, ROBUST_BLOCK // int(samples))
    for idx in itertools.product(*[range(n) for n in cat_shape]):
        values = {**base, **{k: str(gv[k][i]) for k, i in zip(cats, idx, strict=True)}}
        where = ("the scene at " + ", ".join(f"{k} = {values[k]}" for k in cats)
                 if cats else "this scene")
        sd = SceneDraws(values, uncertain, int(samples), entropy, int(samples), where=where,
                        chosen=named)
        assumed = sd.assumed
        not_drawn_all += [t for t in sd.not_drawn if t not in not_drawn_all]
        draws, laws = sd.draws, sd.draws.dists
        # the draws of every law, and a point's propensity, u0* and e_w at every draw
        check_memory_for("samples", int(samples), 8 * (len(laws) + 3), item="sample")
        drawn = {k: np.empty(int(samples)) for k in laws}
        for _ in draws.chunks(out=drawn):
            pass
        for k in laws:
            drawn_text.setdefault(k, f"{k} = {draws.dists[k]!r}" + (
                f" [{FIELD_META[k][0]}]" if k in FIELD_META else
                f" ({assumed[k].law.law} {assumed[k].law.params}, assumed in the database)"))
        sample_fields = sd.scene_values(values, drawn)
        # draws that are valid but implausible are said, once, as for a Scene
        before = set(scene_findings(values))
        findings += [f for f in scene_findings({**values, **sample_fields})
                     if f not in before and f not in findings]
        prop = np.empty((n_points, int(samples)))
        for start in range(0, n_points, per_batch):
            sl = slice(start, min(start + per_batch, n_points))
            vals = dict(values)
            for k, m in zip(nums, mesh, strict=True):
                vals[k] = m[sl, None]
            for k, v in sample_fields.items():  # a drawn composition: oxide -> draws
                vals[k] = ({ox: w[None, :] for ox, w in v.items()} if isinstance(v, dict)
                           else v[None, :])
            r = Resolved(vals)
            crit = critical_outputs(r)
            # where the speed model has no answer (a draw's or the point's), NaN
            out = flagged_collision_outputs(r, crit["u_star"], nodes)
            prop[sl] = np.broadcast_to(out["propensity"], (sl.stop - sl.start, int(samples)))
        mean[idx] = prop.mean(axis=1).reshape(num_shape)
        quant[idx] = np.quantile(prop, q, axis=1).T.reshape(num_shape + (q.size,))
        # a point where some draw has no impact speed has no summary: NaN, as its mean
        p_unsafe[idx] = np.where(np.isnan(prop).any(axis=1), np.nan,
                                 np.mean(prop > threshold, axis=1)).reshape(num_shape)
    warn_findings(findings, stacklevel=4)
    nominal_flag = (nominal["speed_flag"].transpose(*cats, *nums).values != 0
                    if "speed_flag" in nominal else False)
    drawn_only = int(np.sum(np.isnan(mean) & ~np.broadcast_to(nominal_flag, mean.shape)))
    if drawn_only:
        import warnings

        from ..bed.speed_models import NoImpactSpeedWarning

        warnings.warn(f"{drawn_only} of {mean.size} points of the robust map have draws at "
                      "which the impact-speed model has no answer (their nominal point has "
                      "one): their propensity_mean, propensity_quantile and p_unsafe are "
                      "NaN and undecided is 2 (no_impact_speed)", NoImpactSpeedWarning,
                      stacklevel=4)
    dims = cats + nums
    ds = nominal.copy()
    ds = ds.assign_coords(quantile=("quantile", q, {"units": "1",
                                                    "long_name": "probability level"}))
    ds["propensity_mean"] = (dims, mean, {
        "units": "1", "long_name": "mean propensity over the plausible inputs"})
    ds["propensity_quantile"] = (dims + ["quantile"], quant, {
        "units": "1", "long_name": "quantile of the propensity over the plausible inputs"})
    ds["p_unsafe"] = (dims, p_unsafe, {
        "units": "1", "long_name": f"probability that the propensity exceeds {threshold:g}",
        "threshold": float(threshold)})
    lo, hi = UNDECIDED
    undecided = np.where(np.isnan(p_unsafe), 2, (p_unsafe > lo) & (p_unsafe < hi))
    ds["undecided"] = (dims, undecided.astype(np.int8), {
        "units": "1", "long_name": f"undecided: probability of being unsafe in ({lo:g}, "
        f"{hi:g})", "flag_values": np.array([0, 1, 2], dtype=np.int8),
        "flag_meanings": "decided undecided no_impact_speed"})
    ds.attrs.update(
        robust_samples=int(samples),
        robust_seed=entropy,
        robust_seed_chosen_by_user=int(chosen),
        robust_threshold=float(threshold),
        robust_uncertain_inputs="; ".join(drawn_text.values()),
        robust_assumed_not_drawn="; ".join(not_drawn_all) or "none",
        robust_method=("common random numbers: draw k is the same at every grid point "
                       "(named streams per input; an assumed database value has the "
                       "stream '<kind> <entry> <field>'); the propensity of every point "
                       "and draw as on the nominal map"),
    )
    return ds
