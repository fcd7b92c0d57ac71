"""Gas viscosity and density at bed conditions: pure fluids and mixtures.

Pure fluids come from CoolProp's reference equations of state and viscosity correlations
(Bell et al. 2014, doi:10.1021/ie4033999). Mixtures combine CoolProp pure-component
properties: Wilke's rule for viscosity and Dalton's law for density (each component at its
own partial pressure), which is exact for ideal gases and keeps each component's own
non-ideality. CoolProp's HEOS mixture model is not used for viscosity: its mixture
viscosity is a crude mole-fraction average that CoolProp itself labels highly approximate,
and it evaluates a humid gas below its dew point inside the water dome without complaint.
"""

from __future__ import annotations

from collections.abc import Mapping
from importlib import metadata

import numpy as np

from .._validate import check_range
from ..inputs import Gas
from ._gas_tables import (
    SPECIES_FORMULAS,
    CondensedPhaseError,
    _cp,
    species_info,
    species_state,
)

__all__ = ["gas_properties", "viscosity_wilke", "mixture_density_dalton", "SPECIES_FORMULAS"]

#: CoolProp's version, for the source text (read without importing CoolProp).
_COOLPROP = metadata.version("CoolProp")


def viscosity_wilke(x, mu, molar_mass):
    """Viscosity of a dilute gas mixture by Wilke's rule [Pa s].

    Parameters
    ----------
    x : array_like, shape (n, ...)
        Mole fractions [-] of the n components, summing to 1 along axis 0.
    mu : array_like, shape (n, ...)
        Pure-component viscosities [Pa s] at the mixture temperature.
    molar_mass : array_like, shape (n,)
        Molar masses [kg/mol].

    Returns
    -------
    numpy.ndarray
        Mixture viscosity [Pa s], shape ``mu.shape[1:]``.

    Notes
    -----
    Wilke, C. R. (1950), A viscosity equation for gas mixtures, J. Chem. Phys. 18:517-519,
    doi:10.1063/1.1747673::

        mu_mix = sum_i x_i mu_i / sum_j x_j Phi_ij
        Phi_ij = [1 + (mu_i/mu_j)^(1/2) (M_j/M_i)^(1/4)]^2 / [8 (1 + M_i/M_j)]^(1/2)
    """
    x = np.asarray(x, dtype=float)
    mu = np.asarray(mu, dtype=float)
    m = np.asarray(molar_mass, dtype=float)
    extra = (1,) * (mu.ndim - 1)
    mi = m.reshape((-1, 1) + extra)
    mj = m.reshape((1, -1) + extra)
    ratio = np.sqrt(mu[:, None] / mu[None, :])
    phi = (1.0 + ratio * (mj / mi) ** 0.25) ** 2 / np.sqrt(8.0 * (1.0 + mi / mj))
    denom = np.sum(x[None, :] * phi, axis=1)
    return np.sum(x * mu / denom, axis=0)


def mixture_density_dalton(rho_partial):
    """Mixture density as the sum of component densities at their partial pressures [kg/m3].

    Parameters
    ----------
    rho_partial : array_like, shape (n, ...)
        Density [kg/m3] of each pure component at the mixture temperature and its partial
        pressure ``x_i P``.

    Notes
    -----
    Dalton's law of additive pressures. Exact for ideal gases; neglects the unlike-pair
    virial terms only, which for flue gases at bed conditions (T >= 400 K, P <= 20 bar)
    change the density by at most 0.2 % (0.1 % at T >= 450 K; benchmarked against
    CoolProp's HEOS mixture).
    """
    return np.sum(np.asarray(rho_partial, dtype=float), axis=0)


def _resolve(composition) -> tuple[dict[str, float], str]:
    """Mole fractions by species formula, and a name for the result."""
    if isinstance(composition, str):
        from .. import materials

        entry = materials.gas(composition)
        return dict(entry.composition), entry.name
    if not isinstance(composition, Mapping):
        raise ValueError(
            "composition must be a gas name from the materials database or a dict of mole "
            f"fractions, got {composition!r}"
        )
    fractions: dict[str, float] = {}
    for key, value in composition.items():
        species_info(key)
        frac = float(check_range(f"composition[{key!r}]", value, 0.0, 1.0, unit="mol/mol"))
        if frac > 0.0:
            fractions[key] = frac
    total = sum(fractions.values())
    if abs(total - 1.0) > 1e-3:
        raise ValueError(
            f"mole fractions in composition sum to {total:g}; they must sum to 1 "
            "(within 1e-3; give fractions, not percent)"
        )
    return {k: v / total for k, v in fractions.items()}, "gas mixture"


def _dew_point_message(exc: CondensedPhaseError, x: float, P: float) -> str:
    sp = species_info(exc.species)
    try:
        t_dew = _cp().PropsSI("T", "P", exc.P, "Q", 1, sp.coolprop)
        dew = f"; its dew point at that partial pressure is {t_dew:.2f} K"
    except ValueError:
        dew = ""
    return (
        f"gas at T = {exc.T:g} K, P = {P:g} Pa is below the {exc.species} dew point: "
        f"{exc.species} (mole fraction {x:g}, partial pressure {exc.P:g} Pa) would be "
        f"{exc.phase}{dew}. No property is returned for a condensing gas."
    )


def gas_properties(
    T,
    P,
    composition="air",
    *,
    method: str = "table",
    beyond_range: str = "raise",
) -> Gas:
    """Viscosity and density of a gas at temperature ``T`` and pressure ``P``.

    Parameters
    ----------
    T : array_like
        Temperature [K], > 0.
    P : array_like
        Absolute pressure [Pa], > 0. Broadcasts with ``T``.
    composition : str or dict
        A gas name from the materials database (``"air"``, ``"nitrogen"``, ``"steam"``,
        ``"biomass-flue-gas"``, ...) or a dict of mole fractions keyed by formula:
        ``N2, O2, CO2, H2O, Ar, CO, H2, CH4`` (and ``Air`` for dry air as one component).
        Fractions must sum to 1 within 1e-3.
    method : {"table", "heos"}
        ``"table"`` (default) interpolates tables built from CoolProp HEOS and checked
        against it to 2e-4 per cell (HEOS is called directly where a cell fails the check);
        ``"heos"`` calls CoolProp HEOS for every state (about 10-25 us each).
    beyond_range : {"raise", "extrapolate"}
        Above a species' validated upper temperature (CoolProp's equation-of-state limit:
        2000 K for air, N2, O2, CO2, H2O, Ar; 1000 K for H2; 625 K for CH4; 500 K for CO)
        ``"raise"`` (default) raises ``ValueError``; ``"extrapolate"`` evaluates the
        equation of state and viscosity correlation beyond their range (for a dilute gas
        this is close to ideal-gas behaviour, but it is not validated), up to 2000 K.

    Returns
    -------
    agglomtool.Gas
        ``mu`` [Pa s] and ``rho`` [kg/m3], arrays of the broadcast shape of ``T`` and ``P``,
        with ``name`` and ``source`` saying how they were obtained.

    Raises
    ------
    ValueError
        For invalid inputs, states outside the models' range, and states where a component
        would condense (for a humid gas: below the water dew point).

    Notes
    -----
    A pure species (one component, or a database entry such as air) is evaluated at ``P``.
    A mixture is evaluated component by component at its partial pressure ``x_i P`` (so
    the water of a humid gas is a vapour exactly when the gas is above its dew point) and
    combined by :func:`viscosity_wilke` and :func:`mixture_density_dalton`.

    References: Lemmon et al. (2000), doi:10.1063/1.1285884 (air); Lemmon and Jacobsen
    (2004), doi:10.1023/B:IJOT.0000022327.04529.f3 (air viscosity); Wagner and Pruss
    (2002), doi:10.1063/1.1461829 and Huber et al. (2009), doi:10.1063/1.3088050 (water);
    Wilke (1950), doi:10.1063/1.1747673.
    """
    T = check_range("T", T, 0.0, None, lo_open=True, unit="K")
    P = check_range("P", P, 0.0, None, lo_open=True, unit="Pa")
    if beyond_range not in ("raise", "extrapolate"):
        raise ValueError(f"beyond_range = {beyond_range!r} is not one of 'raise', 'extrapolate'")
    fractions, name = _resolve(composition)
    T_b, P_b = np.broadcast_arrays(T, P)
    shape = T_b.shape
    t1, p1 = T_b.ravel(), P_b.ravel()
    opts = {"method": method, "beyond_range": beyond_range}
    if len(fractions) == 1:
        (formula,) = fractions
        mu, rho = species_state(formula, t1, p1, **opts)
        source = f"CoolProp {_COOLPROP} HEOS ({species_info(formula).coolprop}), {method}"
    else:
        formulas = list(fractions)
        x = np.array([fractions[f] for f in formulas])
        mus, rhos = [], []
        for f, xi in zip(formulas, x, strict=True):
            try:
                mu_i, rho_i = species_state(f, t1, xi * p1, **opts)
            except CondensedPhaseError as exc:
                raise ValueError(_dew_point_message(exc, xi, exc.P / xi)) from None
            mus.append(mu_i)
            rhos.append(rho_i)
        molar = np.array([species_info(f).molar_mass for f in formulas])
        mu = viscosity_wilke(x[:, None], np.array(mus), molar)
        rho = mixture_density_dalton(np.array(rhos))
        source = (
            f"CoolProp {_COOLPROP} pure components ({method}) at partial pressures; "
            "Wilke (1950) viscosity, Dalton density"
        )
    return Gas(mu=mu.reshape(shape), rho=rho.reshape(shape), name=name, source=source)
