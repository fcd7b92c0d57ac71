"""From two particles, a liquid, a gas and a bed to the collision kernel's numbers.

This is where the property layer (drag, minimum fluidization) meets the collision core:
wet masses (Eqs. 32-33), the harmonic radius (Eq. 3), the gaps, the collision axis of the
paper's Fig. 5, and the body forces (Eqs. 18-24, 116-119) projected on that axis.

Geometry (Fig. 5): particle i at the origin; the axis ``n`` from i to j lies in the Y-Z
plane at ``beta`` from the horizontal Y axis towards +Z; gravity along -Z; the gas flows
along +Z.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import vectorize

from ._jit import CACHE
from ._validate import as_float_array, check_range
from .collision.physics import U_E_PER_UMF, WEN_YU_C1, WEN_YU_C2
from .collision.physics import wet_mass as _wet_mass_scalar
from .collision.physics import wet_umf as _wet_umf_scalar
from .constants import GRAVITY
from .inputs import Bed, Gas, Liquid, Particle
from .properties import drag_force_gidaspow

__all__ = [
    "PairState",
    "prepare_pair",
    "flatten",
    "DRAG_SLIP_MODES",
    "check_inputs",
    "broadcast_shape",
]

#: How the slip velocity in the drag law is taken (docs/model.md, "Forces"):
#: "emulsion": the paper's local gas velocity from Eq. 22, slip = U_e / eps, vertical;
#: "particle": slip = U_e / eps - u0 (the particle's own impact velocity subtracted).
DRAG_SLIP_MODES = ("emulsion", "particle")


@dataclass
class PairState:
    """Everything the kernels need (float64 arrays that broadcast to ``shape``)."""

    shape: tuple
    m_i: np.ndarray
    m_j: np.ndarray
    r: np.ndarray
    H0: np.ndarray
    Ha: np.ndarray
    mu_l: np.ndarray
    gamma: np.ndarray
    cos_t: np.ndarray
    theta: np.ndarray
    e: np.ndarray
    fn_i: np.ndarray
    fn_j: np.ndarray
    w_per_u0: np.ndarray  # relative normal speed per unit head-on u0 (2, or 1 with a plate)
    U_e: np.ndarray


@vectorize(["float64(float64, float64, float64, float64)"], cache=CACHE)
def _wet_mass_ufunc(d, rho, h0, rho_l):
    return _wet_mass_scalar(d, rho, h0, rho_l)


@vectorize(["float64(float64, float64, float64, float64, float64, float64, float64)"],
           cache=CACHE)
def _wet_umf_ufunc(d, h0, m, mu_g, rho_g, c1, c2):
    return _wet_umf_scalar(d, h0, m, mu_g, rho_g, c1, c2)


def wet_mass(p: Particle, rho_l) -> np.ndarray:
    """Mass of a coated particle [kg] (Eqs. 32-33); ``inf`` for a plate.

    ``agglomtool.collision.physics.wet_mass`` over the broadcast arrays (the coating
    volume written without cancellation for thin coatings).
    """
    return np.asarray(_wet_mass_ufunc(p.d, p.rho, p.h0, rho_l))


def _wet_volume_and_diameter(p: Particle):
    d_wet = p.d + 2.0 * p.h0
    return (np.pi / 6.0) * (d_wet * d_wet * d_wet), d_wet


def emulsion_velocity(p_i, p_j, liquid, gas, bed) -> np.ndarray:
    """Emulsion superficial gas velocity [m/s]: ``bed.U``, or 1.1 x the larger Wen-Yu
    ``U_mf`` of the pair (the paper's Section 3.1 choice,
    :data:`agglomtool.collision.physics.U_E_PER_UMF`), a plate not counting.

    ``U_mf`` uses the wet diameter and the wet particle's mean density (not stated
    in the paper; immaterial at its coatings): ``agglomtool.collision.physics.wet_umf``.
    """
    if bed.U is not None:
        return np.asarray(bed.U, dtype=float)
    umfs = [_wet_umf_ufunc(p.d, p.h0, wet_mass(p, liquid.rho), gas.mu, gas.rho, WEN_YU_C1,
                           WEN_YU_C2) for p in (p_i, p_j)]
    return np.asarray(U_E_PER_UMF * np.maximum(umfs[0], umfs[1]))


def body_force_vector(p: Particle, m, liquid, gas, bed, U_e, u_vec, drag_slip):
    """Net body force on one particle, (F_y, F_z) [N] (Eqs. 18-24, 116-117).

    Weight ``-m g`` (coating included), buoyancy ``rho_g V_p g`` upward (Eq. 23, opposing
    gravity), Gidaspow drag (Eq. 18) on the wet particle. A plate is fixed: zero.
    """
    vol, d_wet = _wet_volume_and_diameter(p)
    plate = np.isinf(p.d)
    vol = np.where(plate, 0.0, vol)
    d_wet = np.where(plate, 1.0, d_wet)
    m_f = np.where(plate, 0.0, m)
    slip_z = U_e / bed.eps
    slip_y = np.zeros_like(slip_z)
    if drag_slip == "particle":
        slip_y = slip_y - u_vec[0]
        slip_z = slip_z - u_vec[1]
    speed = np.hypot(slip_y, slip_z)
    f_drag = drag_force_gidaspow(speed, d_wet, vol, bed.eps, gas.mu, gas.rho)
    safe = np.where(speed > 0.0, speed, 1.0)
    f_y = f_drag * slip_y / safe
    f_z = f_drag * slip_z / safe + (gas.rho * vol - m_f) * GRAVITY
    return f_y, f_z


def check_inputs(p_i, p_j, liquid, gas, bed) -> None:
    """Each input is of its class (a ``ValueError`` naming the field otherwise), and at most
    one particle is a plate."""
    for name, val, cls in (("liquid", liquid, Liquid), ("gas", gas, Gas), ("bed", bed, Bed)):
        if not isinstance(val, cls):
            raise ValueError(
                f"{name} = {val!r} is not allowed: an agglomtool.{cls.__name__} is required"
            )
    check_pair(p_i, p_j)


def broadcast_shape(names, values) -> tuple:
    """The common shape of ``values``; a ``ValueError`` naming the fields (``names``) and
    their shapes when they do not broadcast together."""
    shapes = [() if type(v) is float else v.shape if isinstance(v, np.ndarray) else np.shape(v)
              for v in values]
    arrays = [s for s in shapes if s != ()]
    if not arrays:
        return ()
    first = arrays[0]
    if arrays.count(first) == len(arrays):  # the common case: one shape (or one array)
        return first
    try:
        return np.broadcast_shapes(*arrays)
    except ValueError:
        listed = ", ".join(
            f"{n} {s}" for n, s in zip(names, shapes, strict=True) if s not in ((), (1,))
        )
        raise ValueError(
            f"the inputs do not broadcast together: {listed}; allowed: shapes that broadcast "
            "(numpy rules)"
        ) from None


def check_pair(p_i, p_j) -> None:
    """Both are Particles, and at most one of them is a plate."""
    for name, p in (("p_i", p_i), ("p_j", p_j)):
        if not isinstance(p, Particle):
            raise ValueError(f"{name} = {p!r} is not allowed: an agglomtool.Particle is "
                             "required")
    d_i, d_j = p_i.d, p_j.d
    if d_i.ndim == 0 and d_j.ndim == 0:
        both = math.isinf(d_i) and math.isinf(d_j)
    elif d_i.max() < math.inf or d_j.max() < math.inf:
        both = False  # one side holds no plate at all (two reductions, no mask)
    else:
        both = bool(np.any(np.isinf(d_i) & np.isinf(d_j)))
    if both:
        raise ValueError("p_i and p_j are both plates (d = inf); at most one may be")


#: The raw inputs of :func:`prepare_pair`, named for error messages.
_RAW_NAMES = (
    "p_i.d", "p_i.rho", "p_i.h0", "p_i.ha", "p_j.d", "p_j.rho", "p_j.h0", "p_j.ha",
    "liquid.mu", "liquid.gamma", "liquid.rho", "liquid.theta_deg", "gas.mu", "gas.rho",
    "bed.eps", "bed.U", "beta_deg", "e", "u0", "u0_j",
)


def prepare_pair(
    p_i: Particle,
    p_j: Particle,
    liquid: Liquid,
    gas: Gas,
    bed: Bed,
    beta_deg,
    e,
    body_forces: bool,
    drag_slip: str,
    u_i=None,
    u_j=None,
) -> PairState:
    """Broadcast the inputs and compute the kernel's per-collision numbers.

    ``u_i``, ``u_j`` (lab speeds towards each other [m/s]) are needed only with
    ``drag_slip="particle"``, where the drag depends on them.
    """
    check_inputs(p_i, p_j, liquid, gas, bed)
    if drag_slip not in DRAG_SLIP_MODES:
        raise ValueError(f"drag_slip = {drag_slip!r} is not one of {DRAG_SLIP_MODES}")
    e = check_range("e", e, 0.0, 1.0, unit="-")
    beta = np.deg2rad(as_float_array("beta_deg", beta_deg))
    cos_b, sin_b = np.cos(beta), np.sin(beta)
    theta = np.deg2rad(liquid.theta_deg)
    broadcast_shape(_RAW_NAMES, (
        p_i.d, p_i.rho, p_i.h0, p_i.ha, p_j.d, p_j.rho, p_j.h0, p_j.ha, liquid.mu,
        liquid.gamma, liquid.rho, liquid.theta_deg, gas.mu, gas.rho, bed.eps,
        0.0 if bed.U is None else bed.U, beta, e, 0.0 if u_i is None else u_i,
        0.0 if u_j is None else u_j,
    ))

    m_i = wet_mass(p_i, liquid.rho)
    m_j = wet_mass(p_j, liquid.rho)
    # Harmonic-mean radius (Eq. 3) as 2 / (1/r_i + 1/r_j): exact 2 r_i for a plate j.
    r = 2.0 / (2.0 / p_i.d + 2.0 / p_j.d)
    U_e = emulsion_velocity(p_i, p_j, liquid, gas, bed)

    if body_forces:
        zero = np.zeros(())
        ui = zero if u_i is None else u_i
        uj = zero if u_j is None else u_j
        # Lab velocity vectors: i moves along +n at u_i, j along -n at u_j.
        fy_i, fz_i = body_force_vector(
            p_i, m_i, liquid, gas, bed, U_e, (ui * cos_b, ui * sin_b), drag_slip
        )
        fy_j, fz_j = body_force_vector(
            p_j, m_j, liquid, gas, bed, U_e, (-uj * cos_b, -uj * sin_b), drag_slip
        )
        fn_i = fy_i * cos_b + fz_i * sin_b  # Eq. 118 with m_ij,app = n_ij
        fn_j = fy_j * cos_b + fz_j * sin_b  # projected on n; the kernel flips signs per stage
    else:
        fn_i = fn_j = np.zeros(np.shape(beta))  # keeps beta's shape in the broadcast

    plate_any = np.isinf(p_i.d) | np.isinf(p_j.d)
    w_per_u0 = np.where(plate_any, 1.0, 2.0)
    fields = (
        m_i, m_j, r, p_i.h0 + p_j.h0, p_i.ha + p_j.ha, liquid.mu, liquid.gamma, np.cos(theta),
        theta, e, fn_i, fn_j, w_per_u0, U_e,
    )
    arrays = tuple(np.asarray(a, dtype=np.float64) for a in fields)
    shape = np.broadcast_shapes(*(a.shape for a in arrays))
    return PairState(shape, *arrays)


def flatten(state: PairState, shape=None) -> PairState:
    """``state`` with every array broadcast to ``shape`` (default ``state.shape``) and
    raveled into a contiguous 1-D array."""
    shape = state.shape if shape is None else shape
    vals = {
        name: np.ascontiguousarray(np.broadcast_to(val, shape)).reshape(-1)
        for name, val in state.__dict__.items()
        if name != "shape"
    }
    return PairState((int(np.prod(shape)),), **vals)
