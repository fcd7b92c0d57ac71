"""Minimum fluidization velocity.

Only what no installed library has is written here: fluids, thermo, chemicals and ht offer
the Archimedes number and the Ergun equation but no Wen-Yu minimum fluidization velocity.
"""

from __future__ import annotations

import numpy as np

__all__ = ["umf_wen_yu", "GRAVITY"]

#: Standard gravity [m/s2].
GRAVITY = 9.80665


def umf_wen_yu(d, rho_p, mu_g, rho_g, c1=33.7, c2=0.0408):
    """Minimum fluidization velocity by Wen and Yu (1966) [m/s].

    Parameters
    ----------
    d : array_like
        Particle diameter [m], > 0.
    rho_p : array_like
        Particle density [kg/m3], > ``rho_g``.
    mu_g, rho_g : array_like
        Gas viscosity [Pa s] and density [kg/m3].
    c1, c2 : float
        Constants of ``Re_mf = sqrt(c1^2 + c2 Ar) - c1``; Wen and Yu's are 33.7 and 0.0408.

    Returns
    -------
    numpy.ndarray
        ``U_mf`` [m/s].

    Notes
    -----
    Wen, C. Y., Yu, Y. H. (1966), A generalized method for predicting the minimum
    fluidization velocity, AIChE J. 12:610-612, doi:10.1002/aic.690120343::

        Ar = d^3 rho_g (rho_p - rho_g) g / mu_g^2
        Re_mf = sqrt(c1^2 + c2 Ar) - c1 = c2 Ar / (sqrt(c1^2 + c2 Ar) + c1)
        U_mf = Re_mf mu_g / (rho_g d)

    The second form of ``Re_mf`` avoids cancellation for fine particles (small ``Ar``).
    """
    d = np.asarray(d, dtype=float)
    ar = d**3 * rho_g * (rho_p - rho_g) * GRAVITY / (mu_g * mu_g)
    re_mf = c2 * ar / (np.sqrt(c1 * c1 + c2 * ar) + c1)
    return re_mf * mu_g / (rho_g * d)
