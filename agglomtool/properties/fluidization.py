"""Minimum fluidization velocity.

Only what no installed library has is written here: fluids, thermo, chemicals and ht offer
the Archimedes number and the Ergun equation but no Wen-Yu minimum fluidization velocity.
The Ergun route (:func:`umf_ergun`) takes its pressure drop from ``fluids.packed_bed.Ergun``.
"""

from __future__ import annotations

import math

import numpy as np
from fluids.packed_bed import Ergun
from numba import vectorize

from .._jit import CACHE
from .._validate import check_range
from ..collision.physics import WEN_YU_C1, WEN_YU_C2, wet_mass
from ..collision.physics import umf_wen_yu as _umf_scalar
from ..constants import GRAVITY

__all__ = ["umf_wen_yu", "umf_ergun", "umf", "umf_methods", "umf_coated", "UMF_C1_C2",
           "GRAVITY"]


@vectorize(["float64(float64, float64, float64, float64, float64, float64)"], cache=CACHE)
def _umf_ufunc(d, rho_p, mu_g, rho_g, c1, c2):
    return _umf_scalar(d, rho_p, mu_g, rho_g, c1, c2)


def umf_wen_yu(d, rho_p, mu_g, rho_g, c1=WEN_YU_C1, c2=WEN_YU_C2):
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
    The formula is written once, ``agglomtool.collision.physics.umf_wen_yu`` (which the
    compiled kernels call too), and broadcast here over the arrays.
    """
    return np.asarray(_umf_ufunc(d, rho_p, mu_g, rho_g, c1, c2))


#: Published (C1, C2) pairs of ``Re_mf = sqrt(C1^2 + C2 Ar) - C1``, with their sources.
UMF_C1_C2 = {
    "wen-yu": (WEN_YU_C1, WEN_YU_C2, "Wen & Yu (1966), AIChE J. 12:610, doi:10.1002/aic.690120343"),
    "richardson": (25.7, 0.0365, "Richardson (1971), in Fluidization, Academic Press"),
    "saxena-vogel": (25.3, 0.0571, "Saxena & Vogel (1977), Trans. IChemE 55:184"),
    "babu": (25.25, 0.0651, "Babu, Shah & Talwalkar (1978), AIChE Symp. Ser. 74(176):176"),
    "grace": (27.2, 0.0408, "Grace (1982), in Handbook of Multiphase Systems, Hemisphere"),
    "chitester": (28.7, 0.0494, "Chitester et al. (1984), Chem. Eng. Sci. 39:253, "
                  "doi:10.1016/0009-2509(84)80025-4"),
}


def umf_ergun(d, rho_p, mu_g, rho_g, eps_mf, phi=1.0):
    """Minimum fluidization velocity from the Ergun equation and a known voidage [m/s].

    Parameters
    ----------
    d : array_like
        Particle diameter [m], > 0.
    rho_p : array_like
        Particle density [kg/m3], > ``rho_g``.
    mu_g, rho_g : array_like
        Gas viscosity [Pa s] and density [kg/m3].
    eps_mf : array_like
        Bed voidage at minimum fluidization [-], in (0, 1).
    phi : array_like
        Sphericity [-], in (0, 1]; the Ergun diameter is ``phi d``.

    Returns
    -------
    numpy.ndarray
        ``U_mf`` [m/s].

    Notes
    -----
    At minimum fluidization the Ergun pressure gradient carries the buoyant bed weight,
    ``dP/L = (1 - eps_mf)(rho_p - rho_g) g``. The pressure drop is
    ``fluids.packed_bed.Ergun`` (Ergun, S. (1952), Chem. Eng. Prog. 48:89-94), which is
    ``a U + b U^2``; ``a`` and ``b`` are read from two evaluations of it and the quadratic is
    solved in closed form, element-wise and without iteration.
    """
    d = check_range("d", d, 0.0, None, lo_open=True, unit="m")
    eps_mf = check_range("eps_mf", eps_mf, 0.0, 1.0, lo_open=True, hi_open=True, unit="-")
    phi = check_range("phi", phi, 0.0, 1.0, lo_open=True, unit="-")
    weight = (1.0 - eps_mf) * (np.asarray(rho_p) - rho_g) * GRAVITY
    if (weight <= 0.0).any():
        raise ValueError("rho_p must exceed rho_g for a bed to fluidize")
    dp = phi * d
    one = Ergun(dp=dp, voidage=eps_mf, vs=1.0, rho=rho_g, mu=mu_g, L=1.0)
    two = Ergun(dp=dp, voidage=eps_mf, vs=2.0, rho=rho_g, mu=mu_g, L=1.0)
    b = 0.5 * (two - 2.0 * one)
    a = one - b
    return 2.0 * weight / (a + np.sqrt(a * a + 4.0 * b * weight))


def umf_methods(eps_mf=None) -> list[str]:
    """Names of the ``method`` values :func:`umf` accepts (``"ergun"`` needs ``eps_mf``)."""
    return list(UMF_C1_C2) + (["ergun"] if eps_mf is not None else [])


def umf(d, rho_p, gas, method="wen-yu", *, eps_mf=None, phi=1.0):
    """Minimum fluidization velocity of spheres of ``d``, ``rho_p`` in ``gas`` [m/s].

    Parameters
    ----------
    d : array_like
        Particle diameter [m], > 0.
    rho_p : array_like
        Particle density [kg/m3].
    gas : agglomtool.Gas
        The fluidizing gas (``mu`` [Pa s], ``rho`` [kg/m3]).
    method : str
        ``"wen-yu"`` (default) or another key of :data:`UMF_C1_C2` (``"richardson"``,
        ``"saxena-vogel"``, ``"babu"``, ``"grace"``, ``"chitester"``), all
        ``Re_mf = sqrt(C1^2 + C2 Ar) - C1``; or ``"ergun"`` (needs ``eps_mf``), see
        :func:`umf_ergun`.
    eps_mf : array_like, optional
        Voidage at minimum fluidization [-]; when given without ``method``, prefer
        ``method="ergun"``, the better route when ``eps_mf`` is known.
    phi : array_like
        Sphericity [-], used by ``"ergun"`` only.

    Returns
    -------
    numpy.ndarray
        ``U_mf`` [m/s].
    """
    d = check_range("d", d, 0.0, None, lo_open=True, unit="m")
    rho_p = check_range("rho_p", rho_p, 0.0, None, lo_open=True, unit="kg/m3")
    if method == "ergun":
        if eps_mf is None:
            raise ValueError("method='ergun' needs eps_mf, the voidage at minimum fluidization")
        return umf_ergun(d, rho_p, gas.mu, gas.rho, eps_mf, phi)
    if method not in UMF_C1_C2:
        raise ValueError(f"method = {method!r} is not one of {umf_methods(eps_mf=0.0)}")
    if (rho_p <= gas.rho).any():
        raise ValueError("rho_p must exceed the gas density for a bed to fluidize")
    c1, c2, _ = UMF_C1_C2[method]
    return umf_wen_yu(d, rho_p, gas.mu, gas.rho, c1=c1, c2=c2)


@vectorize(["float64(float64, float64, float64, float64, float64, float64, float64, "
            "float64, float64, float64)"], cache=CACHE)
def _coated_kernel(d, rho_s, h0, rho_l, vol, d_wet, mu_g, rho_g, c1, c2):
    """:func:`umf_coated`'s one compiled pass: the wet mass
    (``agglomtool.collision.physics.wet_mass``), the wet density over the given wet
    volume ``vol`` and ``agglomtool.collision.physics.umf_wen_yu`` of the wet diameter
    ``d_wet``, as the numpy route takes them; NaN where the wet density does not exceed the
    gas's (or is NaN)."""
    rho_p = wet_mass(d, rho_s, h0, rho_l) / vol
    if not rho_p > rho_g:
        return math.nan
    return _umf_scalar(d_wet, rho_p, mu_g, rho_g, c1, c2)


def umf_coated(d, rho_s, h0, rho_l, mu_g, rho_g, method="wen-yu"):
    """``U_mf`` [m/s] of a sphere (diameter ``d`` [m], density ``rho_s`` [kg/m3]) coated
    with ``h0`` [m] of a liquid of density ``rho_l`` [kg/m3], fluidized by a gas of
    ``mu_g`` [Pa s] and ``rho_g`` [kg/m3]: :func:`umf` of the wet diameter ``d + 2 h0`` and
    the wet particle's mean density (wet mass, :func:`agglomtool.pair.wet_mass`, over the
    wet volume ``(pi/6) d_wet^3``), by a correlation of :data:`UMF_C1_C2`.

    The same numbers as that numpy route (the wet volume's power taken by numpy on the
    inputs' own shapes, every other operation in one compiled pass over the broadcast
    result, the same scalar functions), without its temporaries. Returns ``None`` where it
    does not apply (a plate, a method outside :data:`UMF_C1_C2`, a wet density not above
    the gas's): the caller then takes the numpy route, which answers or raises there.
    """
    if method not in UMF_C1_C2:
        return None
    d, h0 = np.asarray(d, dtype=float), np.asarray(h0, dtype=float)
    d_wet = d + 2.0 * h0
    if not np.all(np.isfinite(d_wet)) or not np.all(d_wet > 0.0):
        return None
    # The power exactly as the numpy route takes it: numpy's power of a scalar can differ
    # in the last bit from its power of an array (a 0-d one included).
    vol = (math.pi / 6.0) * d_wet**3
    c1, c2, _ = UMF_C1_C2[method]
    out = _coated_kernel(d, rho_s, h0, rho_l, vol, d_wet, mu_g, rho_g, c1, c2)
    if np.isnan(out).any():
        return None
    return out
