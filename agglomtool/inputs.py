"""The four things a collision is made of: two particles, a liquid, a gas, and a bed.

Every field may be a scalar or a numpy array; fields broadcast together when a collision is
evaluated. All values are SI (m, kg/m3, Pa s, N/m); angles are in degrees at this edge and
are converted to radians once, inside.

Types: the constructors take anything array-like (``numpy.typing.ArrayLike``: a float, a
list, an array; a pint Quantity is converted to SI) and store what they checked, a float
array, so the fields are typed ``numpy.ndarray``. The classes are frozen dataclasses (field
order, equality, repr, :func:`dataclasses.replace`) with a written ``__init__``, because a
dataclass's own would type each parameter as its field, an array.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._validate import check_field

__all__ = ["Particle", "Liquid", "Gas", "Bed"]


def _store(obj, **values) -> None:
    """Set a frozen dataclass's fields as given; ``__post_init__`` then checks them."""
    for name, value in values.items():
        object.__setattr__(obj, name, value)


@dataclass(frozen=True, init=False)
class Particle:
    """A solid sphere with an optional liquid coating.

    Parameters
    ----------
    d : float or array
        Solid diameter [m], in (0, 1e10]. ``math.inf`` is a plate: infinite radius and
        mass, fixed.
    rho : float or array
        Solid density [kg/m3], in (0, 1e5]. Ignored for a plate.
    h0 : float or array
        Coating (liquid layer) thickness [m], in [0, 1e10]. 0 is a dry particle.
    ha : float or array
        Asperity (surface roughness) height [m], in [0, 1e10].

    Every field's physical range is that of :data:`agglomtool._fields.CORE_RANGES` (the
    documentation's inputs page gives the reasons); outside it, NaN, an empty array, a
    string or ``None`` raise a ``ValueError`` naming the field, the value and the range.

    Notes
    -----
    Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Fig. 1.
    """

    d: np.ndarray
    rho: np.ndarray
    h0: np.ndarray
    ha: np.ndarray

    def __init__(self, d: ArrayLike, rho: ArrayLike, h0: ArrayLike = 0.0,
                 ha: ArrayLike = 0.0) -> None:
        _store(self, d=d, rho=rho, h0=h0, ha=ha)
        self.__post_init__()

    def __post_init__(self) -> None:
        d = check_field("Particle.d", self.d, allow_inf=True)
        rho = check_field("Particle.rho", self.rho, allow_inf=True)
        h0 = check_field("Particle.h0", self.h0)
        ha = check_field("Particle.ha", self.ha)
        if rho.ndim == 0 and d.ndim == 0:  # the common scalar, without numpy
            bad = math.isinf(rho) and not math.isinf(d)
        else:
            bad = (np.isinf(rho) & ~np.isinf(d)).any()
        if bad:
            raise ValueError(
                "Particle.rho = inf is allowed only for a plate (d = inf); "
                "a finite particle needs a finite density in (0, 100000] kg/m3"
            )
        object.__setattr__(self, "d", d)
        object.__setattr__(self, "rho", rho)
        object.__setattr__(self, "h0", h0)
        object.__setattr__(self, "ha", ha)

    @classmethod
    def plate(cls, h0: ArrayLike = 0.0, ha: ArrayLike = 0.0) -> Particle:
        """A flat wall: infinite radius and mass, fixed in the lab frame, no body force."""
        return cls(d=math.inf, rho=math.inf, h0=h0, ha=ha)

    @property
    def is_plate(self) -> np.ndarray:
        """True where this particle is a plate (``d = inf``)."""
        return np.isinf(self.d)


@dataclass(frozen=True, init=False)
class Liquid:
    """The coating liquid or melt that forms the bridge.

    Parameters
    ----------
    mu : float or array
        Dynamic viscosity [Pa s], in (0, 1e30].
    gamma : float or array
        Surface tension [N/m], in (0, 10].
    rho : float or array
        Density [kg/m3], in (0, 1e5].
    theta_deg : float or array
        Contact angle [deg], in [0, 90): the model is for wetting liquids.
    """

    mu: np.ndarray
    gamma: np.ndarray
    rho: np.ndarray
    theta_deg: np.ndarray
    name: str | None
    source: str | None

    def __init__(self, mu: ArrayLike, gamma: ArrayLike, rho: ArrayLike,
                 theta_deg: ArrayLike = 0.0, name: str | None = None,
                 source: str | None = None) -> None:
        _store(self, mu=mu, gamma=gamma, rho=rho, theta_deg=theta_deg, name=name,
               source=source)
        self.__post_init__()

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "mu", check_field("Liquid.mu", self.mu)
        )
        object.__setattr__(
            self,
            "gamma",
            check_field("Liquid.gamma", self.gamma),
        )
        object.__setattr__(
            self, "rho", check_field("Liquid.rho", self.rho)
        )
        object.__setattr__(
            self,
            "theta_deg",
            check_field("Liquid.theta_deg", self.theta_deg),
        )


@dataclass(frozen=True, init=False)
class Gas:
    """The fluidizing gas at bed conditions.

    Parameters
    ----------
    mu : float or array
        Dynamic viscosity [Pa s], in (0, 1].
    rho : float or array
        Density [kg/m3], in (0, 1e5].
    """

    mu: np.ndarray
    rho: np.ndarray
    name: str | None
    source: str | None

    def __init__(self, mu: ArrayLike, rho: ArrayLike, name: str | None = None,
                 source: str | None = None) -> None:
        _store(self, mu=mu, rho=rho, name=name, source=source)
        self.__post_init__()

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "mu", check_field("Gas.mu", self.mu)
        )
        object.__setattr__(
            self, "rho", check_field("Gas.rho", self.rho)
        )


@dataclass(frozen=True, init=False)
class Bed:
    """The local state of the bed around the colliding pair.

    Parameters
    ----------
    eps : float or array
        Local voidage [-], in (0, 1). The paper uses 0.55 (emulsion phase).
    U : float, array or None
        Emulsion-phase superficial gas velocity [m/s], upward (+Z), in [0, 1e12]. ``None``
        takes the paper's choice: 1.1 x the larger Wen-Yu minimum fluidization velocity of
        the pair.
    """

    eps: np.ndarray
    U: np.ndarray | None

    def __init__(self, eps: ArrayLike = 0.55, U: ArrayLike | None = None) -> None:
        _store(self, eps=eps, U=U)
        self.__post_init__()

    def __post_init__(self) -> None:
        object.__setattr__(
            self,
            "eps",
            check_field("Bed.eps", self.eps),
        )
        if self.U is not None:
            object.__setattr__(self, "U", check_field("Bed.U", self.U))
