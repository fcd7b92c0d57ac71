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

from .._fields import CORE_RANGES
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


_CLASSES = {"p_i": "Particle", "p_j": "Particle", "liquid": "Liquid", "gas": "Gas",
            "bed": "Bed", "call": "collide"}


def _spec(target, field, units, long_name, lo=None, hi=None, lo_open=None, hi_open=None):
    """The input's physical range: that of :data:`agglomtool._fields.CORE_RANGES` (the one
    the core validates), narrowed where given here (a speed towards the other, > 0)."""
    c_lo, c_hi, c_lo_open, c_hi_open, _unit = CORE_RANGES[f"{_CLASSES[target]}.{field}"]
    return InputSpec(target, field, units, long_name,
                     c_lo if lo is None else lo, c_hi if hi is None else hi,
                     c_lo_open if lo_open is None else lo_open,
                     c_hi_open if hi_open is None else hi_open)


#: name in ``uncertain=`` -> InputSpec
UNCERTAIN_INPUTS: dict[str, InputSpec] = {
    "d_i": _spec("p_i", "d", "m", "solid diameter of particle i"),
    "d_j": _spec("p_j", "d", "m", "solid diameter of particle j"),
    "rho_i": _spec("p_i", "rho", "kg/m^3", "solid density of particle i"),
    "rho_j": _spec("p_j", "rho", "kg/m^3", "solid density of particle j"),
    "h0_i": _spec("p_i", "h0", "m", "coating thickness of particle i"),
    "h0_j": _spec("p_j", "h0", "m", "coating thickness of particle j"),
    "ha_i": _spec("p_i", "ha", "m", "asperity height of particle i"),
    "ha_j": _spec("p_j", "ha", "m", "asperity height of particle j"),
    "mu_l": _spec("liquid", "mu", "Pa s", "liquid viscosity"),
    "gamma": _spec("liquid", "gamma", "N/m", "liquid surface tension"),
    "rho_l": _spec("liquid", "rho", "kg/m^3", "liquid density"),
    "theta_deg": _spec("liquid", "theta_deg", "degree", "contact angle"),
    "mu_g": _spec("gas", "mu", "Pa s", "gas viscosity"),
    "rho_g": _spec("gas", "rho", "kg/m^3", "gas density"),
    "eps": _spec("bed", "eps", "dimensionless", "local bed voidage"),
    "U": _spec("bed", "U", "m/s", "emulsion superficial gas velocity"),
    "u0": _spec("call", "u0", "m/s", "impact speed of particle i (lab frame)", lo=0.0,
                lo_open=True),
    "u0_j": _spec("call", "u0_j", "m/s", "impact speed of particle j (lab frame)", lo=0.0),
    "beta_deg": _spec("call", "beta_deg", "degree", "collision angle"),
    "e": _spec("call", "e", "dimensionless", "dry restitution coefficient"),
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
