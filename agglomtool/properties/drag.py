"""Gas drag on a particle in a bed: Gidaspow's blend of Ergun and Wen-Yu.

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Eqs. 18-21,
after Gidaspow (1994), *Multiphase Flow and Fluidization*, Academic Press.
"""

from __future__ import annotations

import numpy as np
from numba import vectorize

from .._jit import CACHE
from ..collision.physics import EPS_SWITCH, drag_gidaspow

__all__ = ["drag_force_gidaspow", "EPS_SWITCH"]


@vectorize(["float64(float64, float64, float64, float64, float64, float64)"], cache=CACHE)
def _drag_ufunc(slip, d, volume, eps, mu_g, rho_g):
    return drag_gidaspow(slip, d, volume, eps, mu_g, rho_g)


def drag_force_gidaspow(slip, d, volume, eps, mu_g, rho_g):
    """Drag force on one particle along the slip velocity [N].

    Parameters
    ----------
    slip : array_like
        Signed component of the gas-particle slip velocity ``u_g - u_p`` [m/s].
    d : array_like
        Particle diameter, coating included [m].
    volume : array_like
        Particle volume, coating included [m3].
    eps : array_like
        Local voidage [-], in (0, 1).
    mu_g, rho_g : array_like
        Gas viscosity [Pa s] and density [kg/m3].

    Returns
    -------
    numpy.ndarray
        Signed force along the slip direction [N].

    Notes
    -----
    ``eps < 0.8`` (Ergun branch, Eq. 18 top)::

        F = (150 (1 - eps) mu_g / (eps d^2) + 1.75 rho_g |slip| / d) V slip

    ``eps >= 0.8`` (Wen-Yu branch, Eq. 18 bottom; the paper's printed ``e^{-1.65}`` is
    ``eps^-1.65``, Wen and Yu's voidage function)::

        F = 3/4 C_d rho_g |slip| slip eps^-1.65 V / d,
        C_d = 24/Re (1 + 0.15 Re^0.687) for Re < 1000, else 0.44,  Re = rho_g eps d |slip| / mu_g

    The Schiller-Naumann form of ``C_d`` is written so that ``slip = 0`` gives 0, not NaN:
    ``C_d Re = 24 (1 + 0.15 Re^0.687)`` is used with ``|slip| / Re = mu_g / (rho_g eps d)``.
    The formula is written once, ``agglomtool.collision.physics.drag_gidaspow`` (which
    the compiled kernels call too), and broadcast here over the arrays.
    """
    return np.asarray(_drag_ufunc(slip, d, volume, eps, mu_g, rho_g))
