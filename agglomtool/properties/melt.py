"""A molten slag or ash melt as a collision liquid: choose the models, build the Liquid."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..inputs import Liquid
from .slag_composition import NormalisedWt, is_array_composition, normalise_wt
from .slag_surface import density_mills_keene, surface_tension_mills
from .slag_viscosity import (
    viscosity_giordano_russell_dingwell,
    viscosity_riboud,
    viscosity_urbain_mills,
)

__all__ = ["VISCOSITY_MODELS", "choose_viscosity_model", "melt_liquid", "fixed_liquid"]

#: Viscosity models by name, with the citation that goes into ``Liquid.source``.
VISCOSITY_MODELS = {
    "grd": (viscosity_giordano_russell_dingwell,
            "Giordano, Russell & Dingwell (2008) doi:10.1016/j.epsl.2008.03.038"),
    "urbain-mills": (viscosity_urbain_mills, "Urbain et al. (1981) with Mills's parameters"),
    "riboud": (viscosity_riboud, "Riboud et al. (1981)"),
}


def _rule(wt: Mapping) -> np.ndarray | str:
    """The rule of :func:`choose_viscosity_model` on a normalised composition: a name, or
    for array compositions an array of names, one per element."""
    caf2 = np.asarray(wt.get("CaF2", 0.0))
    sio2 = np.asarray(wt.get("SiO2", 0.0))
    chosen = np.where(caf2 >= 2.0, "riboud", np.where(sio2 >= 50.0, "grd", "urbain-mills"))
    return str(chosen) if chosen.ndim == 0 else chosen


def choose_viscosity_model(composition: Mapping[str, float]):
    """The viscosity model for a composition (wt %), by a rule on its chemistry.

    1. CaF2 >= 2 wt %: ``"riboud"``, the only one of the three with a fluoride term
       (mould fluxes).
    2. SiO2 >= 50 wt %: ``"grd"``, silica-rich melts such as K2O-CaO-SiO2 biomass ash,
       down toward the glass transition.
    3. Otherwise ``"urbain-mills"``: CaO-Al2O3-SiO2 slags and coal ash, fully liquid.

    A composition of arrays (one per element) gives an array of names: the rule applies
    to each composition, so the model may change from one element to the next.
    """
    return _rule(normalise_wt(composition))


def melt_liquid(
    composition: Mapping[str, float],
    T,
    *,
    viscosity_model: str = "auto",
    theta_deg=0.0,
    name: str | None = None,
) -> Liquid:
    """Viscosity, surface tension and density of a melt of given oxides at ``T``.

    Parameters
    ----------
    composition : dict
        Oxide -> wt %, summing to 100. The values may be arrays (one composition per
        element, broadcast against ``T``), as a Monte Carlo over an uncertain composition
        draws them.
    T : array_like
        Temperature [K].
    viscosity_model : {"auto", "grd", "urbain-mills", "riboud"}
        ``"auto"`` applies :func:`choose_viscosity_model` (to each composition).
    theta_deg : float
        Contact angle on the bed solid [deg].
    name : str, optional
        Name carried by the result.

    Returns
    -------
    agglomtool.Liquid
        ``source`` names the three models that produced ``mu``, ``gamma`` and ``rho``:
        the chosen viscosity model, Mills's surface tension
        (:func:`~agglomtool.properties.surface_tension_mills`) and the Mills-Keene density
        (:func:`~agglomtool.properties.density_mills_keene`). Each model warns outside its
        calibration.
    """
    if viscosity_model != "auto" and viscosity_model not in VISCOSITY_MODELS:
        raise ValueError(
            f"viscosity_model = {viscosity_model!r} is not one of "
            f"{['auto', *VISCOSITY_MODELS]}"
        )
    wt = normalise_wt(composition)
    if not is_array_composition(wt):
        chosen = str(_rule(wt)) if viscosity_model == "auto" else viscosity_model
        func, cite = VISCOSITY_MODELS[chosen]
        mu = func(wt, T)
        how = "chosen by rule" if viscosity_model == "auto" else "requested"
        used = f"{chosen} ({how}), {cite}"
    else:
        mu, used = _viscosity_per_element(wt, T, viscosity_model)
    gamma = surface_tension_mills(wt, T)
    rho = density_mills_keene(wt, T)
    source = (
        f"viscosity: {used}; surface tension: Mills (2011) additive model; "
        "density: Mills & Keene (1987) partial molar volumes"
    )
    return Liquid(mu=mu, gamma=gamma, rho=rho, theta_deg=theta_deg, name=name or "melt",
                  source=source)


def _viscosity_per_element(wt: Mapping, T, viscosity_model: str):
    """Viscosity of array compositions: each element by its model (the rule's, where
    ``"auto"``), each model evaluated once on the elements that use it."""
    shape = np.broadcast_shapes(np.shape(T), next(iter(wt.values())).shape)
    T_b = np.broadcast_to(np.asarray(T, dtype=float), shape)
    wt_b = {k: np.broadcast_to(v, shape) for k, v in wt.items()}
    if viscosity_model == "auto":
        chosen = np.broadcast_to(_rule(wt_b), shape)
    else:
        chosen = np.full(shape, viscosity_model)
    mu = np.empty(shape)
    used = []
    for model, (func, cite) in VISCOSITY_MODELS.items():
        here = chosen == model
        n = int(np.count_nonzero(here))
        if n == 0:
            continue
        mu[here] = func(NormalisedWt({k: v[here] for k, v in wt_b.items()}), T_b[here])
        share = "" if n == here.size else f" for {n} of {here.size} compositions"
        used.append(f"{model}{share}, {cite}")
    how = "chosen by rule" if viscosity_model == "auto" else "requested"
    return mu, f"{'; '.join(used)} ({how})"


def fixed_liquid(mu, gamma, rho, theta_deg=0.0, *, name=None, source=None) -> Liquid:
    """A liquid of fixed properties, such as the paper's "hypothetical slag".

    Parameters
    ----------
    mu : float
        Viscosity [Pa s].
    gamma : float
        Surface tension [N/m].
    rho : float
        Density [kg/m3].
    theta_deg : float
        Contact angle [deg].

    Notes
    -----
    Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Table 2:
    the hypothetical slag has mu = 10 Pa s, gamma = 0.400 N/m, rho = 2500 kg/m3.
    """
    return Liquid(mu=mu, gamma=gamma, rho=rho, theta_deg=theta_deg, name=name,
                  source=source or "fixed values")
