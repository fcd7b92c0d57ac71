"""Which collision inputs may be uncertain, where each one lives, its unit and its range.

One table, :data:`UNCERTAIN_INPUTS`, maps the names accepted in ``uncertain=`` to the object
and field of :func:`agglomtool.collide` they replace, the SI unit (a string pint can
parse), a readable name, and the physical range that truncation enforces (the same ranges
the input dataclasses validate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..api import collide
from ..inputs import Bed, Gas, Liquid, Particle

__all__ = ["InputSpec", "UNCERTAIN_INPUTS", "evaluate_e_w"]

INF = math.inf


@dataclass(frozen=True)
class InputSpec:
    """Where an uncertain input goes, and its physical range ``lo < x < hi``."""

    target: str  # "p_i", "p_j", "liquid", "gas", "bed" or "call" (a keyword of collide)
    field: str
    units: str
    long_name: str
    lo: float
    hi: float
    lo_open: bool
    hi_open: bool

    def range_text(self) -> str:
        """The physical range as text, e.g. ``(0, inf) m``."""
        return (
            f"{'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}"
            f"{')' if self.hi_open else ']'} {self.units}"
        )


def _spec(target, field, units, long_name, lo=0.0, hi=INF, lo_open=True, hi_open=True):
    return InputSpec(target, field, units, long_name, lo, hi, lo_open, hi_open)


#: name in ``uncertain=`` -> InputSpec
UNCERTAIN_INPUTS: dict[str, InputSpec] = {
    "d_i": _spec("p_i", "d", "m", "solid diameter of particle i"),
    "d_j": _spec("p_j", "d", "m", "solid diameter of particle j"),
    "rho_i": _spec("p_i", "rho", "kg/m^3", "solid density of particle i"),
    "rho_j": _spec("p_j", "rho", "kg/m^3", "solid density of particle j"),
    "h0_i": _spec("p_i", "h0", "m", "coating thickness of particle i", lo_open=False),
    "h0_j": _spec("p_j", "h0", "m", "coating thickness of particle j", lo_open=False),
    "ha_i": _spec("p_i", "ha", "m", "asperity height of particle i", lo_open=False),
    "ha_j": _spec("p_j", "ha", "m", "asperity height of particle j", lo_open=False),
    "mu_l": _spec("liquid", "mu", "Pa s", "liquid viscosity"),
    "gamma": _spec("liquid", "gamma", "N/m", "liquid surface tension"),
    "rho_l": _spec("liquid", "rho", "kg/m^3", "liquid density"),
    "theta_deg": _spec("liquid", "theta_deg", "degree", "contact angle", 0.0, 90.0, False),
    "mu_g": _spec("gas", "mu", "Pa s", "gas viscosity"),
    "rho_g": _spec("gas", "rho", "kg/m^3", "gas density"),
    "eps": _spec("bed", "eps", "dimensionless", "local bed voidage", 0.0, 1.0),
    "U": _spec("bed", "U", "m/s", "emulsion superficial gas velocity", lo_open=False),
    "u0": _spec("call", "u0", "m/s", "impact speed of particle i (lab frame)"),
    "u0_j": _spec("call", "u0_j", "m/s", "impact speed of particle j (lab frame)",
                  lo_open=False),
    "beta_deg": _spec("call", "beta_deg", "degree", "collision angle", -INF, INF),
    "e": _spec("call", "e", "dimensionless", "dry restitution coefficient", 0.0, 1.0,
               False, False),
}


def check_names(uncertain) -> None:
    """Raise ``ValueError`` naming any key of ``uncertain`` that is not an input."""
    for name in uncertain:
        if name not in UNCERTAIN_INPUTS:
            raise ValueError(
                f"uncertain input {name!r} is not one of {sorted(UNCERTAIN_INPUTS)}"
            )


def nominal_value(name: str, base: dict):
    """The fixed (base) value of input ``name`` in the collision ``base``."""
    spec = UNCERTAIN_INPUTS[name]
    if spec.target == "call":
        return base[spec.field]
    return getattr(base[spec.target], spec.field)


def evaluate_e_w(base: dict, values: dict[str, np.ndarray], mode: str):
    """Run :func:`agglomtool.collide` on ``base`` with the inputs in ``values`` replaced.

    Parameters
    ----------
    base : dict
        ``p_i``, ``p_j``, ``liquid``, ``gas``, ``bed`` and the keywords of ``collide``
        (``u0``, ``u0_j``, ``beta_deg``, ``e``, ``body_forces``, ``drag_slip``).
    values : dict of str to numpy.ndarray
        SI values of the uncertain inputs, all of one 1-D shape.
    mode : str
        Model tier, passed through to ``collide``.

    Returns
    -------
    CollisionResult
    """
    objs = {k: base[k] for k in ("p_i", "p_j", "liquid", "gas", "bed")}
    changes: dict[str, dict] = {k: {} for k in objs}
    call = {k: base[k] for k in ("u0", "u0_j", "beta_deg", "e", "body_forces", "drag_slip")}
    for name, arr in values.items():
        spec = UNCERTAIN_INPUTS[name]
        if spec.target == "call":
            call[spec.field] = arr
        else:
            changes[spec.target][spec.field] = arr
    for key, ch in changes.items():
        if ch:
            objs[key] = replace(objs[key], **ch)
    return collide(objs["p_i"], objs["p_j"], liquid=objs["liquid"], gas=objs["gas"],
                   bed=objs["bed"], mode=mode, details=False, **call)


def base_inputs(p_i, p_j, liquid, gas, bed, u0, u0_j, beta_deg, e, body_forces, drag_slip):
    """Check the types of the fixed inputs and pack them in a dict."""
    for name, obj, cls in (("p_i", p_i, Particle), ("p_j", p_j, Particle),
                           ("liquid", liquid, Liquid), ("gas", gas, Gas)):
        if not isinstance(obj, cls):
            raise ValueError(f"{name} must be an agglomtool.{cls.__name__}, got {obj!r}")
    bed = Bed() if bed is None else bed
    if not isinstance(bed, Bed):
        raise ValueError(f"bed must be an agglomtool.Bed or None, got {bed!r}")
    return dict(p_i=p_i, p_j=p_j, liquid=liquid, gas=gas, bed=bed, u0=u0, u0_j=u0_j,
                beta_deg=beta_deg, e=e, body_forces=body_forces, drag_slip=drag_slip)
