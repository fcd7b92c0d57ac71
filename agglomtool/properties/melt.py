"""A molten slag or ash melt as a collision liquid: choose the models, build the Liquid."""

from __future__ import annotations

from collections.abc import Mapping

from ..inputs import Liquid
from .slag_composition import normalise_wt
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


def choose_viscosity_model(composition: Mapping[str, float]) -> str:
    """The viscosity model for a composition (wt %), by a rule on its chemistry.

    1. CaF2 >= 2 wt %: ``"riboud"``, the only one of the three with a fluoride term
       (mould fluxes).
    2. SiO2 >= 50 wt %: ``"grd"``, silica-rich melts such as K2O-CaO-SiO2 biomass ash,
       down toward the glass transition.
    3. Otherwise ``"urbain-mills"``: CaO-Al2O3-SiO2 slags and coal ash, fully liquid.
    """
    wt = normalise_wt(composition)
    if wt.get("CaF2", 0.0) >= 2.0:
        return "riboud"
    if wt.get("SiO2", 0.0) >= 50.0:
        return "grd"
    return "urbain-mills"


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
        Oxide -> wt %, summing to 100.
    T : array_like
        Temperature [K].
    viscosity_model : {"auto", "grd", "urbain-mills", "riboud"}
        ``"auto"`` applies :func:`choose_viscosity_model`.
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
    chosen = choose_viscosity_model(composition) if viscosity_model == "auto" else viscosity_model
    if chosen not in VISCOSITY_MODELS:
        raise ValueError(
            f"viscosity_model = {viscosity_model!r} is not one of "
            f"{['auto', *VISCOSITY_MODELS]}"
        )
    func, cite = VISCOSITY_MODELS[chosen]
    mu = func(composition, T)
    gamma = surface_tension_mills(composition, T)
    rho = density_mills_keene(composition, T)
    how = "chosen by rule" if viscosity_model == "auto" else "requested"
    source = (
        f"viscosity: {chosen} ({how}), {cite}; surface tension: Mills (2011) additive model; "
        "density: Mills & Keene (1987) partial molar volumes"
    )
    return Liquid(mu=mu, gamma=gamma, rho=rho, theta_deg=theta_deg, name=name or "melt",
                  source=source)


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
