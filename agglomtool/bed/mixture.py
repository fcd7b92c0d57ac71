"""A component of a bed: one solid, its mass fraction, its size classes and its coating."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import ndtri

from .. import materials
from .._validate import check_range, check_typed, unknown_name
from ..plausibility import component_findings, warn_findings
from ..units import is_quantity, to_si, to_si_array

__all__ = ["Component", "MAX_CLASSES", "TAIL"]

#: Most size classes one component may have.
MAX_CLASSES = 200
#: Mass quantiles taken as the outer class edges of a lognormal (its tails are unbounded).
TAIL = 1e-3


@dataclass(frozen=True)
class Component:
    """One component of a bed: a solid of the database, its mass fraction, sizes and coating.

    Give the sizes either as a lognormal (``d50``, ``gsd``, ``classes``) or as explicit
    classes (``d`` and ``d_fractions``). Lengths are numbers in m, or quantities with units
    (``d50="500 um"``, a pint Quantity) as everywhere (:mod:`agglomtool.units`). A size
    outside the solid's typical range, a coating thicker than a film or an implausible
    asperity height warns (:class:`agglomtool.PlausibilityWarning`), as a Scene does.

    Parameters
    ----------
    solid : str
        Bed solid, a name of the materials database (``materials.names("solid")``).
    fraction : float
        Mass fraction of this component in the bed [-], in [0, 1]. The fractions of all the
        components of a bed must sum to 1 (within 1e-9).
    d50 : float, optional
        Mass-median diameter of the lognormal size distribution [m], > 0.
    gsd : float
        Geometric standard deviation of the mass distribution of diameters [-], in [1, 10]
        (1: monodisperse).
    classes : int
        Number of size classes the lognormal is cut into, in [1, 200]: classes of equal mass,
        each represented by the diameter at its mid mass-quantile,
        ``d_k = d50 gsd**z((k - 1/2) / classes)`` (``z`` the standard normal quantile); the
        class edges are the quantiles ``k / classes``, the outer ones the 0.1 % and 99.9 %
        quantiles.
    d : sequence of float, optional
        Explicit class diameters [m], > 0 (instead of ``d50``).
    d_fractions : sequence of float, optional
        Mass fractions of the explicit classes within the component [-], each in [0, 1],
        summing to 1 within 1e-9 (default: equal).
    h0 : float, optional
        Coating thickness [m], >= 0 (0: a dry particle). ``None``: the scene's ``h0``.
    ha : float, optional
        Asperity height [m], >= 0. ``None``: the solid's database value.
    """

    solid: str
    fraction: float
    d50: float | None = None
    gsd: float = 1.0
    classes: int = 1
    d: tuple | None = None
    d_fractions: tuple | None = None
    h0: float | None = None
    ha: float | None = None

    def __post_init__(self) -> None:
        typed = {}
        for name, long_name in (("d50", "mass-median diameter"), ("h0", "coating thickness"),
                                ("ha", "asperity height")):  # quantities, unit strings -> m
            value = typed[name] = getattr(self, name)
            if isinstance(value, str) or is_quantity(value):
                object.__setattr__(self, name, to_si(name, value, "m", long_name))
        typed["d"] = self.d
        if self.d is not None and not isinstance(self.d, list | tuple | np.ndarray) and not (
                is_quantity(self.d) and np.ndim(self.d.magnitude) == 1):
            raise ValueError(f"d = {self.d!r} is not allowed: a list of 1-{MAX_CLASSES} class "
                             "diameters [m] (one class: d = [value])")
        if self.d is not None:
            d = to_si_array("d", self.d if is_quantity(self.d) else list(self.d), "m",
                            "class diameters")
            object.__setattr__(self, "d", d)
        known = materials.names("solid")
        if not isinstance(self.solid, str) or materials._key(self.solid) not in known:
            raise unknown_name("solid", self.solid, "solid", known)
        if np.ndim(self.fraction):
            raise ValueError(f"fraction = {self.fraction!r} must be a single number in [0, 1] "
                             "(sweep the fraction with bed_sweep(..., fraction=[...], mix=...))")
        check_range("fraction", self.fraction, 0.0, 1.0)
        if (self.d50 is None) == (self.d is None):
            raise ValueError(f"d50 = {self.d50!r}, d = {self.d!r}: give exactly one of d50 [m] "
                             "(a lognormal) or d [m] (explicit classes)")
        if self.d50 is not None:
            check_typed("d50", typed["d50"], self.d50, key="d_i", scalar=True)
            if np.ndim(self.gsd):
                raise ValueError(f"gsd = {self.gsd!r} must be a single number in [1, 10]")
            check_range("gsd", self.gsd, 1.0, 10.0)
            if (not isinstance(self.classes, int | np.integer)
                    or not 1 <= self.classes <= MAX_CLASSES):
                raise ValueError(f"classes = {self.classes!r} is outside the allowed range "
                                 f"1-{MAX_CLASSES} (an integer)")
            if self.d_fractions is not None:
                raise ValueError(f"d_fractions = {self.d_fractions!r} needs explicit classes d, "
                                 "not d50")
        else:
            assert self.d is not None  # the branch above took d is None
            if np.ndim(self.d) != 1 or not 1 <= np.size(self.d) <= MAX_CLASSES:
                empty = " is empty;" if np.size(self.d) == 0 else ""
                raise ValueError(f"d = {typed['d']!r}{empty} must be a list of 1-{MAX_CLASSES} "
                                 "diameters [m]")
            d = check_typed("d", typed["d"], self.d, key="d_i")
            uniq, counts = np.unique(d, return_counts=True)
            if uniq.size != d.size:
                raise ValueError(f"d = {typed['d']!r} repeats the class diameter "
                                 f"{float(uniq[counts > 1][0])!r} m; allowed: distinct "
                                 "diameters (one class each: add up their d_fractions)")
            object.__setattr__(self, "d", tuple(float(x) for x in d))
            if self.d_fractions is not None:
                w = check_range("d_fractions", self.d_fractions, 0.0, 1.0)
                if w.shape != d.shape:
                    raise ValueError(f"d_fractions = {self.d_fractions!r} must have one value "
                                     f"per diameter ({d.size})")
                if abs(float(w.sum()) - 1.0) > 1e-9:
                    raise ValueError(f"d_fractions = {self.d_fractions!r} sum to {w.sum():.12g}; "
                                     "allowed: a sum of 1 within 1e-9")
                object.__setattr__(self, "d_fractions", tuple(float(x) for x in w))
        if self.h0 is not None:
            check_typed("h0", typed["h0"], self.h0, key="h0", scalar=True)
        if self.ha is not None:
            check_typed("ha", typed["ha"], self.ha, key="ha_i", scalar=True)
        warn_findings(component_findings(self), stacklevel=4)

    @property
    def density(self) -> float:
        """Solid density [kg/m3] (database)."""
        return materials.solid(self.solid).density

    @property
    def name(self) -> str:
        """The database's name of the solid."""
        return materials.solid(self.solid).name

    def size_classes(self):
        """``(d, w, lo, hi)``: class diameters [m], mass fractions within the component [-]
        and lower and upper class edges [m] (see the class docstring)."""
        if self.d is not None:
            d = np.asarray(self.d, dtype=float)
            n = d.size
            w = (np.full(n, 1.0 / n) if self.d_fractions is None
                 else np.asarray(self.d_fractions, dtype=float))
            order = np.sort(d)
            mids = np.sqrt(order[1:] * order[:-1])  # geometric midpoints between neighbours
            if n > 1:
                lo_s = np.concatenate([[order[0] ** 2 / mids[0]], mids])
                hi_s = np.concatenate([mids, [order[-1] ** 2 / mids[-1]]])
            else:
                lo_s = hi_s = order
            rank = np.argsort(np.argsort(d))
            return d, w, lo_s[rank], hi_s[rank]
        n = int(self.classes)
        s = np.log(self.gsd)
        k = np.arange(n)
        d = self.d50 * np.exp(s * ndtri((k + 0.5) / n))
        q = np.concatenate([[TAIL], np.arange(1, n) / n, [1.0 - TAIL]])
        edges = self.d50 * np.exp(s * ndtri(q))
        return d, np.full(n, 1.0 / n), edges[:-1], edges[1:]
