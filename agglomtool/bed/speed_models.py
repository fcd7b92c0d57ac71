"""Impact-speed models: the impact-speed law of a pair from the bed's operating conditions.

Each model turns what a scene knows of the bed (gas velocities, the bed material, the
bed's geometry, the height of interest) into one of the distributions of
:mod:`agglomtool.bed.speeds` with its parameters. The registry
:data:`IMPACT_SPEED_MODELS` lists them by the name a scene's ``speed`` field takes;
:func:`speed_law` evaluates one; :func:`agglomtool.impact_speed_methods` lists those valid
at a scene.

``"excess-gas"``
    An order-of-magnitude estimate: a Maxwellian whose r.m.s. velocity per component is
    ``fluctuation_ratio (U - U_mf)``. No correlation behind it.
``"bubble-darton"``, ``"bubble-mori-wen"``
    The circulation that bubble wakes drive: bubble size at the height of interest
    (Darton et al. 1977, or Mori and Wen 1975), their rise velocity (Davidson and
    Harrison), bubble fraction and solids downflow (Kunii and Levenspiel 1991); the
    Maxwellian with the granular temperature of that vertical velocity field
    (:func:`.hydrodynamics.granular_temperature_bubble_wake`).
``"collisional-balance"``
    The Maxwellian with the granular temperature at which inelastic collisions dissipate
    the excess gas's power (kinetic theory of granular flow:
    :func:`.hydrodynamics.granular_temperature_collisional_balance`).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit, prange, vectorize

from .._jit import CACHE
from .._validate import PlausibilityWarning
from . import hydrodynamics as hd
from .speeds import SpeedModel

__all__ = ["ImpactSpeedModel", "IMPACT_SPEED_MODELS", "speed_law", "bubble_state",
           "MECHANISMS", "choice_weights", "mixed_law", "PER_PARTICLE", "bed_mean_particle",
           "SPEED_FLAGS", "NoImpactSpeedWarning", "speed_domain", "speed_law_partial",
           "partial_law"]


@dataclass(frozen=True)
class ImpactSpeedModel:
    """One impact-speed model of the registry.

    ``needs`` names the inputs :func:`speed_law` reads (keys of its ``inputs``);
    ``law(inputs)`` returns the :class:`~agglomtool.bed.speeds.SpeedModel`.
    """

    name: str
    summary: str
    reference: str
    needs: tuple[str, ...]
    law: Callable[[dict], SpeedModel]


@vectorize(cache=CACHE)
def _excess_theta(U, Umf, ratio):  # pragma: no cover - compiled
    """``(ratio (U - Umf))**2`` of one element where ``U - Umf`` is not ``<= 0`` (NaN
    included, as numpy's formula gives it); -1 where it is (no square is negative): the
    caller then takes the plain path, whose error names the value. One pass, no
    temporaries; the same operations as the formula, so the same numbers."""
    return _excess_theta_one(U, Umf, ratio)


@njit(inline="always", cache=CACHE)
def _excess_theta_one(U, Umf, ratio):  # pragma: no cover - compiled
    """The rule of :func:`_excess_theta`, written once for it and :func:`_excess_pass` (a
    selection, not a branch: a loop of it vectorizes)."""
    excess = U - Umf
    t = ratio * excess
    return -1.0 if excess <= 0.0 else t * t


@njit(parallel=True, cache=CACHE)
def _excess_pass(ins, st, shp, plan, out, stats):  # pragma: no cover - compiled
    """:func:`_excess_theta` of a map's elements on every thread (``ins``: U, Umf, ratio,
    read by their broadcast steps: :func:`.hydrodynamics._map_inputs`) into ``out``;
    ``stats[blk, 0]``: how many of block ``blk``'s elements it refused (-1 written)."""
    for blk in prange(stats.shape[0]):  # each block a serial loop (compiles faster)
        _excess_block(ins, st, shp, plan, out, stats, blk)


@njit(cache=CACHE)
def _excess_block(ins, st, shp, plan, out, stats, blk):  # pragma: no cover - compiled
    """Block ``blk`` of :func:`_excess_pass` (the pieces of :func:`.hydrodynamics._plan`)."""
    chunk, per_row, per_block = plan
    last = shp.shape[0] - 1
    row_len = shp[last]
    pieces = (out.shape[0] // row_len) * per_row
    s0, s1, s2 = st[0, last], st[1, last], st[2, last]
    x0, x1, x2 = ins
    off = np.empty(3, np.int64)
    refused = 0
    for piece in range(blk * per_block, min(pieces, (blk + 1) * per_block)):
        row = piece // per_row
        j0 = (piece - row * per_row) * chunk
        hd._row_offsets(off, st, shp, row, j0)
        o0, o1, o2 = off[0], off[1], off[2]
        k = row * row_len + j0
        m = min(row_len - j0, chunk)
        o = out[k:k + m]
        if s0 == 1 and s1 == 0 and s2 == 0:
            # a map's usual row: U runs along it, U_mf and the ratio do not (contiguous
            # views: a loop the compiler vectorizes)
            u = x0[o0:o0 + m]
            Umf = x1[o1]
            ratio = x2[o2]
            for j in range(m):
                t = _excess_theta_one(u[j], Umf, ratio)
                refused += t < 0.0
                o[j] = t
        else:
            for j in range(m):
                t = _excess_theta_one(x0[o0 + j * s0], x1[o1 + j * s1], x2[o2 + j * s2])
                refused += t < 0.0
                o[j] = t
    stats[blk, 0] = refused


def _excess_gas(x) -> SpeedModel:
    U, Umf = np.asarray(x["U"], float), np.asarray(x["Umf"], float)
    ratio = np.asarray(x["fluctuation_ratio"], float)
    # A map's arrays: one compiled pass on every thread (the same operations per element:
    # the same numbers), which counts the refused elements as it goes.
    shape = hd._map_shape(U, Umf, ratio)
    ins = None if shape is None else hd._map_inputs((U, Umf, ratio), shape)
    if shape is not None and ins is not None:
        theta = np.empty(shape)
        if not hd._run(_excess_pass, *ins, theta.reshape(-1)).any():
            return SpeedModel("maxwellian", granular_temperature=theta)
    else:
        # (the compiled comparison flags a NaN as an invalid operation, numpy's does not:
        # that flag is not a warning here, as it was not with numpy)
        with np.errstate(invalid="ignore"):
            theta = np.asarray(_excess_theta(U, Umf, ratio))
        # the smallest value ignoring NaN: the sentinel -1 wherever U does not exceed U_mf
        if theta.size and not np.fmin.reduce(theta, axis=None) < 0.0:
            return SpeedModel("maxwellian", granular_temperature=theta)
    excess = U - Umf
    if np.any(excess <= 0.0):
        bad = float(np.broadcast_to(U, excess.shape)[excess <= 0.0][0])
        raise ValueError(
            f"U = {bad:g} m/s does not exceed U_mf: the excess-gas speed estimate "
            "needs a fluidized bed (U_Umf > 1 or U > U_mf), or give u0 or "
            "granular_temperature"
        )
    theta = (np.asarray(x["fluctuation_ratio"], float) * excess) ** 2
    return SpeedModel("maxwellian", granular_temperature=theta)


def bubble_state(x: dict, correlation: str) -> dict:
    """The bubbles at the height of interest: ``d_b`` [m], ``u_b`` [m/s], ``delta`` [-].

    ``x`` holds ``U``, ``Umf``, ``d_p``, ``rho_p``, ``rho_g``, ``eps`` (the emulsion's
    voidage), ``column_diameter``, ``orifice_area`` and ``height`` (SI);
    ``correlation`` is ``"darton"`` or ``"mori-wen"``.
    """
    U, Umf, D_t = x["U"], x["Umf"], x["column_diameter"]
    d_b = _bubble_diameter(x, correlation)
    u_b = hd.bubble_velocity_davidson_harrison(U, Umf, d_b, D_t)
    delta = hd.bubble_fraction_kunii_levenspiel(U, Umf, u_b, x["eps"])
    return {"d_b": d_b, "u_b": u_b, "delta": delta}


def _bubble_diameter(x: dict, correlation: str):
    """The bubble diameter at the height of interest [m] by ``correlation``."""
    U, Umf, h, A0 = x["U"], x["Umf"], x["height"], x["orifice_area"]
    if correlation == "darton":
        return hd.bubble_diameter_darton(U, Umf, h, A0, d_p=x["d_p"], rho_p=x["rho_p"],
                                         rho_g=x["rho_g"])
    return hd.bubble_diameter_mori_wen(U, Umf, h, x["column_diameter"], A0, d_p=x["d_p"])


def _bubble(correlation: str):
    def law(x) -> SpeedModel:
        # on a map's arrays: compiled parallel passes (None where the plain path must
        # speak: an element outside the domain, a refused input)
        theta = hd.bubble_theta_map(correlation, x["U"], x["Umf"], x["height"],
                                    x["orifice_area"], x["column_diameter"], x["eps"],
                                    x["wake_fraction"], d_p=x["d_p"], rho_p=x["rho_p"],
                                    rho_g=x["rho_g"])
        if theta is not None:
            return SpeedModel("maxwellian", granular_temperature=theta)
        # bubble_state's chain, the steps after the bubble size in one compiled pass
        theta = hd.granular_temperature_bubbles(
            x["U"], x["Umf"], _bubble_diameter(x, correlation), x["column_diameter"],
            x["eps"], x["wake_fraction"])
        return SpeedModel("maxwellian", granular_temperature=theta)

    return law


def _collisional(x) -> SpeedModel:
    theta = hd.collisional_theta_map(x["U"], x["Umf"], x["d_p"], x["rho_p"], x["rho_g"],
                                     x["eps"], x["e"])
    if theta is not None:  # a map's arrays, in a compiled parallel pass
        return SpeedModel("maxwellian", granular_temperature=theta)
    theta = hd.granular_temperature_collisional_balance(
        x["U"], x["Umf"], x["d_p"], x["rho_p"], x["rho_g"], x["eps"], x["e"])
    return SpeedModel("maxwellian", granular_temperature=theta)


_BUBBLE_NEEDS = ("U", "Umf", "d_p", "rho_p", "rho_g", "eps", "column_diameter",
                 "orifice_area", "height", "wake_fraction")
_BUBBLE_REF = ("Darton et al. (1977) Trans. IChemE 55:274; Mori and Wen (1975) AIChE J. "
               "21:109; Davidson and Harrison (1963); Kunii and Levenspiel (1991), "
               "Fluidization Engineering, ch. 5-6")

#: The impact-speed models by name (the ``speed`` names that need no speed of their own).
IMPACT_SPEED_MODELS = {
    "excess-gas": ImpactSpeedModel(
        "excess-gas",
        "Maxwellian, r.m.s. velocity per component = fluctuation_ratio (U - U_mf): an "
        "order-of-magnitude assumption, not a correlation",
        "none (an assumption)", ("U", "Umf", "fluctuation_ratio"), _excess_gas),
    "bubble-darton": ImpactSpeedModel(
        "bubble-darton",
        "Maxwellian with the granular temperature of the solids' circulation by bubble "
        "wakes; bubbles of Darton et al. (1977) at the height of interest",
        _BUBBLE_REF, _BUBBLE_NEEDS, _bubble("darton")),
    "bubble-mori-wen": ImpactSpeedModel(
        "bubble-mori-wen",
        "as bubble-darton, with the bubbles of Mori and Wen (1975) (a maximum size set by "
        "the column)",
        _BUBBLE_REF, _BUBBLE_NEEDS, _bubble("mori-wen")),
    "collisional-balance": ImpactSpeedModel(
        "collisional-balance",
        "Maxwellian with the granular temperature at which inelastic collisions dissipate "
        "the power of the excess gas (kinetic theory of granular flow): an upper bound",
        "Lun et al. (1984) J. Fluid Mech. 140:223; Gidaspow (1994), Multiphase Flow and "
        "Fluidization, ch. 9; Carnahan and Starling (1969)",
        ("U", "Umf", "d_p", "rho_p", "rho_g", "eps", "e"), _collisional),
}


#: Values of a map's ``speed_flag`` output: why the impact-speed model has no answer at a
#: point (0: it has one). ``{code: (CF flag meaning, sentence)}``.
SPEED_FLAGS = {
    0: ("computed", "the impact-speed model has an answer"),
    1: ("not_fluidized", "U does not exceed U_mf: the model needs a fluidized bed"),
    2: ("bubbles_too_slow", "bubble fraction >= 1: bubbles rising this slowly cannot carry "
                            "U - U_mf, outside the bubbling-bed model"),
    3: ("no_emulsion", "bubbles and their wakes fill the bed: no emulsion is left for the "
                       "solids' downflow (U - U_mf beyond a bubbling bed)"),
    4: ("outside_model", "an input outside the model's domain (e.g. a restitution of 1 "
                         "for the collisional balance)"),
}


class NoImpactSpeedWarning(UserWarning):
    """Points of a map where the impact-speed model has no answer: their ``speed_flag``
    says why and their propensity is NaN; the rest of the map is computed."""


def speed_domain(name: str, inputs: dict) -> np.ndarray:
    """Where model ``name`` has an answer, per element of its inputs' broadcast: an int8
    array of :data:`SPEED_FLAGS` codes (0 where :func:`speed_law` answers). The same
    checks as the model's own (the bubble models' in one compiled pass,
    :func:`.hydrodynamics.bubble_domain`); plausibility warnings are not given here."""
    model = IMPACT_SPEED_MODELS[name]
    arrays = {k: np.asarray(inputs[k], dtype=float) for k in model.needs}
    shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    with np.errstate(invalid="ignore"):
        excess = np.broadcast_to(arrays["U"] - arrays["Umf"], shape)
        flag = np.where(excess > 0.0, 0, 1).astype(np.int8)
    ok = flag == 0
    if name.startswith("bubble-") and ok.any():
        sub = {k: np.broadcast_to(a, shape)[ok] for k, a in arrays.items()}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            d_b = _bubble_diameter(sub, name[len("bubble-"):])
        flag[ok] = hd.bubble_domain(sub["U"] - sub["Umf"], sub["Umf"], d_b,
                                    sub["column_diameter"], sub["eps"], sub["wake_fraction"])
    elif name == "collisional-balance":
        flag[ok & (np.broadcast_to(arrays["e"], shape) >= 1.0)] = 4
    return flag


def speed_law_partial(name: str, inputs: dict) -> tuple[SpeedModel, np.ndarray | None]:
    """:func:`speed_law` for a map: ``(law, flag)``, the law where the model answers and
    NaN where it has none, ``flag`` the :func:`speed_domain` codes there, or None where
    every element answers (the law is then :func:`speed_law`'s, unchanged).

    An error that no element's domain explains (a bad input of the whole map) is raised.
    Where some elements have no answer, the plausibility warnings the first attempt gave
    stand (they are about the map's inputs) and the law is computed again on the
    answering elements alone, without repeating them."""
    on_map = _partial_on_map(name, inputs)
    if on_map is not None:  # a map's arrays: the law and its flag in one compiled pass
        theta, flag = on_map
        return SpeedModel("maxwellian", granular_temperature=theta), flag
    try:
        return speed_law(name, inputs), None
    except ValueError:
        flag = speed_domain(name, inputs)
        if not flag.any():
            raise
    ok = flag == 0
    theta = np.full(flag.shape, np.nan)
    if ok.any():
        sub = {k: (np.broadcast_to(np.asarray(v, dtype=float), flag.shape)[ok]
                   if np.ndim(v) else v) for k, v in inputs.items()}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            law = speed_law(name, sub)
        theta[ok] = law.theta
    return SpeedModel("maxwellian", granular_temperature=theta), flag


def _partial_on_map(name: str, inputs: dict):
    """:func:`speed_law_partial`'s ``(theta, flag)`` from the compiled map passes of
    :mod:`.hydrodynamics` (the law, the flag and the warnings in one pass; the same
    numbers, codes and warnings), or None where they do not apply (not a map's arrays, an
    input refused otherwise than by the model's domain, the excess-gas estimate, whose
    plain pass costs little)."""
    if name not in ("bubble-darton", "bubble-mori-wen", "collisional-balance"):
        return None
    x = {k: inputs[k] for k in IMPACT_SPEED_MODELS[name].needs}
    if name == "collisional-balance":
        return hd.collisional_theta_map(x["U"], x["Umf"], x["d_p"], x["rho_p"], x["rho_g"],
                                        x["eps"], x["e"], partial=True)
    return hd.bubble_theta_map(name[len("bubble-"):], x["U"], x["Umf"], x["height"],
                               x["orifice_area"], x["column_diameter"], x["eps"],
                               x["wake_fraction"], d_p=x["d_p"], rho_p=x["rho_p"],
                               rho_g=x["rho_g"], partial=True)


def partial_law(names, inputs_of) -> tuple[SpeedModel, np.ndarray | None]:
    """:func:`speed_law_partial` of model ``names`` (a name, or an array of names per
    element as ``mixed_law`` takes them; ``inputs_of(name)`` the model's inputs):
    ``(law, flag or None)``. Where every element answers, the law is :func:`speed_law`'s
    or ``mixed_law``'s, bitwise."""
    if isinstance(names, str):
        return speed_law_partial(names, inputs_of(names))
    names = np.asarray(names)
    theta = flag = None
    for name in dict.fromkeys(names.ravel().tolist()):
        law, f = speed_law_partial(name, inputs_of(name))
        t = np.asarray(law.theta, dtype=float)
        sel = names == name
        theta = np.where(sel, t, np.nan if theta is None else theta)
        if f is not None or flag is not None:
            f = np.zeros((), np.int8) if f is None else f
            flag = np.where(sel, f, np.int8(0) if flag is None else flag).astype(np.int8)
    return SpeedModel("maxwellian", granular_temperature=theta), flag


def speed_law(name: str, inputs: dict) -> SpeedModel:
    """The impact-speed law of model ``name`` (a key of :data:`IMPACT_SPEED_MODELS`) with
    the ``inputs`` it needs (SI arrays that broadcast; see each model's ``needs``)."""
    try:
        model = IMPACT_SPEED_MODELS[name]
    except KeyError:
        raise ValueError(f"speed model {name!r} is not one of "
                         f"{sorted(IMPACT_SPEED_MODELS)}") from None
    return model.law(inputs)


#: The mechanism each model estimates the particles' agitation by. Two models of one
#: mechanism (the two bubble-size correlations) are two estimates of the same physics.
MECHANISMS = {"excess-gas": "excess gas (an assumption)", "bubble-darton": "bubble wakes",
              "bubble-mori-wen": "bubble wakes",
              "collisional-balance": "collisional energy balance"}


def choice_weights(names) -> dict[str, float]:
    """The probability of each impact-speed model of ``names`` (the models valid at a
    scene) when the model choice is drawn as an uncertain input.

    Each mechanism of :data:`MECHANISMS` among ``names`` has the same weight, shared
    equally by its models: no measured particle speeds are at hand to rank the mechanisms
    (docs/speed_models.md, "Measured values"), and two correlations of one mechanism
    (Darton's and Mori and Wen's bubble sizes, which agree within a few per cent in a
    Geldart B bed) should not count twice.
    """
    names = [n for n in names if n in IMPACT_SPEED_MODELS]
    if not names:
        raise ValueError("no impact-speed model of the registry is valid at this scene: "
                         "nothing to draw the model choice from")
    groups: dict[str, list[str]] = {}
    for n in names:
        groups.setdefault(MECHANISMS[n], []).append(n)
    return {n: 1.0 / (len(groups) * len(groups[MECHANISMS[n]])) for n in names}


def mixed_law(names, inputs_of) -> SpeedModel:
    """The impact-speed law where the model differs between elements: ``names`` an array
    of model names (one per element, broadcasting with the inputs), ``inputs_of(name)``
    the inputs of model ``name``. Every model of the registry gives a Maxwellian, so the
    mixture is the Maxwellian whose granular temperature is, element by element, that of
    the element's model. Each model present is evaluated on every element and then
    picked (the models cost little beside the collisions)."""
    names = np.asarray(names)
    theta = None
    for name in dict.fromkeys(names.ravel().tolist()):
        law = speed_law(name, inputs_of(name))
        if law.family != "maxwellian":  # pragma: no cover - every registry model is
            raise ValueError(f"speed model {name!r} is not a Maxwellian: cannot be mixed")
        t = np.asarray(law.theta, dtype=float)
        theta = (np.where(names == name, t, np.nan) if theta is None
                 else np.where(names == name, t, theta))
    return SpeedModel("maxwellian", granular_temperature=theta)


#: Models whose law depends on the particle (its size, density and restitution), not on
#: the bed's gas and geometry alone: in a bed of several classes they are evaluated once,
#: for the bed's mean particle (:func:`bed_mean_particle`), so that every pair of classes
#: shares one granular temperature, as the bed's collision-rate weighting assumes.
PER_PARTICLE = ("collisional-balance",)


def bed_mean_particle(n, d, rho, e_pair, W):
    """The mean particle of a bed for a :data:`PER_PARTICLE` model: ``(d_p, rho_p, e)``.

    ``n`` (..., K) number densities, ``d`` (K,) diameters [m], ``rho`` (K,) densities
    [kg/m3] of the classes, ``e_pair`` (..., K, K) the restitution of each ordered pair,
    ``W`` (..., K, K) the pairs' collision-rate weights (summing to 1). ``d_p`` is the
    Sauter mean diameter (as for the bed's ``U_mf``), ``rho_p`` the mean density by
    volume, and ``e`` the restitution whose ``1 - e**2`` is the collision-rate weighted
    mean of the pairs' (the collisional dissipation is linear in ``1 - e**2``). A bed of
    one class is that class's particle.
    """
    n, d, rho = (np.asarray(x, dtype=float) for x in (n, d, rho))
    vol = n * d**3
    d_p = vol.sum(-1) / (n * d**2).sum(-1)
    rho_p = (vol * rho).sum(-1) / vol.sum(-1)
    loss = (np.asarray(W, float) * (1.0 - np.asarray(e_pair, float) ** 2)).sum((-2, -1))
    return d_p, rho_p, np.sqrt(1.0 - loss)

