"""Viscosity of molten slags and ash melts from their oxide composition.

No installed library implements these models; they are written here from the published
equations. Each function warns when the composition or temperature lies outside the model's
calibration: for K-Ca silicates at 800 C the models disagree by several decades, so the
caller must know which model produced a number (see :func:`agglomtool.properties.melt_liquid`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._validate import PlausibilityWarning, check_range
from .slag_composition import molar_mass, mole_fractions, normalise_wt

__all__ = ["viscosity_giordano_russell_dingwell", "viscosity_urbain_mills", "viscosity_riboud"]


def _warn(msg: str) -> None:
    """A value outside a correlation's calibration: plausible input, implausible answer."""
    warnings.warn(msg, PlausibilityWarning, stacklevel=3)


def _temperature(T) -> np.ndarray:
    return check_range("T", T, 0.0, None, lo_open=True, unit="K")


# GRD (2008) coefficients, their Table 1; the composition terms are mol % oxides.
_GRD_A = -4.55
_GRD_B = (159.56, -173.34, 72.13, 75.69, -38.98, -84.08, 141.54, -2.43, -0.91, 17.62)
_GRD_C = (2.75, 15.72, 8.32, 10.20, -12.29, -99.54, 0.30)
_GRD_OXIDES = ("SiO2", "TiO2", "Al2O3", "FeO", "MnO", "MgO", "CaO", "Na2O", "K2O", "P2O5", "H2O")


def viscosity_giordano_russell_dingwell(composition: Mapping[str, float], T):
    """Melt viscosity by Giordano, Russell and Dingwell (2008) [Pa s].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100. Total iron is taken as FeO (Fe2O3 is converted).
    T : array_like
        Temperature [K].

    Returns
    -------
    numpy.ndarray
        Viscosity [Pa s].

    Notes
    -----
    Giordano, D., Russell, J. K., Dingwell, D. B. (2008), Viscosity of magmatic liquids: a
    model, Earth Planet. Sci. Lett. 271:123-134, doi:10.1016/j.epsl.2008.03.038. A
    Vogel-Fulcher-Tammann law with a common high-temperature limit::

        log10 eta = A + B / (T - C),  A = -4.55,

    with ``B`` and ``C`` linear in mol % oxides plus cross terms (V = H2O, TA = TiO2 + Al2O3,
    FM = FeO + MnO + MgO, NK = Na2O + K2O)::

        B = 159.56 (SiO2+TiO2) - 173.34 Al2O3 + 72.13 (FeO+MnO+P2O5) + 75.69 MgO
            - 38.98 CaO - 84.08 (Na2O+V) + 141.54 (V + ln(1+H2O))
            - 2.43 (SiO2+TiO2) FM - 0.91 (SiO2+TA+P2O5)(NK+H2O) + 17.62 Al2O3 NK
        C = 2.75 SiO2 + 15.72 TA + 8.32 FM + 10.20 CaO - 12.29 NK - 99.54 ln(1+V)
            + 0.30 (Al2O3 + FM + CaO - P2O5)(NK + V)

    Fluorine (the F2O-1 part of V) is not supported. Calibrated on natural silicate melts
    (about 41-79 wt % SiO2) over log10 eta = -1 to 12: the defensible default for
    silica-rich alkali ash melts at 800-1000 C. It is unreliable for CaO-rich metallurgical
    slags (about 100x too low for a blast-furnace slag at 1500 C).
    """
    T = _temperature(T)
    wt = normalise_wt(composition)
    if "Fe2O3" in wt:
        wt["FeO"] = wt.get("FeO", 0.0) + wt.pop("Fe2O3") * 2 * molar_mass("FeO") / molar_mass(
            "Fe2O3"
        )
    other = sorted(k for k in wt if k not in _GRD_OXIDES)
    if other:
        _warn(f"GRD (2008) has no terms for {other}; they are ignored")
    x = mole_fractions({k: v for k, v in wt.items() if k in _GRD_OXIDES})
    m = {k: 100.0 * x.get(k, 0.0) for k in _GRD_OXIDES}  # mol %
    v = m["H2O"]
    ta = m["TiO2"] + m["Al2O3"]
    fm = m["FeO"] + m["MnO"] + m["MgO"]
    nk = m["Na2O"] + m["K2O"]
    siti = m["SiO2"] + m["TiO2"]
    b_terms = (
        siti, m["Al2O3"], m["FeO"] + m["MnO"] + m["P2O5"], m["MgO"], m["CaO"], m["Na2O"] + v,
        v + np.log1p(m["H2O"]), siti * fm, (m["SiO2"] + ta + m["P2O5"]) * (nk + m["H2O"]),
        m["Al2O3"] * nk,
    )  # fmt: skip
    c_terms = (
        m["SiO2"], ta, fm, m["CaO"], nk, np.log1p(v),
        (m["Al2O3"] + fm + m["CaO"] - m["P2O5"]) * (nk + v),
    )  # fmt: skip
    b = sum(c * t for c, t in zip(_GRD_B, b_terms, strict=True))
    c = sum(k * t for k, t in zip(_GRD_C, c_terms, strict=True))
    glass = T <= c
    if glass.any():
        T_b, c_b = np.broadcast_arrays(T, c)
        n = int(np.count_nonzero(glass))
        which = "" if glass.size == 1 else f" ({n} of {glass.size} compositions and T)"
        raise ValueError(
            f"T = {T_b[glass].flat[0]:g} K is at or below the VFT temperature C = "
            f"{c_b[glass].flat[0]:.1f} K of GRD (2008) for this composition{which}: the "
            "melt is a glass there"
        )
    log_eta = _GRD_A + b / (T - c)
    sio2, cao = np.asarray(wt.get("SiO2", 0.0)), np.asarray(wt.get("CaO", 0.0))
    outside = (sio2 < 40.0) | (sio2 > 80.0) | (cao > 25.0)
    if outside.any():
        share = (f" ({int(np.count_nonzero(outside))} of {outside.size} compositions)"
                 if outside.size > 1 else "")
        _warn(f"composition outside GRD (2008) calibration{share} (natural silicate melts, "
              "about 41-79 wt % SiO2, CaO <= 25 wt %)")
    if (log_eta < -1.0).any() or (log_eta > 12.0).any():
        _warn("viscosity outside the GRD (2008) calibration range log10 eta = -1 to 12 Pa s")
    return 10.0**log_eta


# Urbain's cation-specific coefficients as tabulated by Mills: B_k = a_k + b_k alpha + c_k
# alpha^2, k = 0..3, for modifier groups Ca, Mg, Mn.
_URBAIN_A = np.array([13.2, 30.5, -40.4, 60.8])
_URBAIN_BC = {
    "Ca": (np.array([41.5, -117.2, 232.1, -156.4]), np.array([-45.0, 130.0, -298.6, 213.6])),
    "Mg": (np.array([15.9, -54.1, 138.0, -99.8]), np.array([-18.6, 33.0, -112.0, 97.6])),
    "Mn": (np.array([20.0, 26.0, -110.3, 64.3]), np.array([-25.6, -56.0, 186.2, -104.6])),
}
#: Modifier weight (per mole of oxide) in X_M, and the cation group it is averaged with.
_URBAIN_MODIFIERS = {
    "CaO": (1, "Ca"), "Na2O": (1, "Ca"), "K2O": (1, "Ca"), "Li2O": (1, "Ca"),
    "BaO": (1, "Ca"), "SrO": (1, "Ca"), "CaF2": (3, "Ca"), "MgO": (1, "Mg"),
    "FeO": (1, "Mn"), "MnO": (1, "Mn"), "TiO2": (2, None), "ZrO2": (2, None),
}  # fmt: skip
_URBAIN_FORMERS = ("SiO2", "P2O5")
_URBAIN_AMPHOTERICS = ("Al2O3", "Fe2O3", "B2O3")


def viscosity_urbain_mills(composition: Mapping[str, float], T):
    """Slag viscosity by Urbain's model with Mills's cation-specific parameters [Pa s].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100.
    T : array_like
        Temperature [K].

    Returns
    -------
    numpy.ndarray
        Viscosity [Pa s].

    Notes
    -----
    Urbain, G., Cambier, F., Deletter, M., Anseau, M. R. (1981), Viscosity of silicate
    melts, Trans. J. Br. Ceram. Soc. 80:139-141; parameters as tabulated by Mills in the
    Slag Atlas (VDEh, 2nd ed. 1995, ch. 9) and Mills (2011), The estimation of slag
    properties, Southern African Pyrometallurgy conference::

        eta [dPa s] = A T exp(1000 B / T),   ln A = -(0.29 B + 11.57)
        X_G = SiO2 + P2O5;  X_A = Al2O3 + Fe2O3 + B2O3
        X_M = CaO + MgO + Na2O + K2O + Li2O + BaO + SrO + FeO + MnO + 3 CaF2 + 2 TiO2 + 2 ZrO2
        (each divided by X_G + X_M + X_A so that they sum to 1)
        alpha = X_M / (X_M + X_A);  B = sum_k (a_k + b_k alpha + c_k alpha^2) X_G^k

    ``B`` is found with the (b, c) of Ca, Mg and Mn and averaged with the mole fractions of
    the modifiers of each group (alkali and alkaline-earth oxides with Ca, FeO with Mn).
    The normalisation by the weighted sum is this package's reading: the two sources
    reachable when it was written differ on it (see ``materials/README.md``). Calibrated on
    fully liquid CaO-Al2O3-SiO2(-MgO-FeO) slags and coal ashes, about +-25-30 %.
    """
    T = _temperature(T)
    x = mole_fractions(normalise_wt(composition))
    xg = sum(x.get(k, 0.0) for k in _URBAIN_FORMERS)
    xa = sum(x.get(k, 0.0) for k in _URBAIN_AMPHOTERICS)
    xm = sum(w * x.get(k, 0.0) for k, (w, _) in _URBAIN_MODIFIERS.items())
    ignored = sorted(k for k in x if k not in _URBAIN_MODIFIERS
                     and k not in _URBAIN_FORMERS + _URBAIN_AMPHOTERICS)
    if ignored:
        _warn(f"Urbain-Mills has no terms for {ignored}; they are ignored")
    total = xg + xm + xa
    xg, xm, xa = xg / total, xm / total, xa / total
    if (np.asarray(xm) <= 0.0).any():
        raise ValueError("Urbain-Mills needs at least one modifier oxide (CaO, MgO, FeO, ...)")
    alpha = np.asarray(xm / (xm + xa))[..., None]
    # X_G^k, k = 0..3, along a last axis (one row per composition)
    powers = np.asarray(xg)[..., None] ** np.arange(4)
    weights: dict[str, Any] = {"Ca": 0.0, "Mg": 0.0, "Mn": 0.0}
    for k, (_, group) in _URBAIN_MODIFIERS.items():
        if group is not None:
            weights[group] += x.get(k, 0.0)
    wsum: Any = sum(weights.values())
    none = np.asarray(wsum) <= 0.0  # no grouped modifier (TiO2 or ZrO2 only): Ca's
    if none.any():
        weights = {"Ca": np.where(none, 1.0, weights["Ca"]), "Mg": weights["Mg"],
                   "Mn": weights["Mn"]}
        wsum = np.where(none, 1.0, wsum)
    b = 0.0
    for group, w in weights.items():
        bk, ck = _URBAIN_BC[group]
        b += w / wsum * np.sum((_URBAIN_A + bk * alpha + ck * alpha**2) * powers, axis=-1)
    b = b if np.ndim(b) else float(b)
    ln_a = -(0.29 * b + 11.57)
    xg_ = np.asarray(xg)
    if (xg_ < 0.2).any() or (xg_ > 0.7).any() or (T < 1473.0).any():
        _warn("composition or temperature outside the Urbain-Mills calibration (fully "
              "liquid slags, X_SiO2 about 0.2-0.7, T >= 1473 K)")
    return 0.1 * np.exp(ln_a + np.log(T) + 1000.0 * b / T)


def viscosity_riboud(composition: Mapping[str, float], T):
    """Mould-flux viscosity by Riboud et al. (1981) [Pa s].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100.
    T : array_like
        Temperature [K].

    Returns
    -------
    numpy.ndarray
        Viscosity [Pa s].

    Notes
    -----
    Riboud, P. V., Roux, Y., Lucas, L. D., Gaye, H. (1981), Improvement of continuous
    casting powders, Fachber. Huttenprax. Metallweiterverarb. 19:859-869; as reviewed by
    Mills (Slag Atlas, 1995) and Kekkonen, Oghbasilasie and Louhenkilpi (2012), Viscosity
    models for molten slags, Aalto University report 12/2012::

        eta [Pa s] = A T exp(B / T)
        ln A = -19.81 + 1.73 X_C + 5.82 X_CaF2 + 7.02 X_N - 35.76 X_Al2O3
        B = 31140 - 23896 X_C - 46356 X_CaF2 - 39159 X_N + 68833 X_Al2O3

    with mole fractions on a single-cation basis for Fe(III) and B (Fe2O3 -> 2 FeO1.5,
    B2O3 -> 2 BO1.5): X_C = CaO + MgO + FeO + FeO1.5 + MnO + BO1.5 + BaO + SrO,
    X_N = Na2O + K2O + Li2O. Calibrated on CaO-SiO2-Al2O3-CaF2-Na2O mould fluxes at
    1473-1773 K.
    """
    T = _temperature(T)
    wt = normalise_wt(composition)
    moles = {k: v / molar_mass(k) for k, v in wt.items()}
    for oxide in ("Fe2O3", "B2O3"):  # two single-cation units per formula unit
        moles[oxide] = 2.0 * moles.get(oxide, 0.0)
    total = sum(moles.values())
    x = {k: v / total for k, v in moles.items()}
    xc = sum(x.get(k, 0.0) for k in ("CaO", "MgO", "FeO", "Fe2O3", "MnO", "B2O3", "BaO", "SrO"))
    xn = sum(x.get(k, 0.0) for k in ("Na2O", "K2O", "Li2O"))
    xf, xal = x.get("CaF2", 0.0), x.get("Al2O3", 0.0)
    ln_a = -19.81 + 1.73 * xc + 5.82 * xf + 7.02 * xn - 35.76 * xal
    b = 31140.0 - 23896.0 * xc - 46356.0 * xf - 39159.0 * xn + 68833.0 * xal
    # The calibration spans 1473-1773 K; an Arrhenius form is trusted 100 K beyond it.
    if (T < 1373.0).any() or (T > 1873.0).any():
        _warn(f"T = {float(T.min()):g}-{float(T.max()):g} K reaches more than 100 K beyond "
              "the Riboud calibration (mould fluxes, 1473-1773 K)")
    if (np.asarray(xal) > 0.2).any():
        _warn(f"Al2O3 = {float(np.max(xal)):.3g} mole fraction is above the Riboud calibration "
              "(mould fluxes, Al2O3 <= 0.2)")
    return np.exp(ln_a + np.log(T) + b / T)
