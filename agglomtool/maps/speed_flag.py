"""Where a map's impact-speed model has no answer: the ``speed_flag`` output.

A bubble model has no answer where the bubbles cannot carry the excess gas or where they
and their wakes fill the bed; every model has none where the bed is not fluidized. A map
that crosses such a limit is computed where the model answers; the other points get a
``speed_flag`` naming the reason (:data:`agglomtool.bed.speed_models.SPEED_FLAGS`), NaN for
every output made of the impact speed (``u_typical``, ``St``, ``e_w``, ``propensity``,
``margin``), ``stage`` :data:`NO_STAGE` and ``agglomerated`` false, and the map warns once
how many points and why (:func:`warn_flagged`). A single point (a Scene) raises the
model's ``ValueError`` instead.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..bed.speed_models import IMPACT_SPEED_MODELS, SPEED_FLAGS, NoImpactSpeedWarning, partial_law
from ..bed.speeds import SpeedModel
from ..scene import Resolved, collision_outputs

__all__ = ["NO_STAGE", "flagged_collision_outputs", "warn_flagged", "SPEED_FLAG_OUTPUTS"]

#: The ``stage`` of a point with no impact speed: no collision was evaluated there.
NO_STAGE = -1
#: Outputs made of the impact speed: NaN where the model has no answer.
SPEED_FLAG_OUTPUTS = ("u_typical", "e_w", "St", "propensity", "margin")
#: The granular temperature [m2/s2] the collision kernels are given at the points with no
#: answer, so that they run as on the others; every output there is replaced afterwards.
_STANDIN = 1.0


def _preset_speeds(r: Resolved) -> np.ndarray | None:
    """Set ``r.speeds`` to its model's law where the model answers (a stand-in elsewhere)
    and return the flag, or None (``r`` untouched) where every element answers or the
    speed is given, not modelled."""
    family = r.v["speed"]
    names = [family] if isinstance(family, str) else np.unique(family).tolist()
    if not all(n in IMPACT_SPEED_MODELS for n in names):
        return None
    get = r._speed_inputs()
    law, flag = partial_law(family, lambda name: {k: get[k]() for k in
                                                  IMPACT_SPEED_MODELS[name].needs})
    theta = law.theta if flag is None else np.where(flag != 0, _STANDIN, law.theta)
    r.__dict__["speeds"] = SpeedModel("maxwellian", granular_temperature=theta)
    return flag


def flagged_collision_outputs(r: Resolved, u_star, nodes: int, out=None) -> dict:
    """``agglomtool.scene.collision_outputs`` of a map's block with ``speed_flag``:
    where the block's impact-speed model has no answer, the flag names why and the
    outputs made of the speed are NaN (see the module's description). A block where
    every point answers is computed as before, bitwise."""
    flag = _preset_speeds(r)
    c = collision_outputs(r, u_star, nodes, out)
    shape = np.shape(c["propensity"])
    if flag is None:
        c["speed_flag"] = np.broadcast_to(np.int8(0), shape)
        return c
    bad = np.broadcast_to(flag != 0, shape)
    for k in SPEED_FLAG_OUTPUTS:
        v = c[k]
        if isinstance(v, np.ndarray) and v.flags.writeable and v.shape == shape:
            np.copyto(v, np.nan, where=bad)  # the result's own block (a map in memory)
        else:
            c[k] = np.where(bad, np.nan, v)
    c["agglomerated"] = np.where(bad, False, c["agglomerated"])
    c["stage"] = np.where(bad, np.int8(NO_STAGE), c["stage"]).astype(np.int8)
    c["speed_flag"] = np.broadcast_to(flag, shape)
    return c


def flag_counts(flag) -> dict[int, int]:
    """``{code: points}`` of the nonzero codes of ``flag``."""
    flag = np.asarray(flag).reshape(-1)
    if not np.any(flag):  # the usual map: one pass, no count
        return {}
    counts = {int(c): int(np.count_nonzero(flag == c)) for c in SPEED_FLAGS if c != 0}
    return {c: n for c, n in counts.items() if n}


def flag_text(flag, what: str = "the map") -> str | None:
    """The sentence a map with flagged points warns (None where none is flagged)."""
    return counts_text(flag_counts(flag), int(np.size(flag)), what)


def counts_text(counts: dict, total: int, what: str = "the map") -> str | None:
    """:func:`flag_text` of a flag with the nonzero codes' ``counts`` (``{code: points}``,
    zeros allowed) of ``total`` points."""
    counts = {c: counts[c] for c in SPEED_FLAGS if c != 0 and counts.get(c)}
    if not counts:
        return None
    reasons = "; ".join(f"{n} {SPEED_FLAGS[c][0]} ({SPEED_FLAGS[c][1]})"
                        for c, n in counts.items())
    return (f"the impact-speed model has no answer at {sum(counts.values())} of {total} "
            f"points of {what}: {reasons}. Their propensity and every output made of "
            "the impact speed are NaN (agglomerated false, stage -1: neither outcome), "
            "and speed_flag says why; the other points are "
            f"computed. {' '.join(_REMEDY[c] for c in counts)}")


#: What gives the model an answer again, per flag code (a map may hold several).
_REMEDY = {
    1: "Where not fluidized: a U above U_mf (every model needs one).",
    2: "Where bubbles are too slow: a lower U, or another speed model.",
    3: "Where no emulsion is left: a lower U, a smaller wake_fraction, or another speed model.",
    4: "Outside the model: inputs within its domain, or another speed model.",
}


def warn_flagged(ds, stacklevel: int = 4, counts: dict | None = None) -> None:
    """Warn (:class:`~agglomtool.bed.speed_models.NoImpactSpeedWarning`) how many points of
    the map ``ds`` have no impact speed and why, if any. ``counts``: the map's
    ``speed_flag`` as ``{code: points}``, where known without reading the map (a store's
    run counts it block by block)."""
    if "speed_flag" not in ds:
        return
    text = (flag_text(ds["speed_flag"].values) if counts is None
            else counts_text(counts, sum(counts.values())))
    if text:
        warnings.warn(text, NoImpactSpeedWarning, stacklevel=stacklevel)
