"""The database's assumed values as uncertain inputs (``uncertain="assumed"``).

The materials database marks the values of an entry that are assumptions (an asperity
height nobody measured, a contact angle taken as perfect wetting) and states for each a
plausible law and the reason for it (:class:`agglomtool.materials.AssumedLaw`). Here those
laws become uncertain inputs of a Scene:

- each assumed value of each material the Scene uses is one uncertain input of its own,
  drawn from its own random stream named after the material and the field
  (``"solid ilmenite asperity_height"``). Two options that share a material (silica sand
  against ilmenite, and silica sand against olivine) therefore see the same draws of the
  sand's values: comparisons are paired, and grids use common random numbers;
- a solid's value is one value for the solid, not one per particle: where both particles
  are of the same solid, ``ha_i`` and ``ha_j`` are the same draw (the uncertainty is what
  the solid is like, not how two grains differ);
- the Scene's ``e`` is the mean of the two solids' restitution coefficients, drawn or not;
- a value the Scene sets itself (``ha_i``, ``e``, ``theta_deg`` given) is not drawn, and
  neither is one named uncertain by the caller: the caller's law wins;
- draws are truncated (by resampling, as for any uncertain input) to the Scene's valid
  range and, for asperity heights, to the range the tool finds plausible;
- the default impact-speed estimate's free coefficient (``fluctuation_ratio`` of the
  ``excess-gas`` model, ``SPEED_COEFFICIENT``) is drawn too where the scene leaves it at
  its default: the stream ``"model excess-gas fluctuation_ratio"``;
- so is the impact-speed model itself where the scene leaves the speed estimate at its
  default (``speed`` not given, ``SPEED_MODEL``; a model the user names is given, not
  drawn, and said so among the values not drawn): one of the models valid at the scene
  (:func:`agglomtool.impact_speed_methods`) per draw, with the weights of
  ``agglomtool.bed.speed_models.choice_weights``; the stream ``"model speed choice"``
  draws a uniform number that picks the model;
- the bubble models' coefficient (``wake_fraction``, ``WAKE_FRACTION``) where the scene
  uses a bubble model or draws the model, and leaves it at its default: the stream
  ``"model bubble wake_fraction"``;
- an assumed melt composition (law ``"logratio"``) is drawn as one uncertain input per
  oxide, the factor on that oxide's share (stream ``"liquid <entry> composition_wt
  <oxide>"``, lognormal of the stated 5-95 % band); each draw's composition is the
  entry's shares times their factors, rescaled to 100 wt %, and its viscosity, surface
  tension and density follow from the melt models at that composition (the viscosity
  model chosen by the entry's rule for each draw where the entry leaves it to the rule).
  A designer reading which input decides a comparison thus sees which oxide.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import ndtri

from .. import materials
from .._fields import DEFAULTS
from ..materials import COMPOSITION_LAW, AssumedLaw
from ..plausibility import ASPERITY_RANGE
from ..scene import COMPOSITION_KEY, FIELD_RANGES
from .distributions import Distribution, LogNormal, Uniform

__all__ = ["AssumedInput", "assumed_draws", "law_distribution", "scene_fields", "ASSUMED",
           "SPEED_COEFFICIENT", "SPEED_MODEL", "WAKE_FRACTION", "speed_model_weights",
           "COMPOSITION_KEY", "drawn_composition", "chosen_fields"]

#: The word that asks for every assumed value of the database.
ASSUMED = "assumed"

#: The standard normal's 95 % quantile: a lognormal's 5-95 % band spans 2 x this many
#: standard deviations of its log.
_Z95 = float(ndtri(0.95))

#: The free coefficient of the default impact-speed estimate ("excess-gas": an r.m.s.
#: particle velocity of ``fluctuation_ratio`` (U - U_mf)), drawn where a scene leaves it at
#: its default. Not a database value, so stated here.
SPEED_COEFFICIENT = AssumedLaw(
    field="fluctuation_ratio", law="lognormal", params=(0.3, 3.0),
    reason=("The excess-gas estimate takes the r.m.s. particle velocity equal to "
            "k (U - U_mf) with k = 1: an order-of-magnitude assumption, not a fitted "
            "correlation. k is drawn within a factor of about 3 either way (5-95 %: "
            "0.3-3; engineering judgement)."))
_COEFFICIENT_KEY = "model excess-gas fluctuation_ratio"

#: The choice of impact-speed model, drawn where a scene leaves the speed estimate at its
#: default: a uniform number on [0, 1) that picks a model by the cumulative weights of
#: :func:`speed_model_weights`.
SPEED_MODEL = AssumedLaw(
    field="speed", law="uniform", params=(0.0, 1.0),
    reason=("The impact-speed models rest on different mechanisms (excess gas, bubble "
            "wakes, a collisional energy balance) and no measured particle speeds are at "
            "hand to rank them (docs/speed_models.md): each mechanism valid at the scene "
            "has the same weight, shared by its correlations."))
_SPEED_MODEL_KEY = "model speed choice"

#: The bubble models' wake fraction (wake volume over bubble volume), drawn where a scene
#: may use a bubble model and leaves it at its default (0.25).
WAKE_FRACTION = AssumedLaw(
    field="wake_fraction", law="lognormal", params=(0.15, 0.4),
    reason=("Kunii and Levenspiel (1991), example 5.1, read f_w = 0.24 for 300 um solids "
            "off their fig. 5.8 (Rowe and Partridge's X-ray data; a figure read by eye); "
            "the figure's spread over sizes and solids was not at hand: drawn within a "
            "factor of about 1.6 either way (5-95 %: 0.15-0.4; engineering judgement)."))
_WAKE_KEY = "model bubble wake_fraction"


def speed_model_weights(values: dict) -> dict[str, float]:
    """The models drawn for the scene ``values`` and their probabilities: those valid at
    the scene (:func:`agglomtool.impact_speed_methods`, calibrated), weighted by
    ``agglomtool.bed.speed_models.choice_weights``."""
    from ..bed.speed_models import choice_weights
    from ..scene import Resolved, Scene, impact_speed_methods

    try:
        return choice_weights(impact_speed_methods(Scene(**values)))
    except ValueError as exc:  # none valid: say why, with the scene's own speed's reason
        try:
            _ = Resolved(values).u_typical  # raises where the scene has no speed
        except ValueError as why:
            raise ValueError(f"{exc}; the scene's own ({values.get('speed')}): {why}") from None
        raise


def chosen_fields(scene) -> tuple[str, ...]:
    """The fields of ``scene`` (a :class:`~agglomtool.Scene`) whose value the user chose
    although the Scene would otherwise derive it: ``("speed",)`` where the user named the
    impact-speed law or model (``speed=None`` derives it: an assumption). What
    :func:`assumed_draws` takes as ``chosen``."""
    return ("speed",) if getattr(scene, "_speed_given", True) else ()


#: database field -> the Scene field it sets, per side (None: the field has no Scene field).
_SOLID_FIELDS = {"asperity_height": ("ha_i", "ha_j"), "restitution_dry": ("e", "e")}
_LIQUID_FIELDS = {"theta_deg": "theta_deg"}


@dataclass(frozen=True)
class AssumedInput:
    """One assumed database value drawn as an uncertain input."""

    key: str  #: its random stream's name: ``"<kind> <entry> <field>"``
    kind: str  #: ``"solid"`` or ``"liquid"``
    entry: str  #: the database entry's name
    field: str  #: the database field
    law: AssumedLaw  #: the law the database states
    dist: Distribution  #: that law as a distribution, SI
    #: the Scene field's range its draws are truncated to: ``(lo, hi, lo_open, hi_open)``
    bounds: tuple
    #: the range as text, for messages
    range_text: str
    #: the value used where it is not drawn (the database's, or the model's default), SI
    value: float


def law_distribution(law: AssumedLaw) -> Distribution:
    """The distribution of an :class:`~agglomtool.materials.AssumedLaw` (SI).

    ``lognormal``: ``ln X`` normal with its 5 and 95 % quantiles at ``ln p05`` and
    ``ln p95`` (median ``sqrt(p05 p95)``); ``uniform``: uniform on ``[lo, hi]``;
    ``logratio``: the lognormal of one oxide's factor.
    """
    a, b = law.params
    if law.law in ("lognormal", COMPOSITION_LAW):  # a composition's: of each oxide's factor
        la, lb = np.log(a), np.log(b)
        return LogNormal.from_log(0.5 * (la + lb), (lb - la) / (2.0 * _Z95))
    if law.law == "uniform":
        return Uniform(a, b)
    raise ValueError(f"law = {law.law!r} is not one of 'lognormal', 'uniform'")


def _scene_range(scene_field: str) -> tuple[tuple, str]:
    """The range the draws of a Scene field are truncated to: where the Scene accepts
    them and, for asperity heights, the range the tool finds plausible (a lognormal's
    upper tail would otherwise draw the implausible heights it warns about)."""
    lo, hi, lo_open, hi_open = FIELD_RANGES[scene_field]
    lo, hi = -np.inf if lo is None else lo, np.inf if hi is None else hi
    if scene_field in ("ha_i", "ha_j"):
        lo, hi = max(lo, ASPERITY_RANGE[0]), min(hi, ASPERITY_RANGE[1])
    text = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    return (lo, hi, lo_open, hi_open), text


def _uses(values: dict):
    """The entries a scene takes values from: ``(solid_i, solid_j, liquid entry)``."""
    si = materials.solid(str(values["solid_i"]))
    sj = materials.solid(str(values.get("solid_j") or values["solid_i"]))
    return si, sj, materials.liquid_entry(str(values["liquid"]))


def assumed_draws(values: dict, given=(), chosen=()) -> tuple[dict[str, AssumedInput],
                                                               list[str]]:
    """The assumed values a scene uses, as uncertain inputs.

    Parameters
    ----------
    values : dict
        The Scene's field values (:meth:`agglomtool.Scene.values`).
    given : iterable of str
        Scene fields the caller already makes uncertain: the database values they would
        replace are not drawn.
    chosen : iterable of str
        Scene fields the user chose where the Scene would derive them
        (``chosen_fields``): a ``speed`` model chosen is given, not drawn (its own
        coefficients still are, where left at their defaults), and ``not_drawn`` says so.
        Without it (a plain dict of values) the model is drawn where the values hold the
        default estimate.

    Returns
    -------
    inputs : dict of str to AssumedInput
        Stream key -> the input, in a stable order (solid i, solid j, liquid).
    not_drawn : list of str
        ``"<entry> <field>"`` of the assumed values used but not drawn, with why.
    """
    given = set(given)
    si, sj, liquid = _uses(values)
    inputs: dict[str, AssumedInput] = {}
    not_drawn: list[str] = []

    def law_of(entry, field_name):
        return next((x for x in entry.uncertainty if x.field == field_name), None)

    def add(kind, entry, field_name, scene_field):
        law = law_of(entry, field_name)
        if law is None:
            return
        key = f"{kind} {entry.name} {field_name}"
        if key not in inputs:
            bounds, text = _scene_range(scene_field)
            inputs[key] = AssumedInput(key, kind, entry.name, field_name, law,
                                       law_distribution(law), bounds, text,
                                       float(getattr(entry, field_name)))

    def add_composition(entry):
        law = law_of(entry, "composition_wt")
        if law is None or entry.composition_wt is None:
            not_drawn.append(f"{entry.name} composition_wt (no law stated)")
            return
        dist = law_distribution(law)
        for oxide in entry.composition_wt:
            key = f"liquid {entry.name} composition_wt {oxide}"
            inputs[key] = AssumedInput(key, "liquid", entry.name, f"composition_wt {oxide}",
                                       law, dist, (0.0, np.inf, True, True), "(0, inf)", 1.0)

    for side, sol in ((0, si), (1, sj)):
        for field_name in sol.assumed:
            if field_name not in _SOLID_FIELDS:
                not_drawn.append(f"{sol.name} {field_name} (no Scene field takes it)")
                continue
            scene_field = _SOLID_FIELDS[field_name][side]
            if values.get(scene_field) is not None or scene_field in given:
                continue  # the scene, or the caller's own law, sets it
            add("solid", sol, field_name, scene_field)
    for field_name in liquid.assumed:
        if field_name == "composition_wt":
            add_composition(liquid)
            continue
        if field_name not in _LIQUID_FIELDS:
            not_drawn.append(f"{liquid.name} {field_name} (not a number: no law yet)")
            continue
        scene_field = _LIQUID_FIELDS[field_name]
        if values.get(scene_field) is not None or scene_field in given:
            continue
        add("liquid", liquid, field_name, scene_field)

    def add_model(key, model, law):  # a model's coefficient left at its default: drawn
        if law.field not in given and values.get(law.field) == DEFAULTS[law.field]:
            bounds, text = _scene_range(law.field)
            inputs[key] = AssumedInput(key, "model", model, law.field, law,
                                       law_distribution(law), bounds, text,
                                       float(values[law.field]))

    if values.get("speed") == "excess-gas":
        add_model(_COEFFICIENT_KEY, "excess-gas", SPEED_COEFFICIENT)
    speed = values.get("speed")
    if "speed" in chosen and isinstance(speed, str):
        from ..bed.speed_models import IMPACT_SPEED_MODELS

        if speed in IMPACT_SPEED_MODELS:
            not_drawn.append(f"impact-speed model speed = {speed!r} (chosen by the user: "
                             "given, not drawn)")
    elif _COEFFICIENT_KEY in inputs:  # the default estimate, left at its default: the model
        key = _SPEED_MODEL_KEY
        inputs[key] = AssumedInput(key, "model", "speed", "speed", SPEED_MODEL,
                                   law_distribution(SPEED_MODEL), (0.0, 1.0, False, True),
                                   "[0, 1)", 0.0)
    if str(values.get("speed")).startswith("bubble-") or _SPEED_MODEL_KEY in inputs:
        add_model(_WAKE_KEY, "bubble", WAKE_FRACTION)
    return inputs, list(dict.fromkeys(not_drawn))


def scene_fields(values: dict, draws: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The Scene fields set by the assumed values drawn (``draws``: stream key -> values).

    ``ha_i``/``ha_j`` from the solids' asperity heights (one draw where the solids are the
    same), ``e`` the mean of the two solids' restitution coefficients (drawn or database),
    ``theta_deg`` from the liquid's contact angle, and under ``COMPOSITION_KEY`` the
    melt's drawn compositions (oxide -> wt % arrays; not a Scene field).
    """
    si, sj, liquid = _uses(values)
    out: dict[str, Any] = {}  # arrays, and a composition (oxide -> arrays)
    for side, sol in (("i", si), ("j", sj)):
        key = f"solid {sol.name} asperity_height"
        if key in draws:
            out[f"ha_{side}"] = draws[key]
    ki, kj = (f"solid {s.name} restitution_dry" for s in (si, sj))
    if ki in draws or kj in draws:
        e_i = draws.get(ki, si.restitution_dry)
        e_j = draws.get(kj, sj.restitution_dry)
        out["e"] = 0.5 * (e_i + e_j)
    key = f"liquid {liquid.name} theta_deg"
    if key in draws:
        out["theta_deg"] = draws[key]
    if _COEFFICIENT_KEY in draws:
        out["fluctuation_ratio"] = draws[_COEFFICIENT_KEY]
    if _WAKE_KEY in draws:
        out["wake_fraction"] = draws[_WAKE_KEY]
    if _SPEED_MODEL_KEY in draws:
        weights = speed_model_weights(values)
        names = np.array(list(weights))
        edges = np.cumsum(list(weights.values()))[:-1]
        out["speed"] = names[np.searchsorted(edges, draws[_SPEED_MODEL_KEY], side="right")]
    prefix = f"liquid {liquid.name} composition_wt "
    factors = {k[len(prefix):]: v for k, v in draws.items() if k.startswith(prefix)}
    if factors and liquid.composition_wt is not None:
        out[COMPOSITION_KEY] = drawn_composition(liquid.composition_wt, factors)
    return out


def drawn_composition(base, factors: dict) -> dict:
    """Compositions [wt %] from an entry's ``base`` shares and each oxide's ``factors``
    (arrays of one shape; an oxide without one keeps factor 1), rescaled to 100 wt %."""
    scaled = {k: w * np.asarray(factors.get(k, 1.0), dtype=float) for k, w in base.items()}
    total = sum(scaled.values())
    return {k: 100.0 * v / total for k, v in scaled.items()}
