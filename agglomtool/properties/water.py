"""Liquid water: viscosity, density and surface tension against temperature.

Viscosity and density come from CoolProp's implementation of the IAPWS formulations;
surface tension from the IAPWS release, written out here (one line; CoolProp's own water
surface tension is Mulero et al.'s 2012 fit, 0.1 % higher at 25 C).
"""

from __future__ import annotations

import atexit
from functools import cache, lru_cache

import CoolProp
import CoolProp.CoolProp as CP
import numpy as np

from .._validate import check_range
from ..inputs import Liquid

__all__ = [
    "water_density_wagner_pruss",
    "water_viscosity_huber",
    "water_surface_tension_iapws",
    "water_liquid",
]

_LIQUID = {CP.iphase_liquid, CP.iphase_supercritical_liquid}
_T_CRIT = 647.096  # K, IAPWS
_P_TRIPLE = 611.655  # Pa, IAPWS (CoolProp's ptriple for Water: 611.6548 Pa)


@cache
def _state():
    return CP.AbstractState("HEOS", "Water")


atexit.register(_state.cache_clear)  # released before exit (as the gas tables' states)


#: ``(P, T) -> (mu, rho)`` of the liquid states evaluated so far. A state depends on its
#: ``(P, T)`` alone (not on the states evaluated before it: CoolProp's PT update starts
#: afresh), so a remembered one is bitwise the one evaluated again; the blocks of a map
#: share their temperatures and take each state once. Cleared when it holds
#: :data:`_MEMO_SIZE` states.
_MEMO: dict = {}
_MEMO_SIZE = 1 << 14


#: Above this many states at one pressure in one call (a Monte Carlo over temperature),
#: they come from a checked table in T (:func:`_table`, some 800 HEOS calls to build)
#: instead of one HEOS call each (about 30 us a state). Below it, and for pressures with
#: fewer states (a Monte Carlo over P), every state is HEOS's own value.
TABLE_MIN = 4096
#: Node spacing of the table in T [K] and the largest relative error accepted in a cell,
#: checked against HEOS at every cell's midpoint.
TABLE_STEP = 0.25
TABLE_TOL = 1e-9


@lru_cache(maxsize=16)
def _table(P: float):
    """``(T0, T1, spline of ln mu, spline of rho, cell_ok)`` of liquid water at ``P`` [Pa].

    Not-a-knot cubic splines on nodes every :data:`TABLE_STEP` K from 273.16 K to the last
    node below the boiling point at ``P`` (or below the critical temperature above the
    critical pressure). A cell is used only if HEOS at its midpoint agrees with the spline
    to :data:`TABLE_TOL` in both ``mu`` and ``rho``; the states of other cells, and any
    state outside the nodes, are evaluated by HEOS.
    """
    from scipy.interpolate import CubicSpline

    st = _state()
    try:
        t_top = CP.PropsSI("T", "P", P, "Q", 0, "Water")
    except ValueError:  # above the critical pressure: no boiling point
        t_top = _T_CRIT
    t0 = 273.16
    n = int(np.floor((t_top - t0) / TABLE_STEP))
    if n < 8:
        return None
    nodes = t0 + TABLE_STEP * np.arange(n)  # every node strictly below the boiling point

    def heos(t):
        st.update(CP.PT_INPUTS, P, float(t))
        return st.viscosity(), st.rhomass(), st.phase() in _LIQUID

    vals = np.array([heos(t) for t in nodes])
    if not vals[:, 2].all():
        return None
    s_mu, s_rho = CubicSpline(nodes, np.log(vals[:, 0])), CubicSpline(nodes, vals[:, 1])
    mids = nodes[:-1] + 0.5 * TABLE_STEP
    ref = np.array([heos(t) for t in mids])
    ok = (np.abs(np.exp(s_mu(mids)) / ref[:, 0] - 1.0) <= TABLE_TOL) & (
        np.abs(s_rho(mids) / ref[:, 1] - 1.0) <= TABLE_TOL) & ref[:, 2].astype(bool)
    return nodes[0], nodes[-1], s_mu, s_rho, ok


def _from_tables(T, P, mu, rho) -> np.ndarray:
    """Fill ``mu``, ``rho`` (1-d) from the tables where they hold; the mask of states
    still to evaluate."""
    todo = np.ones(T.shape, dtype=bool)
    pressures, counts = np.unique(P, return_counts=True)
    for p in pressures[counts > TABLE_MIN]:  # a table pays only for many states at one P
        at_p = P == p
        tab = _table(float(p))
        if tab is None:
            continue
        t0, t1, s_mu, s_rho, ok = tab
        t = T[at_p]
        cell = np.clip(((t - t0) / TABLE_STEP).astype(np.intp), 0, ok.size - 1)
        use = (t >= t0) & (t <= t1) & ok[cell]
        idx = np.flatnonzero(at_p)[use]
        mu[idx] = np.exp(s_mu(t[use]))
        rho[idx] = s_rho(t[use])
        todo[idx] = False
    return todo


def _liquid_states(T, P):
    T = check_range("T", T, 273.16, _T_CRIT, lo_open=False, hi_open=True, unit="K")
    try:
        P = check_range("P", P, _P_TRIPLE, 1e9, unit="Pa")
    except ValueError as exc:  # below the triple point CoolProp has no saturation state
        raise ValueError(f"{exc}: below water's triple-point pressure ({_P_TRIPLE:g} Pa) no "
                         "liquid water exists; pressures are absolute, in Pa") from None
    T, P = np.broadcast_arrays(T, P)
    mu = np.empty(T.shape)
    rho = np.empty(T.shape)
    if T.size > TABLE_MIN:
        todo = _from_tables(T.ravel(), P.ravel(), mu.reshape(-1), rho.reshape(-1))
        todo = todo.reshape(T.shape)
    else:
        todo = np.ones(T.shape, dtype=bool)
    st = None
    # the states left (all of them below TABLE_MIN), as index tuples; () for a 0-d array
    left = zip(*np.nonzero(todo), strict=True) if todo.ndim else ([()] if todo else [])
    for k in left:
        key = (float(P[k]), float(T[k]))
        got = _MEMO.get(key)
        if got is None:
            st = _state() if st is None else st
            st.update(CP.PT_INPUTS, key[0], key[1])
            if st.phase() not in _LIQUID:
                raise ValueError(
                    f"water at T = {T[k]:g} K, P = {P[k]:g} Pa is not a liquid (it boils at "
                    f"{CP.PropsSI('T', 'P', key[0], 'Q', 0, 'Water'):.2f} K at that "
                    "pressure)"
                )
            got = (st.viscosity(), st.rhomass())
            if len(_MEMO) >= _MEMO_SIZE:
                _MEMO.clear()
            _MEMO[key] = got
        mu[k], rho[k] = got
    return mu, rho


def water_density_wagner_pruss(T, P=101325.0):
    """Density of liquid water by IAPWS-95 [kg/m3].

    Parameters
    ----------
    T : array_like
        Temperature [K], from 273.16 K to the boiling point at ``P``.
    P : array_like
        Pressure [Pa].

    Notes
    -----
    Wagner, W., Pruss, A. (2002), J. Phys. Chem. Ref. Data 31:387-535,
    doi:10.1063/1.1461829, as implemented in CoolProp (HEOS backend).
    """
    return _liquid_states(T, P)[1]


def water_viscosity_huber(T, P=101325.0):
    """Viscosity of liquid water by the IAPWS 2008 formulation [Pa s].

    Parameters
    ----------
    T : array_like
        Temperature [K], from 273.16 K to the boiling point at ``P``.
    P : array_like
        Pressure [Pa].

    Notes
    -----
    Huber, M. L. et al. (2009), New international formulation for the viscosity of H2O,
    J. Phys. Chem. Ref. Data 38:101-125, doi:10.1063/1.3088050, evaluated at the IAPWS-95
    density, as implemented in CoolProp.
    """
    return _liquid_states(T, P)[0]


def water_surface_tension_iapws(T):
    """Surface tension of water against its vapour by IAPWS R1-76 (2014) [N/m].

    Parameters
    ----------
    T : array_like
        Temperature [K], from 248.15 K (supercooled) to the critical point 647.096 K.

    Notes
    -----
    IAPWS R1-76(2014), Revised release on surface tension of ordinary water substance;
    Vargaftik, N. B., Volkov, B. N., Voljak, L. D. (1983), J. Phys. Chem. Ref. Data
    12:817-820, doi:10.1063/1.555688::

        sigma = 235.8e-3 tau^1.256 (1 - 0.625 tau),  tau = 1 - T / 647.096
    """
    T = check_range("T", T, 248.15, _T_CRIT, hi_open=True, unit="K")
    tau = 1.0 - T / _T_CRIT
    return 235.8e-3 * tau**1.256 * (1.0 - 0.625 * tau)


def water_liquid(T, P=101325.0, *, theta_deg=0.0) -> Liquid:
    """Liquid water at ``T`` [K] and ``P`` [Pa] as an :class:`~agglomtool.Liquid`.

    Viscosity by :func:`water_viscosity_huber`, density by
    :func:`water_density_wagner_pruss`, surface tension by
    :func:`water_surface_tension_iapws`; ``theta_deg`` is the contact angle [deg].
    """
    mu, rho = _liquid_states(T, P)
    gamma = water_surface_tension_iapws(np.broadcast_to(T, np.shape(mu)))
    return Liquid(
        mu=mu, gamma=gamma, rho=rho, theta_deg=theta_deg, name="water",
        source=f"CoolProp {CoolProp.__version__}: IAPWS-95 density, IAPWS 2008 viscosity; "
        "IAPWS R1-76 surface tension",
    )
