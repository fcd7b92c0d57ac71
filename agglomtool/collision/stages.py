"""The steps of one collision that several tiers take alike, written once.

Every tier kernel runs the same flow: the bridge's force constants, the dry collision where
no bridge forms, the approach, the solid contact, the rupture gap and the separation, each
writing its columns of the details. The steps whose arithmetic is the same in every tier
that takes them are the functions here (the pair's masses and body force are in
:mod:`.physics`, the bridge geometry in :mod:`.bridge`), so that changing one step's
physics means changing one function. What differs between the tiers on purpose stays in
each:

- :func:`.paper._stage` moves each particle in the centre-of-mass frame, with its own share
  of the losses and its own stop (and takes ``|Delta ln f|`` for either direction in one
  expression); the relative-motion tiers move one body of the reduced mass
  (:func:`stage_losses`, :func:`stage_energy`);
- "ode" integrates the stages instead of taking their closed forms and holds its energies
  as fractions of the initial one (its per-particle details are those fractions times the
  initial energy, another order of operations than :func:`split_details`);
- the piecewise forms of "auto" cut a stage into pieces (:func:`.auto._stage_pieces`).

Each function gives bitwise what the tiers computed before they shared it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._jit import CACHE
from . import _codes as codes
from .bridge import (
    capillary_constant,
    g_change,
    g_diff,
    ln_f,
    ln_f_change,
    rupture_gap,
    viscous_constant,
)
from .records import Bridge

__all__ = [
    "viscous_loss",
    "bridge_constants",
    "fresh_details",
    "no_bridge",
    "dry_contact",
    "contact_details",
    "contact_speed",
    "relative_contact",
    "rupture_at",
    "separation_start",
    "split_details",
    "stage_details",
    "rupture_details",
    "stage_losses",
    "stage_energy",
    "term_work_fractions",
    "work_details",
    "tier_outputs",
]


def tier_outputs(n, details):
    """The output arrays of a tier call over ``n`` collisions, ``(e_w, stage, path, det)``:
    ``e_w`` float64, the stage codes and path flags int8, the details ``(n, N_DETAILS)``
    where ``details`` is true, else ``(n, 0)``."""
    return (np.empty(n), np.empty(n, dtype=np.int8), np.empty(n, dtype=np.int8),
            np.empty((n, codes.N_DETAILS if details else 0)))


@njit(cache=CACHE)
def viscous_loss(v, m, c_delta):
    """Energy a particle of mass ``m`` [kg] entering at ``v`` [m/s] loses to viscosity over a
    stretch with ``c Delta`` = ``c_delta`` [kg/s * -] (the exact solution of the
    viscous-only equation of motion, Eqs. 72-75, 88-90, 95-97); ``m = inf`` gives
    ``c_delta v``. Valid while ``c_delta < m v``, which every caller checks first."""
    return c_delta * (v - 0.5 * c_delta / m)


@njit(cache=CACHE, inline="always")
def bridge_constants(pair):
    """The bridge's force constants of the pair ``pair`` (a :class:`~.records.Pair`), a
    :class:`~.records.Bridge`: ``c`` (Eq. 26), ``kcap`` (Eq. 25) and
    ``a^2 = H0^2 - Ha^2`` (Eqs. 29-30, written without cancellation)."""
    r = pair.r
    a2 = (pair.H0 - pair.Ha) * (pair.H0 + pair.Ha)
    return Bridge(viscous_constant(pair.mu_l, r), capillary_constant(pair.gamma, r, pair.cos_t),
                  a2)


@njit(cache=CACHE, inline="always")
def fresh_details(det):
    """Set every column of the details row ``det`` to NaN (a column a tier does not reach
    stays NaN); True when details are wanted (``det`` not of length 0)."""
    nan = math.nan
    for q in range(det.shape[0]):
        det[q] = nan
    return det.shape[0] > 0


@njit(cache=CACHE, inline="always")
def no_bridge(e):
    """The outcome where no bridge forms (``H0 <= Ha``): a dry collision with restitution
    ``e``, ``(e_w, stage, path)``. Its details are :func:`contact_details` at the impact
    speed."""
    if e > 0.0:
        return e, codes.REBOUND, codes.P_NO_BRIDGE
    return 0.0, codes.CONTACT, codes.P_NO_BRIDGE


@njit(cache=CACHE, inline="always")
def dry_contact(det, m_r, e, w):
    """:func:`no_bridge` with its details written where ``det`` has length: the contact at
    the impact speed ``w`` [m/s] (:func:`contact_details`, reduced mass ``m_r`` [kg])."""
    if det.shape[0] > 0:
        contact_details(det, m_r, e, w)
    return no_bridge(e)


@njit(cache=CACHE, inline="always")
def contact_details(det, m_r, e, w_c):
    """The contact's details: the relative speed ``w_c`` [m/s] reaching the solid contact
    and the energy the restitution ``e`` takes there, ``m_r (1 - e^2) w_c^2 / 2`` [J]."""
    det[codes.W_CONTACT] = w_c
    det[codes.L_C] = 0.5 * m_r * (1.0 - e * e) * w_c * w_c


@njit(cache=CACHE, inline="always")
def contact_speed(k_app, m_r):
    """The relative speed [m/s] reaching the solid contact with the kinetic energy
    ``k_app`` [J] of the relative motion (reduced mass ``m_r`` [kg])."""
    return math.sqrt(2.0 * k_app / m_r)


@njit(cache=CACHE, inline="always")
def relative_contact(det, frac_i, frac_j, m_r, e, k_app):
    """The solid contact of the relative motion (reduced mass ``m_r`` [kg], restitution
    ``e``), reached with the kinetic energy ``k_app`` [J]: the speed it leaves with, ``e``
    times the speed ``w_c`` it arrives with [m/s]; where ``det`` has length, ``k_app``
    (split as :func:`split_details`) and :func:`contact_details` are written."""
    w_c = contact_speed(k_app, m_r)
    if det.shape[0] > 0:
        split_details(det, codes.K_APP_I, codes.K_APP_J, frac_i, frac_j, k_app)
        contact_details(det, m_r, e, w_c)
    return e * w_c


@njit(cache=CACHE, inline="always")
def rupture_at(w_s, mu_l, gamma, theta, vol3):
    """The capillary number ``Ca = mu_l w_s / gamma`` [-] at the opening speed ``w_s``
    [m/s] and the rupture gap of Eq. 94 [m] (:func:`~.bridge.rupture_gap`, ``vol3`` the
    cube root of the bridge volume [m]): ``(Ca, h_rupt)``."""
    ca = mu_l * w_s / gamma
    return ca, rupture_gap(theta, ca, vol3)


@njit(cache=CACHE, inline="always")
def separation_start(det, pair, frac_i, frac_j, m_r, w_s, vol3):
    """The start of the relative motion's separation at the opening speed ``w_s`` [m/s]
    (reduced mass ``m_r`` [kg]): its kinetic energy [J] and the rupture gap [m] of the
    ``pair`` (:func:`rupture_at`); where ``det`` has length, they and the capillary number
    are written (:func:`rupture_details`, the energy split as :func:`split_details`)."""
    k_s = 0.5 * m_r * w_s * w_s
    ca, h_rupt = rupture_at(w_s, pair.mu_l, pair.gamma, pair.theta, vol3)
    if det.shape[0] > 0:
        rupture_details(det, frac_j * k_s, frac_i * k_s, ca, h_rupt)
    return k_s, h_rupt


@njit(cache=CACHE, inline="always")
def split_details(det, col_i, col_j, frac_i, frac_j, value):
    """An energy of the relative motion ``value`` [J] split into the per-particle columns
    ``col_i, col_j`` as the centre-of-mass frame splits kinetic energies: ``frac_j`` of it
    to i, ``frac_i`` to j."""
    det[col_i] = frac_j * value
    det[col_j] = frac_i * value


@njit(cache=CACHE, inline="always")
def stage_details(det, separation, l_cap, l_vis, l_bdw, frac_i, frac_j):
    """A liquid stage's losses [J] of the relative motion in the details: of the approach,
    or of the separation where ``separation``; the body-force loss split as
    :func:`split_details` splits it."""
    if separation:
        det[codes.L_CAP_SEP] = l_cap
        split_details(det, codes.L_BDW_SEP_I, codes.L_BDW_SEP_J, frac_i, frac_j, l_bdw)
        det[codes.L_VIS_SEP] = l_vis
    else:
        det[codes.L_CAP_APP] = l_cap
        split_details(det, codes.L_BDW_APP_I, codes.L_BDW_APP_J, frac_i, frac_j, l_bdw)
        det[codes.L_VIS_APP] = l_vis


@njit(cache=CACHE, inline="always")
def rupture_details(det, k_i, k_j, ca, h_rupt):
    """The separation's start in the details: the kinetic energies ``k_i, k_j`` [J] the
    particles leave the contact with, the capillary number ``ca`` [-] and the rupture gap
    ``h_rupt`` [m] of Eq. 94."""
    det[codes.K_SEP_I] = k_i
    det[codes.K_SEP_J] = k_j
    det[codes.CA] = ca
    det[codes.H_RUPT] = h_rupt


@njit(cache=CACHE, inline="always")
def stage_losses(start, end, bridge, f_b):
    """The losses of the relative motion over a liquid stage from the gap ``start`` to
    ``end`` (:class:`~.records.Gap` records; the approach when ``end.d < start.d``, else the
    separation), under the constants ``bridge`` (:class:`~.records.Bridge`) and the body
    force ``f_b`` [N] on the relative motion (positive towards each other):
    ``(c Delta, l_cap, l_bdw)``, with ``Delta = |ln f(end.d) - ln f(start.d)|``, the
    capillary loss ``kcap (g(end.d) - g(start.d))`` [J] and the body-force loss [J] (a gain
    on the approach where ``f_b > 0``). None of them depends on the speed."""
    c, kcap, a2 = bridge
    change = ln_f_change(start, end)
    if end.d < start.d:  # the approach: the gap closes, ln f falls
        c_delta = c * -change
        l_bdw = -f_b * (start.d - end.d)
    else:
        c_delta = c * change
        l_bdw = f_b * (end.d - start.d)
    return c_delta, kcap * g_change(start, end, a2), l_bdw


@njit(cache=CACHE, inline="always")
def stage_energy(k, v, m_r, c_delta, l_cap, l_bdw):
    """One liquid stage of the relative motion (reduced mass ``m_r`` [kg]), entered with
    kinetic energy ``k`` [J] at speed ``v`` [m/s], with its viscous ``c Delta`` and its
    capillary and body-force losses [J] (:func:`stage_losses`): ``(code, k_end, l_vis)``,
    ``code`` 0 where the pair goes through with ``k_end`` left, 1 where viscosity alone
    stops it (``c Delta >= m_r v``, the paper's Eqs. 73, 75 for the relative motion;
    ``k_end`` 0, ``l_vis`` NaN), 2 where the energy is spent (``k_end <= 0``)."""
    if not c_delta < m_r * v:
        return 1, 0.0, math.nan
    l_vis = viscous_loss(v, m_r, c_delta)
    k_end = k - l_cap - l_vis - l_bdw
    return (0 if k_end > 0.0 else 2), k_end, l_vis


@njit(cache=CACHE)
def term_work_fractions(scale, h_rupt):
    """Bounds of the work of two optional terms, as fractions of the initial relative kinetic
    energy ``scale.k0`` [J]: ``(body, volume correction)``; ``scale`` a
    :class:`~.records.WorkScale`, ``h_rupt`` the rupture gap [m].

    - body forces: ``|F_b| (H0 - Ha + h_rupt - Ha)``, the most they can do over the bridge;
    - the bridge-volume correction ``X_v``: the change it makes to the capillary work and to
      the viscous work at the impact speed ``w`` (with ``X_v = 1`` the capillary work over a
      stage is ``kcap |dD|`` and the viscous ``c w |d ln D|``).

    ``h_rupt`` NaN (the pair stuck before contact) counts the approach only.
    """
    k0, w, c, kcap, f_b, H0, Ha, a2 = scale
    sep = h_rupt > Ha
    d_body = (H0 - Ha) + ((h_rupt - Ha) if sep else 0.0)
    body = abs(f_b) * d_body / k0
    if not Ha > 0.0:
        return body, math.inf
    ln_h0, ln_ha = math.log(H0), math.log(Ha)
    cap = kcap * abs((H0 - Ha) - abs(g_diff(H0, Ha, a2)))
    vis = c * w * abs((ln_h0 - ln_ha) - abs(ln_f(H0, a2) - ln_f(Ha, a2)))
    if sep:
        cap += kcap * abs((h_rupt - Ha) - abs(g_diff(Ha, h_rupt, a2)))
        ln_hr = math.log(h_rupt)
        vis += c * w * abs((ln_hr - ln_ha) - abs(ln_f(h_rupt, a2) - ln_f(Ha, a2)))
    return body, (cap + vis) / k0


@njit(cache=CACHE, inline="always")
def work_details(det, scale, h_rupt):
    """The detail columns of the body and volume-correction work fractions
    (:func:`term_work_fractions`; ``scale`` a :class:`~.records.WorkScale`)."""
    body, vol = term_work_fractions(scale, h_rupt)
    det[codes.W_BODY] = body
    det[codes.W_VOLCORR] = vol
