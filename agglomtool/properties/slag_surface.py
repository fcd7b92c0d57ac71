"""Surface tension and density of molten slags and ash melts from their oxide composition.

No installed library implements these models; they are written here from the published
equations, with the coefficient sources and their verification status recorded in
``materials/README.md``.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._validate import PlausibilityWarning, check_range
from .slag_composition import molar_mass, mole_fractions, normalise_wt

__all__ = ["surface_tension_mills", "surface_tension_kucuk", "density_mills_keene"]

#: Mills's partial surface tensions at 1773 K [mN/m] and their temperature coefficients
#: [mN/(m K)], Mills (2011) and Mills et al. (2016), doi:10.2355/isijinternational.ISIJINT-2015-364.
_MILLS_GAMMA = {
    "SiO2": (260.0, 0.031), "TiO2": (360.0, -0.15), "Al2O3": (655.0, -0.177),
    "FeO": (645.0, 0.1), "MgO": (635.0, -0.13), "MnO": (645.0, -0.1), "CaO": (625.0, -0.094),
    "Na2O": (295.0, -0.11), "K2O": (160.0, -0.11), "Li2O": (300.0, -0.11),
    "CaF2": (290.0, -0.07), "ZrO2": (400.0, -0.15), "B2O3": (110.0, 0.04),
    "Fe2O3": (300.0, -0.05), "BaO": (560.0, -0.1), "SrO": (600.0, -0.1),
}  # fmt: skip

#: Piecewise replacements of X_i gamma_i for surface-active components [mN/m]:
#: (X_switch, (c0, c1, c2) below, (d0, d1) at or above the switch).
_MILLS_ACTIVE = {
    "K2O": (0.115, (0.8, -1388.0, 6723.0), (-94.5, 254.5)),
    "CaF2": (0.13, (-2.0, -934.0, 4769.0), (-92.5, 382.5)),
    "B2O3": (0.1, (-5.2, -3454.0, 22178.0), (-155.3, 265.3)),
    "Fe2O3": (0.125, (-3.7, -2972.0, 14312.0), (-216.2, 516.2)),
}


def _left_out(model: str, unknown: list, x: Mapping) -> None:
    """Say which oxides of the user's melt a model has no term for, and how much of the melt
    they are: their share is left out of the model's sum (a PlausibilityWarning, so that
    ``--strict`` or an error filter turns it into an error)."""
    share = sum(float(np.max(np.asarray(x[k]))) for k in unknown)
    warnings.warn(f"{model} has no term for {', '.join(unknown)} (up to {share:.3g} mole "
                  "fraction of the melt): that share is left out of its sum",
                  PlausibilityWarning, stacklevel=3)

def surface_tension_mills(composition: Mapping[str, float], T, *, temperature="per-oxide"):
    """Surface tension of a slag by Mills's additive model [N/m].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100.
    T : array_like
        Temperature [K].
    temperature : {"per-oxide", "uniform"}
        ``"per-oxide"`` (default) uses each oxide's d(gamma)/dT of Mills et al. (2016);
        ``"uniform"`` uses -0.15 mN/(m K) for the whole melt (Mills 2011), which
        over-corrects silica-rich melts, whose d(gamma)/dT is close to zero.

    Returns
    -------
    numpy.ndarray
        Surface tension [N/m].

    Notes
    -----
    Mills, K. C. (2011), The estimation of slag properties, Southern African
    Pyrometallurgy 2011; Mills, K. C., Karagadde, S., Lee, P. D., Yuan, L., Shahbazian, F.
    (2016), ISIJ Int. 56:264-273, doi:10.2355/isijinternational.ISIJINT-2015-364::

        gamma(1773 K) = sum_i X_i gamma_i   [mN/m]

    where the surface-active K2O, CaF2, B2O3 and Fe2O3 replace ``X_i gamma_i`` by fitted
    functions of ``X_i``. Na2O keeps the plain additive term: the Na2O fit available to this
    package (a transcription identical to the K2O one below X = 0.115, and negative above)
    could not be checked against Mills's paper, and with it the model falls 27 % below the
    Kucuk et al. (1999) regression for a soda-lime glass, the melts that regression was
    fitted to; without it the two agree within 6 %.
    """
    T = check_range("T", T, 0.0, None, lo_open=True, unit="K")
    if temperature not in ("per-oxide", "uniform"):
        raise ValueError(f"temperature = {temperature!r} is not one of 'per-oxide', 'uniform'")
    x = mole_fractions(normalise_wt(composition))
    unknown = sorted(k for k in x if k not in _MILLS_GAMMA)
    if unknown:
        _left_out("Mills surface tension", unknown, x)
    gamma_1773: Any = 0.0  # a float, or an array over compositions
    slope = 0.0
    for oxide, xi in x.items():
        if oxide not in _MILLS_GAMMA:
            continue
        g_i, dg_i = _MILLS_GAMMA[oxide]
        slope += xi * dg_i
        active = _MILLS_ACTIVE.get(oxide)
        if active is None:
            gamma_1773 += xi * g_i
            continue
        x_switch, (c0, c1, c2), high = active
        if np.ndim(xi):  # one composition per element; an absent oxide adds nothing
            gamma_1773 += np.where(xi <= 0.0, 0.0,
                                   np.where(xi < x_switch, c0 + c1 * xi + c2 * xi * xi,
                                            high[0] + high[1] * xi))
        elif xi < x_switch:
            gamma_1773 += c0 + c1 * xi + c2 * xi * xi
        else:
            gamma_1773 += high[0] + high[1] * xi
    if temperature == "uniform":
        slope = -0.15
    gamma = gamma_1773 + slope * (T - 1773.0)
    if (gamma <= 0.0).any():
        raise ValueError("Mills surface tension is not positive for this composition and T")
    return 1e-3 * gamma


#: Kucuk, Clare and Jones (1999) regression coefficients [mN/m per mol %], at 1400 C.
#: Oxides not listed (SiO2, Na2O) carry no term: they set the 271.2 mN/m base.
_KUCUK = {
    "Li2O": 1.48, "K2O": -2.22, "MgO": 1.96, "CaO": 3.34, "BaO": 1.28, "SrO": 3.32,
    "FeO": 2.68, "MnO": 2.92, "B2O3": -2.86, "Al2O3": 3.47,
}  # fmt: skip
_KUCUK_BASE = {"SiO2", "Na2O"}


def surface_tension_kucuk(composition: Mapping[str, float]):
    """Surface tension of a silicate glass melt at 1400 C (1673.15 K) [N/m].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100.

    Returns
    -------
    float
        Surface tension at 1673.15 K [N/m].

    Notes
    -----
    Kucuk, A., Clare, A. G., Jones, L. (1999), An estimation of the surface tension for
    silicate glass melts at 1400 C using statistical analysis, Glass Technol. 40:149-153::

        gamma [mN/m] = 271.2 + sum_i c_i (mol % i)

    Used as an independent check of :func:`surface_tension_mills`.
    """
    x = mole_fractions(normalise_wt(composition))
    unknown = sorted(k for k in x if k not in _KUCUK and k not in _KUCUK_BASE)
    if unknown:
        _left_out("Kucuk (1999) surface tension", unknown, x)
    return 1e-3 * (271.2 + sum(c * 100.0 * x.get(k, 0.0) for k, c in _KUCUK.items()))


#: Mills-Keene partial molar volumes at 1773 K [cm3/mol]: constant, or (a, b, c) for
#: V = a + b X + c X^2 of the oxide's own mole fraction X.
_MILLS_KEENE_V: dict[str, float | tuple[float, float, float]] = {
    "SiO2": (19.55, 7.966, 0.0), "Al2O3": (28.31, 32.0, -31.45), "CaO": 20.7, "MgO": 16.1,
    "FeO": 15.8, "Fe2O3": 38.4, "MnO": 15.6, "Na2O": 33.0, "K2O": 51.8, "TiO2": 24.0,
    "P2O5": 65.7,
}  # fmt: skip


def density_mills_keene(composition: Mapping[str, float], T):
    """Density of a molten slag from partial molar volumes [kg/m3].

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100; oxides without a partial molar volume raise.
    T : array_like
        Temperature [K].

    Returns
    -------
    numpy.ndarray
        Density [kg/m3].

    Notes
    -----
    Mills, K. C., Keene, B. J. (1987), Physical properties of BOS slags, Int. Mater. Rev.
    32:1-120, doi:10.1179/095066087790150296::

        V(1773 K) = sum_i X_i V_i,   V(T) = V(1773 K) (1 + 1e-4 (T - 1773)),
        rho = sum_i X_i M_i / V(T)

    with ``V_SiO2 = 19.55 + 7.966 X_SiO2`` and ``V_Al2O3 = 28.31 + 32.0 X - 31.45 X^2``.
    The +1 % per 100 K expansion is Mills's rule of thumb for liquid slags.
    """
    T = check_range("T", T, 0.0, None, lo_open=True, unit="K")
    x = mole_fractions(normalise_wt(composition))
    unknown = sorted(k for k in x if k not in _MILLS_KEENE_V)
    if unknown:
        raise ValueError(f"Mills-Keene density has no partial molar volume for {unknown}")
    v = 0.0
    for oxide, xi in x.items():
        coef = _MILLS_KEENE_V[oxide]
        vi = coef if isinstance(coef, float) else coef[0] + coef[1] * xi + coef[2] * xi * xi
        v += xi * vi
    mass = sum(xi * molar_mass(k) for k, xi in x.items())  # kg/mol
    return mass / (v * 1e-6 * (1.0 + 1e-4 * (np.asarray(T) - 1773.0)))
