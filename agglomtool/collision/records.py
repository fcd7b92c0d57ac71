"""Named records of the collision core: the pair state, a tier call's input arrays, the
stage results and the solver options, instead of long positional parameter lists and bare
tuples of integer codes.

Each record is a :class:`typing.NamedTuple`, which Numba compiles in nopython mode as a
tuple with names: built, passed in and out and read by attribute inside compiled code, at
no cost (its fields are passed as the separate scalars they were before; measured on the
benchmark batch, see ``docs/maintainers.md``), except that building one from arrays loads
every field (:func:`pair_at`). Units are SI; each field says its own.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numba import njit

from .._jit import CACHE

__all__ = [
    "Pair",
    "RawPair",
    "Prepared",
    "TierInputs",
    "INPUT_FIELDS",
    "tier_inputs",
    "pair_at",
    "Gap",
    "Mover",
    "Bridge",
    "StageResult",
    "WorkScale",
    "OdeForces",
    "OdeOptions",
    "OdeStops",
    "RuptureLaw",
    "RuptureEnd",
]


class Pair(NamedTuple):
    """The state of one colliding pair, everything but the relative speed ``w`` (which the
    critical-speed searches and mode "auto" vary)."""

    #: wet mass of particle i [kg]; ``inf`` for a plate (not both)
    m_i: float
    #: wet mass of particle j [kg]; ``inf`` for a plate
    m_j: float
    #: harmonic-mean solid radius [m] (``2 r_i`` against a plate)
    r: float
    #: gap at first liquid contact [m]
    H0: float
    #: gap at solid contact (the asperities) [m]
    Ha: float
    #: liquid viscosity [Pa s]
    mu_l: float
    #: surface tension [N/m]
    gamma: float
    #: cosine of the contact angle [-]
    cos_t: float
    #: contact angle [rad]
    theta: float
    #: net body force on i projected on the normal from i towards j [N]
    fn_i: float
    #: net body force on j projected on the same normal [N]
    fn_j: float
    #: dry restitution coefficient [-]
    e: float


class RawPair(NamedTuple):
    """The raw inputs of one collision of the fused kernels (:mod:`.fused`), all but its
    lab speeds ``u0`` and ``u0_j``: what :func:`.fused.prepare_one` makes a :class:`Pair`
    from, in the order of :data:`.fused.INPUT_NAMES`."""

    #: solid diameter of particle i [m]; ``inf`` for a plate
    d_i: float
    #: solid density of i [kg/m3]
    rho_i: float
    #: liquid layer on i [m]
    h0_i: float
    #: asperities of i [m]
    ha_i: float
    #: solid diameter of particle j [m]; ``inf`` for a plate
    d_j: float
    #: solid density of j [kg/m3]
    rho_j: float
    #: liquid layer on j [m]
    h0_j: float
    #: asperities of j [m]
    ha_j: float
    #: liquid viscosity [Pa s]
    mu_l: float
    #: surface tension [N/m]
    gamma: float
    #: liquid density [kg/m3]
    rho_l: float
    #: contact angle [deg]
    theta_deg: float
    #: gas viscosity [Pa s]
    mu_g: float
    #: gas density [kg/m3]
    rho_g: float
    #: bed voidage [-]
    eps: float
    #: superficial gas speed [m/s]; NaN: ``1.1 U_mf`` of the pair
    U: float
    #: collision angle [deg]
    beta_deg: float
    #: dry restitution coefficient [-]
    e: float


class Prepared(NamedTuple):
    """What :func:`.fused.prepare_one` makes of a :class:`RawPair` and its lab speeds: the
    :class:`Pair` fields that change (the others are the raw inputs' ``mu_l``, ``gamma``
    and ``e``), the relative speed and its ratio to a head-on ``u0``."""

    #: wet mass of i [kg]
    m_i: float
    #: wet mass of j [kg]
    m_j: float
    #: harmonic-mean solid radius [m]
    r: float
    #: gap at first liquid contact [m]
    H0: float
    #: gap at solid contact [m]
    Ha: float
    #: cosine of the contact angle [-]
    cos_t: float
    #: contact angle [rad]
    theta: float
    #: net body force on i along the normal [N]
    fn_i: float
    #: net body force on j along the normal [N]
    fn_j: float
    #: relative normal speed ``u_i + u_j`` [m/s]
    w: float
    #: ``w`` per head-on ``u0`` [-]: 2, or 1 with a plate
    w_per_u0: float


class TierInputs(NamedTuple):
    """The flat, equal-length float64 arrays of a tier call (one element per collision):
    the fields of :class:`Pair` and the relative normal impact speed ``w``, in the order of
    the tiers' calling convention (:mod:`.tiers`)."""

    #: wet masses [kg]
    m_i: np.ndarray
    #: wet masses [kg]
    m_j: np.ndarray
    #: harmonic-mean solid radii [m]
    r: np.ndarray
    #: gaps at first liquid contact [m]
    H0: np.ndarray
    #: gaps at solid contact [m]
    Ha: np.ndarray
    #: liquid viscosities [Pa s]
    mu_l: np.ndarray
    #: surface tensions [N/m]
    gamma: np.ndarray
    #: cosines of the contact angle [-]
    cos_t: np.ndarray
    #: contact angles [rad]
    theta: np.ndarray
    #: relative normal impact speeds ``u_i - u_j`` > 0 [m/s]
    w: np.ndarray
    #: net body forces on i along the normal [N]
    fn_i: np.ndarray
    #: net body forces on j along the normal [N]
    fn_j: np.ndarray
    #: dry restitution coefficients [-]
    e: np.ndarray


#: The names of a tier call's input arrays, in order.
INPUT_FIELDS = TierInputs._fields


def tier_inputs(arrays: Sequence[np.ndarray]) -> TierInputs:
    """``arrays`` as a :class:`TierInputs`: a :class:`TierInputs` is returned as it is, any
    other sequence must hold the :data:`INPUT_FIELDS` arrays in order."""
    if isinstance(arrays, TierInputs):
        return arrays
    arrays = tuple(arrays)
    if len(arrays) != len(INPUT_FIELDS):
        raise ValueError(
            f"a tier call takes {len(INPUT_FIELDS)} input arrays {INPUT_FIELDS}; "
            f"got {len(arrays)}"
        )
    return TierInputs(*arrays)


@njit(cache=CACHE, inline="always")
def pair_at(ins, q):
    """The :class:`Pair` of collision ``q`` of the input arrays ``ins`` (a
    :class:`TierInputs`); its speed is ``ins.w[q]``."""
    return Pair(ins.m_i[q], ins.m_j[q], ins.r[q], ins.H0[q], ins.Ha[q], ins.mu_l[q],
                ins.gamma[q], ins.cos_t[q], ins.theta[q], ins.fn_i[q], ins.fn_j[q], ins.e[q])


class Gap(NamedTuple):
    """A gap with the parts of it the bridge functions take (:func:`.bridge.gap_parts`)."""

    #: the gap [m]
    d: float
    #: ``sqrt(d^2 + a^2)`` [m]
    s: float
    #: the kind of the ``ln f`` parts (0 or 1, :func:`.bridge.ln_f_parts`) [-]
    kind: int
    #: the value of the ``ln f`` parts [-]
    val: float


class Mover(NamedTuple):
    """One particle through a liquid stage of the paper's model (:func:`.paper._stage`)."""

    #: kinetic energy at the start of the stage [J]
    k: float
    #: centre-of-mass frame speed at the start [m/s]
    v: float
    #: its share of the gap change [-] (Eqs. 13-16: its partner's mass fraction)
    share: float
    #: mass [kg] (``inf`` for a plate)
    m: float
    #: body force along its motion relative to the partner [N]
    f: float


class Bridge(NamedTuple):
    """The bridge's force constants (Eqs. 25-26, 29-30)."""

    #: viscous constant ``(3/2) pi mu_l r^2`` [kg m]
    c: float
    #: capillary constant ``2 pi gamma r cos(theta)`` [N]
    kcap: float
    #: ``a^2 = H0^2 - Ha^2`` [m2]
    a2: float


class StageResult(NamedTuple):
    """The outcome of one liquid stage of the paper's model (:func:`.paper._stage`)."""

    #: 0 both go on, 1 viscous stop, 2 energy spent, 3 the lone mover runs out, 4 viscosity
    #: stops the lone mover [-]
    code: int
    #: kinetic energy of i at the end of the stage [J]
    k_end_i: float
    #: kinetic energy of j at the end of the stage [J]
    k_end_j: float
    #: the gap where one particle stopped first [m]; NaN when nobody did
    d_stop: float
    #: 1 if i stopped first, 2 if j did, else 0 [-]
    flags: int
    #: capillary loss over the stage [J]
    l_cap: float
    #: viscous loss over the stage [J] (NaN after a viscous stop)
    l_vis: float
    #: body-force loss of i [J]
    l_bdw_i: float
    #: body-force loss of j [J]
    l_bdw_j: float


class WorkScale(NamedTuple):
    """What the work bounds of the optional terms need (:func:`.stages.term_work_fractions`)."""

    #: initial relative kinetic energy [J]
    k0: float
    #: relative impact speed [m/s]
    w: float
    #: viscous constant [kg m]
    c: float
    #: capillary constant [N]
    kcap: float
    #: body force on the relative motion [N], positive towards each other
    f_b: float
    #: gap at first liquid contact [m]
    H0: float
    #: gap at solid contact [m]
    Ha: float
    #: ``a^2`` [m2]
    a2: float


class OdeForces(NamedTuple):
    """The force law of the integrated relative motion, normalised by the initial relative
    kinetic energy ``K0`` (:mod:`.ode`)."""

    #: ``a^2`` [m2]
    a2: float
    #: ``kcap / K0`` [1/m]
    kc: float
    #: ``F_b / K0`` [1/m]
    fb: float
    #: ``2 c / (m_r w)`` [-]
    vis: float
    #: True: the bridge-volume correction ``X_v``; False: ``X_v = 1``
    volcorr: bool


class OdeOptions(NamedTuple):
    """The options of one integration (:func:`.ode.ode_batch` names them)."""

    #: relative tolerance of the step control on ``k = K / K0`` [-]
    rtol: float
    #: absolute tolerance [-]
    atol: float
    #: True: the rupture gap follows the opening speed (self-consistent rupture)
    self_consistent: bool
    #: True: the bridge-volume correction ``X_v``; False: ``X_v = 1``
    volcorr: bool
    #: first trial step in ``ln D`` [-]
    h_first: float
    #: largest step in ``ln D`` [-]
    h_max: float
    #: the first step changes ``k`` by at most this times ``max(k, 1e-3)`` [-]
    first_change: float
    #: the separation stops as a stick with this margin in ``k`` [-]; < 0 disables it
    stick_margin: float


class OdeStops(NamedTuple):
    """The early stops of one integrated stage (:func:`.ode._integrate`)."""

    #: ``e^2`` [-]
    e2: float
    #: lower bound of the opening energy a rebound needs [-]; < 0 disables the stop
    need: float
    #: True: stop at the first ``ln D >= ln h_rupt(k)`` (self-consistent rupture)
    event: bool
    #: stop as a stick once the pair sticks with this margin in ``k`` [-]; < 0 disables it
    stick_margin: float


class RuptureLaw(NamedTuple):
    """The rupture gap of Eq. 94 as a function of the opening speed (:mod:`.ode`)."""

    #: contact angle [rad]
    theta: float
    #: capillary number per ``sqrt(k)``: ``mu_l w / gamma`` [-]
    ca_per_sqrtk: float
    #: bridge volume [m3]
    vol: float


class RuptureEnd(NamedTuple):
    """The fixed rupture gap a separation is integrated to (:func:`.ode._must_stick`)."""

    #: the rupture gap [m]
    h_end: float
    #: ``sqrt(h_end^2 + a^2)`` [m]
    s_end: float
    #: ``ln f(h_end)`` [-]
    lnf_end: float
    #: True where the capillary and body forces pull the pair back all the way to it
    pulls: bool
