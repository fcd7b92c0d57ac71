"""The paper's Monte Carlo analyses (Table 4) as ready-to-run inputs.

Shabanian, Duchesne, Syamlal and Runstedtler (2024), Heliyon 10:e29397,
doi:10.1016/j.heliyon.2024.e29397: Table 2 (reference cases I, water, and II, slag) and
Table 4 (means, reference and alternative standard deviations of nine uncertain inputs).
The paper states errors as percentages; its standard deviations are one third of them
(e.g. u0: "30 % error", sd = 10 % of the mean).

:func:`table4_case` returns the keyword arguments of
:func:`agglomtool.uncertainty.monte_carlo` (or of the sensitivity functions) for one
case, one mean impact speed and, optionally, one input group at an alternative spread.
"""

from __future__ import annotations

from ..inputs import Bed, Gas, Liquid, Particle
from .distributions import Normal

__all__ = ["TABLE4", "TABLE4_GROUPS", "TABLE4_U0", "table4_case"]

#: The paper's input groups (one panel of Figs. 10-11 each): both particles' diameters,
#: asperity heights and coating thicknesses vary together.
TABLE4_GROUPS: dict[str, tuple[str, ...]] = {
    "d": ("d_i", "d_j"),
    "ha": ("ha_i", "ha_j"),
    "h0": ("h0_i", "h0_j"),
    "mu_l": ("mu_l",),
    "gamma": ("gamma",),
    "u0": ("u0",),
}

#: Table 4, SI units: group -> (mean, reference sd, alternative sds) for each case.
TABLE4: dict[str, dict[str, tuple[float, float, tuple[float, ...]]]] = {
    "water": {
        "d": (1000e-6, 10e-6, (3.33e-6, 33.33e-6)),
        "ha": (0.10e-6, 0.005e-6, (0.0025e-6, 0.010e-6)),
        "h0": (5.00e-6, 0.10e-6, (0.05e-6, 0.15e-6)),
        "mu_l": (8.9e-4, 7.42e-5, (2.97e-5, 1.48e-4)),
        "gamma": (0.073, 0.00608, (0.00243,)),
    },
    "slag": {
        "d": (1000e-6, 10e-6, (3.33e-6, 33.33e-6)),
        "ha": (0.10e-6, 0.005e-6, (0.0025e-6, 0.010e-6)),
        "h0": (0.15e-6, 0.01e-6, (0.005e-6, 0.015e-6)),
        "mu_l": (10.0, 0.833, (0.333, 1.670)),
        "gamma": (0.400, 0.033, (0.0133,)),
    },
}

#: Table 4, the mean impact speeds [m/s] with their reference and alternative sds, keyed by
#: the e_w the paper reports at the mean inputs ("about 0.52" and "about 0.20").
TABLE4_U0: dict[str, dict[float, tuple[float, float, tuple[float, ...]]]] = {
    "water": {0.52: (0.0425, 0.00425, (0.00142, 0.00708)),
              0.20: (0.0347, 0.00347, (0.00116, 0.00578))},
    "slag": {0.52: (1.50, 0.15, (0.05, 0.25)),
             0.20: (0.81, 0.081, (0.027, 0.135))},
}


def _fixed(case: str):
    """Table 2 reference case I (water) or II (slag): the fixed inputs."""
    if case == "water":
        h0 = 5.00e-6
        liquid = Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0, name="water")
        gas = Gas(mu=18.48e-6, rho=1.168, name="air, 25 C")
    else:
        h0 = 0.15e-6
        liquid = Liquid(mu=10.0, gamma=0.400, rho=2500.0, theta_deg=10.0,
                        name="hypothetical slag")
        gas = Gas(mu=45.48e-6, rho=0.324, name="air, 800 C")
    p = Particle(d=1000e-6, rho=2650.0, h0=h0, ha=0.10e-6)
    # The paper's model: these cases reproduce its Section 3.4 (the tool's default tier is
    # "relative"; at beta = 0 for identical particles the two coincide).
    return dict(p_i=p, p_j=p, liquid=liquid, gas=gas, bed=Bed(eps=0.55, U=None), e=0.9,
                mode="paper")


def table4_case(case: str, e_w_target: float = 0.52, alternative: dict | None = None,
                only: tuple[str, ...] | None = None) -> dict:
    """Keyword arguments of :func:`monte_carlo` for one analysis of the paper's Table 4.

    Parameters
    ----------
    case : {"water", "slag"}
        Table 2 reference case I (capillary-limited) or II (viscous-limited).
    e_w_target : {0.52, 0.20}
        Which mean impact speed: the one giving e_w about 0.52 (Figs. 10-11) or about 0.20
        (Supplementary Figs. S.5-S.6).
    alternative : dict of str to float, optional
        Group name (a key of :data:`TABLE4_GROUPS`) -> standard deviation [SI] replacing the
        reference one; the paper changes one group at a time, the others at reference.
    only : tuple of str, optional
        Keep only these groups uncertain (the others fixed at their means), for
        one-at-a-time analyses.

    Returns
    -------
    dict
        ``p_i, p_j, liquid, gas, bed, e, u0, uncertain`` with Normal laws in SI units.
    """
    if case not in TABLE4:
        raise ValueError(f"case = {case!r} is not one of {tuple(TABLE4)}")
    if e_w_target not in TABLE4_U0[case]:
        raise ValueError(f"e_w_target = {e_w_target!r} is not one of {tuple(TABLE4_U0[case])}")
    rows = dict(TABLE4[case])
    rows["u0"] = TABLE4_U0[case][e_w_target]
    alternative = dict(alternative or {})
    for g in list(alternative) + list(only or ()):
        if g not in TABLE4_GROUPS:
            raise ValueError(f"group {g!r} is not one of {tuple(TABLE4_GROUPS)}")
    uncertain = {}
    for group, names in TABLE4_GROUPS.items():
        if only is not None and group not in only:
            continue
        mean, sd, _ = rows[group]
        sd = alternative.get(group, sd)
        for name in names:
            uncertain[name] = Normal(mean, sd)
    kwargs = _fixed(case)
    kwargs["u0"] = rows["u0"][0]
    kwargs["uncertain"] = uncertain
    return kwargs
