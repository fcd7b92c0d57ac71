"""Comparisons that say whether they are decided: options of one Scene field under paired
draws of the uncertain inputs they share.

A designer asks "does ilmenite stick less than silica sand?". Each option is the same Scene
with one field changed; every option is evaluated on the same draws of every uncertain input
(the random streams are named after the input, so an input two options share is drawn alike
for both: paired draws). For each pair of options the answer is the probability, over the
plausible inputs, that one sticks less than the other, and the input whose uncertainty
decides that difference.

Which input decides is measured by the first-order sensitivity index of the difference of
the two propensities, ``S_k = Var(E[D | X_k]) / Var(D)``, estimated from the same draws by
binning ``X_k`` into equal-count bins (a given-data estimator: no extra model runs; its
bias is of the order of bins / n, small for n in the thousands).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from .._fields import CATEGORICAL_FIELDS, FIELD_META, NUMERIC_FIELDS
from .._validate import check_memory_for
from .._version import __version__
from ..scene import Scene

__all__ = ["compare", "verdicts"]

#: A ranking is called decided when one option sticks less in at least this share of the
#: plausible inputs and more in at most 1 - this share.
DECIDED = 0.9
#: Below this first-order index no single input is said to decide a difference.
INDEX_MIN = 0.2

#: Database fields in words.
_WORDS = {"asperity_height": "asperity height", "restitution_dry": "dry restitution",
          "theta_deg": "contact angle", "density": "density"}


def _options(option_grid: Mapping) -> tuple[str, list]:
    if len(option_grid) != 1:
        raise ValueError(f"option: {sorted(option_grid) or 'none'} given; allowed: exactly "
                         "one field (a Scene field) with its options, e.g. "
                         "solid_j=['silica-sand', 'ilmenite']")
    (field, values), = option_grid.items()
    if field not in CATEGORICAL_FIELDS and field not in NUMERIC_FIELDS:
        raise ValueError(f"{field!r} is not a Scene field; fields: "
                         f"{', '.join(CATEGORICAL_FIELDS + NUMERIC_FIELDS)}")
    vals = [values] if isinstance(values, str) else list(np.atleast_1d(values).tolist()
                                                         if not isinstance(values, list)
                                                         else values)
    if len(vals) < 2:
        raise ValueError(f"compare {field}: needs at least two options, got {values!r}")
    if len({str(v) for v in vals}) != len(vals):
        raise ValueError(f"compare {field}: options repeat: {values!r}; allowed: distinct "
                         "options")
    return field, vals


def _first_order(x: np.ndarray, d: np.ndarray, bins: int) -> float:
    """``Var(E[d | x]) / Var(d)`` by equal-count bins of ``x`` (0 where d does not vary)."""
    var = float(np.var(d))
    if var <= 0.0 or np.ptp(x) == 0.0:
        return 0.0
    order = np.argsort(x, kind="stable")
    groups = np.array_split(d[order], bins)
    means = np.array([g.mean() for g in groups])
    sizes = np.array([g.size for g in groups])
    between = float(np.sum(sizes * (means - d.mean()) ** 2) / d.size)
    return between / var


#: Equal-count bins of the first-order index that finds the deciding input (the default of
#: :func:`compare`; a comparison needs at least as many draws).
BINS = 16


def compare(scene: Scene, *, uncertain="assumed", n: int = 4096, seed: int | None = 0,
            bins: int = BINS, **option) -> xr.Dataset:
    """Compare the options of one Scene field under paired uncertain inputs.

    Parameters
    ----------
    scene : Scene
        The operating point; the options replace one of its fields.
    uncertain : mapping or ``"assumed"``
        As for :func:`agglomtool.monte_carlo` with a Scene: Scene field -> distribution,
        ``"assumed"`` (every value the materials database assumes, from the laws it
        states), or a mapping holding ``"assumed": True`` as well. Default ``"assumed"``.
    n : int
        Draws per option (>= ``bins``; thousands for a ranking to be read).
    seed : int or None
        Seed of the draws (the same for every option: paired draws).
    bins : int
        Equal-count bins of the sensitivity estimator (2 <= bins <= n).
    **option
        Exactly one Scene field with two or more options, e.g.
        ``solid_j=["silica-sand", "ilmenite", "olivine"]`` or ``h0=[1e-6, 5e-6]``.

    Returns
    -------
    xarray.Dataset
        Over ``option`` (and ``other``, the same options): ``propensity_mean``,
        ``propensity_quantile`` (5, 50, 95 %), ``u_star_quantile``;
        ``p_lower[option, other]``: the probability that ``option`` sticks less than
        ``other`` (propensity strictly lower) over the plausible inputs; ``p_equal``;
        ``deciding_input`` and ``deciding_index``: the uncertain input with the largest
        first-order index of the difference, and that index. ``attrs["verdicts"]``: one
        sentence per pair (``agglomtool.uncertainty.compare.verdicts``).
    """
    from .._validate import material_key
    from ..scene import Scene, swept_without_effect
    from ._sampling import resolve_seed
    from .scene_mc import (
        drawn_speeds,
        scene_monte_carlo,
        split_uncertain,
        uncertain_without_effect,
    )

    if not isinstance(scene, Scene):
        raise ValueError(f"scene = {scene!r} is not allowed: an agglomtool.Scene is required")
    field, opts = _options(option)
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ValueError(f"n = {n!r} must be a positive integer")
    if isinstance(bins, bool) or not isinstance(bins, int | np.integer) or bins < 2:
        raise ValueError(f"bins = {bins!r} must be an integer in [2, n = {n}]")
    if n < bins:
        raise ValueError(f"n = {n} is fewer draws than the {bins} equal-count bins that find "
                         f"the deciding input; allowed: n >= {bins} (or bins <= n)")
    resolve_seed(seed)  # every request checked before the first draw
    split_uncertain(uncertain)
    found = swept_without_effect(scene.values(), {field: opts},
                                 drawn_speeds(scene, uncertain), what="")
    if found:
        raise ValueError(f"compare {field}: {found[1]}")
    found = uncertain_without_effect(scene, uncertain, opts if field == "speed" else ())
    if found:
        raise ValueError(found[1])
    scenes = []
    for v in opts:
        try:
            scenes.append(scene.replace(**{field: v}))
        except ValueError as exc:
            raise ValueError(f"compare {field}: option {v!r}: {exc}") from None
    # the same option in two spellings ("1 um" and 1e-6, silica_sand): compared as the
    # scene holds it, SI numbers and names as the database spells them
    held = [getattr(s, field) for s in scenes]
    held = [material_key(h) if isinstance(h, str) else float(h) for h in held]
    if len(set(held)) != len(held):
        raise ValueError(f"compare {field}: options repeat: {opts!r} are "
                         f"{len(set(held))} distinct options; allowed: distinct options")
    q = (0.05, 0.5, 0.95)
    # every option's propensity, u0* and e_w of every draw, kept side by side
    check_memory_for("n", n, len(scenes) * 32)
    # each option's draws as monte_carlo(s, ...) makes them; an uncertain field was checked
    # above against the speeds of every option, not of one
    runs = [scene_monte_carlo(s, uncertain=uncertain, n=int(n), seed=seed,
                              chunk_size=1_000_000, quantiles=q, bins=8, keep_samples=True)
            for s in scenes]
    prop = np.stack([r.propensity.values for r in runs])  # (option, sample)
    # the inputs each option drew (its sample variables that carry a distribution)
    inputs = [[k for k in r.data_vars if r[k].dims == ("sample",)
               and "distribution" in r[k].attrs] for r in runs]
    k_opt = len(opts)
    p_lower = np.zeros((k_opt, k_opt))
    p_equal = np.zeros((k_opt, k_opt))
    deciding = np.full((k_opt, k_opt), "", dtype=object)
    index = np.zeros((k_opt, k_opt))
    for a in range(k_opt):
        for b in range(k_opt):
            d = prop[a] - prop[b]
            p_lower[a, b] = float(np.mean(d < 0.0))
            p_equal[a, b] = float(np.mean(d == 0.0))
            if b <= a:
                continue  # the index of -d is that of d: found once, for a < b
            best, best_s = "", 0.0
            # every input drawn for either option is a covariate of the difference (the
            # samples are aligned: sample k of both options shares the shared inputs);
            # an input both draw must have been drawn alike (paired)
            for name in dict.fromkeys(inputs[a] + inputs[b]):
                here = [r[name].values for r in (runs[a], runs[b]) if name in r]
                if len(here) == 2 and not np.array_equal(here[0], here[1]):
                    continue
                s_k = _first_order(here[0], d, int(bins))
                if s_k > best_s:
                    best, best_s = str(name), s_k
            deciding[a, b] = deciding[b, a] = best
            index[a, b] = index[b, a] = best_s
    labels = [str(v) for v in opts]
    dimless = "1"
    ds = xr.Dataset(coords={
        "option": ("option", labels, {"long_name": f"option of {field}"}),
        "other": ("other", labels, {"long_name": f"the option compared with ({field})"}),
        "quantile": ("quantile", np.asarray(q), {"units": dimless,
                                                "long_name": "probability level"}),
    })
    ds["propensity_mean"] = ("option", prop.mean(axis=1), {
        "units": dimless, "long_name": "mean propensity over the plausible inputs"})
    ds["propensity_quantile"] = (("option", "quantile"), np.stack(
        [r.propensity_quantile.values for r in runs]), {
        "units": dimless, "long_name": "quantile of the propensity over the plausible inputs"})
    ds["u_star_quantile"] = (("option", "quantile"), np.stack(
        [r.u_star_quantile.values for r in runs]), {
        "units": "m/s", "long_name": "quantile of u0* over the plausible inputs"})
    ds["p_lower"] = (("option", "other"), p_lower, {
        "units": dimless, "long_name": "probability that option sticks less than other "
        "(lower propensity), paired draws"})
    ds["p_equal"] = (("option", "other"), p_equal, {
        "units": dimless, "long_name": "probability that option and other stick alike"})
    ds["deciding_input"] = (("option", "other"), deciding.astype(str), {
        "long_name": "uncertain input with the largest first-order index of the "
                     "difference of the propensities"})
    ds["deciding_index"] = (("option", "other"), index, {
        "units": dimless, "long_name": "first-order sensitivity index of the difference "
        "(binned given-data estimate)"})
    first = runs[0].attrs
    ds.attrs.update(
        title=f"Comparison of {field} options under uncertain inputs",
        agglomtool_version=__version__,
        compared_field=field,
        unit=FIELD_META[field][0] if field in FIELD_META else "",
        n_samples_per_option=int(n),
        seed=first["seed"],
        uncertain_inputs=first["uncertain_inputs"],
        distributions=first["distributions"],
        assumed_drawn=first.get("assumed_drawn", ""),
        assumed_not_drawn=first.get("assumed_not_drawn", ""),
        decided_threshold=DECIDED,
        scene=repr(scene),
    )
    ds.attrs["verdicts"] = "\n".join(verdicts(ds))
    return ds


def _input_text(name: str) -> str:
    """``"solid_ilmenite_asperity_height"`` (an assumed value's sample variable) -> ``"the
    asperity height of ilmenite, which the database assumes"``; a Scene field stays its
    name. Entry names hold no underscore (they are normalised to hyphens)."""
    kind, _, rest = name.partition("_")
    if name == "model_speed_choice":
        return "the choice of impact-speed model, which is assumed"
    if kind == "model" and "_" in rest:
        model, _, field = rest.partition("_")
        return f"the {field.replace('_', ' ')} of the {model} speed estimate, which is assumed"
    if kind in ("solid", "liquid") and "_" in rest:
        entry, _, field = rest.partition("_")
        if field.startswith("composition_wt_"):  # one oxide's factor of a melt's composition
            oxide = field[len("composition_wt_"):]
            return (f"the {oxide} content of {entry} (its composition, which the database "
                    "assumes)")
        words = _WORDS.get(field, field.replace("_", " "))
        return f"the {words} of {entry}, which the database assumes"
    return name


def _pct(p: float) -> str:
    """A share as a percentage, never rounded onto or across 0, 90 or 100 %: one decimal
    where whole numbers would hide which side of a threshold it lies."""
    text = f"{100 * p:.0f} %"
    if round(100 * p) in (0, 100, round(100 * DECIDED)) and 100 * p != round(100 * p):
        text = f"{100 * p:.1f} %"
    return text


def verdicts(ds: xr.Dataset) -> list[str]:
    """One sentence per pair of options, the better one first, that a designer can act on."""
    labels = list(ds.option.values)
    out = []
    for a in range(len(labels)):
        for b in range(a + 1, len(labels)):
            pl = float(ds.p_lower.values[a, b])
            pm = float(ds.p_lower.values[b, a])
            pe = float(ds.p_equal.values[a, b])
            lo, hi = (a, b) if pl >= pm else (b, a)
            p_less, p_more = max(pl, pm), min(pl, pm)
            what = (f"{labels[lo]} sticks less than {labels[hi]} in {_pct(p_less)} of "
                    f"plausible inputs, as much in {_pct(pe)}, more in {_pct(p_more)}")
            name = str(ds.deciding_input.values[lo, hi])
            idx = float(ds.deciding_index.values[lo, hi])
            if p_less >= DECIDED:
                out.append(f"decided: {what}.")
            elif pe >= DECIDED:
                out.append(f"no difference: {labels[a]} and {labels[b]} stick alike in "
                           f"{_pct(pe)} of plausible inputs.")
            else:
                why = (f"depends on {_input_text(name)} (first-order index {idx:.2f})"
                       if name and idx >= INDEX_MIN else
                       "no single input explains the difference (largest first-order index "
                       f"{idx:.2f}{': ' + _input_text(name) if name else ''})")
                n = int(ds.attrs.get("n_samples_per_option", 0))
                se = (p_less * (1.0 - p_less) / n) ** 0.5 if n else 0.0
                close = (f" ({_pct(p_less)} is within 3 Monte Carlo standard errors, "
                         f"{100 * se:.1f} %, of {_pct(DECIDED)}: more draws would tell)"
                         if n and abs(p_less - DECIDED) < 3.0 * se else "")
                out.append(f"not decided (a decision needs {_pct(DECIDED)}): {what}; {why}"
                           f"{close}.")
    return out
