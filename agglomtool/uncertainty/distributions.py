"""Distributions of uncertain inputs: normal, lognormal and uniform, optionally truncated.

A distribution is a small frozen spec. It knows how to draw samples with a numpy
``Generator`` and how to map probabilities in (0, 1) to values (its inverse CDF, used by
the quasi-random Sobol designs). Truncation to ``[lo, hi]`` is applied by *resampling*:
draws that fall outside are replaced by draws from the distribution conditioned on
``[lo, hi]`` (the law that repeated rejection would give, obtained in one vectorised step
through the inverse CDF). The number of replaced draws is returned so that it can be
reported.

Values are given in ``units`` (default: the SI unit of the input they describe), or each
as a quantity with its unit (``Normal("50 degC", 5)``, ``Normal("500 um", "50 um")``, a
pint Quantity), and converted to SI once, at the boundary, by :func:`to_si` through
:mod:`agglomtool.units`, the one conversion every number a person types goes through.
Locations (``mean``, ``low``, ``high``, ``lo``, ``hi``) are converted as values
(``50 degC`` is 323.15 K), spreads (``sd``) as differences (``5 degC`` is 5 K). A bare
number is in ``units``, or without ``units`` in the input's SI unit (so in
``Normal("50 degC", 5)`` the ``sd`` is 5 K).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np
from scipy.special import ndtr, ndtri

__all__ = ["Distribution", "Normal", "LogNormal", "Uniform", "to_si"]

#: Parameters that are values (converted with a unit's offset) and spreads (differences).
_LOCATIONS = ("mean", "low", "high", "lo", "hi")
_SPREADS = ("sd",)


def _check_bounds(kind: str, lo, hi) -> tuple[float, float]:
    lo_f = -math.inf if lo is None else float(lo)
    hi_f = math.inf if hi is None else float(hi)
    if math.isnan(lo_f) or math.isnan(hi_f) or not lo_f < hi_f:
        raise ValueError(f"{kind}: truncation bounds lo = {lo!r}, hi = {hi!r} need lo < hi")
    return lo_f, hi_f


@dataclass(frozen=True)
class Distribution:
    """Base class: common fields and the truncated sampling machinery.

    Subclasses implement ``_draw(rng, n)`` (untruncated draws), ``_ppf_trunc(u, lo, hi)``
    (the inverse CDF of the law conditioned on ``[lo, hi]``), ``_mass(lo, hi)`` (its
    probability of ``[lo, hi]``), ``_scaled(factor)`` and ``nominal``; optionally
    ``_draw_into(rng, out)``, the same draws as ``_draw(rng, out.size)`` written into the
    float64 array ``out`` without temporaries.
    """

    def _draw(self, rng: np.random.Generator, n: int) -> np.ndarray:  # pragma: no cover
        """``n`` untruncated draws (each subclass implements it)."""
        raise NotImplementedError

    def _ppf_trunc(self, u: np.ndarray, lo: float, hi: float) -> np.ndarray:  # pragma: no cover
        """Inverse CDF of the law conditioned on ``[lo, hi]`` (each subclass)."""
        raise NotImplementedError

    def _mass(self, lo: float, hi: float) -> float:  # pragma: no cover
        """Probability of ``[lo, hi]`` under the untruncated law (each subclass)."""
        raise NotImplementedError

    def _scaled(self, factor: float) -> Distribution:  # pragma: no cover
        """The law with every location and scale parameter times ``factor`` (each
        subclass)."""
        raise NotImplementedError

    def _draw_into(self, rng: np.random.Generator, out: np.ndarray) -> None:
        out[...] = self._draw(rng, out.size)

    def _params(self) -> dict:
        return {k: getattr(self, k) for k in _LOCATIONS + _SPREADS if hasattr(self, k)}

    def _with_units(self) -> bool:
        """True where a parameter carries a unit (or ``units`` is given): the law is then
        checked as numbers once :func:`to_si` has converted it, and each parameter with a
        unit is checked to be a number with a unit pint knows now."""
        from ..units import _parse, is_quantity

        units = getattr(self, "units", None)  # (a user's law may have no units field)
        given = {k: v for k, v in self._params().items() if isinstance(v, str) or is_quantity(v)}
        for k, v in self._params().items():  # a list, a dict, None for a required number
            if k not in given and (v is not None or k in ("mean", "sd", "low", "high")) and (
                    isinstance(v, bool) or not isinstance(
                        v, int | float | np.integer | np.floating)):
                raise ValueError(f"{type(self).__name__}: {k} = {v!r} is not a number or a "
                                 "quantity with a unit")
        if units is None and not given:
            return False
        if units is not None:
            if not isinstance(units, str):
                raise ValueError(f"{type(self).__name__}: units = {units!r} must be a "
                                 "unit (a string such as \"um\" or \"degC\")")
            from ..units import quantity

            quantity("units", 1.0, units, units)
        for k, v in given.items():
            if isinstance(v, str):
                _parse(k, v)
        for k, v in self._params().items():
            if k not in given and v is not None and (isinstance(v, bool) or not isinstance(
                    v, int | float | np.integer | np.floating)):
                raise ValueError(f"{type(self).__name__}: {k} = {v!r} is not a number or a "
                                 "quantity with a unit")
        return True

    def bounds(self) -> tuple[float, float]:
        """The user's truncation bounds ``(lo, hi)`` in the distribution's units."""
        return _check_bounds(type(self).__name__, getattr(self, "lo", None),
                             getattr(self, "hi", None))

    @property
    def nominal(self) -> float:  # pragma: no cover - overridden
        """The central value used for the point estimate (the stated mean)."""
        raise NotImplementedError

    def mass(self, lo: float, hi: float) -> float:
        """Probability that an untruncated draw lies in ``[lo, hi]`` [-]."""
        return float(self._mass(lo, hi))

    def ppf(self, u, lo: float = -math.inf, hi: float = math.inf) -> np.ndarray:
        """Inverse CDF of the law truncated to ``[lo, hi]`` (and to the spec's own bounds).

        Parameters
        ----------
        u : array
            Probabilities in (0, 1) [-].
        lo, hi : float
            Extra bounds (the physical range of the input), in the distribution's units.
        """
        lo, hi = self._effective_bounds(lo, hi)
        u = np.asarray(u, dtype=np.float64)
        return self._ppf_trunc(u, lo, hi)

    def _effective_bounds(self, lo: float, hi: float) -> tuple[float, float]:
        if self._with_units():
            raise ValueError(f"{self!r} has units: its numbers are known once it describes an "
                             "input (monte_carlo, sobol_indices, or to_si(name, law, unit))")
        s_lo, s_hi = self.bounds()
        lo, hi = max(lo, s_lo), min(hi, s_hi)
        if not lo < hi or self.mass(lo, hi) <= 0.0:
            raise ValueError(
                f"{self!r} has no probability in the allowed range [{lo:g}, {hi:g}]"
            )
        return lo, hi

    def sample(
        self,
        rng: np.random.Generator,
        n: int,
        lo: float = -math.inf,
        hi: float = math.inf,
        *,
        lo_open: bool = False,
        hi_open: bool = False,
    ) -> tuple[np.ndarray, int]:
        """Draw ``n`` values truncated to ``[lo, hi]`` and the spec's own bounds.

        Draws outside the range are replaced by draws from the truncated law (resampling).

        Returns
        -------
        values : numpy.ndarray
            ``n`` draws, in the distribution's units.
        n_resampled : int
            How many first draws fell outside the range and were replaced.
        """
        lo, hi = self._effective_bounds(lo, hi)
        x = np.empty(int(n))
        self._draw_into(rng, x)
        # The replacement has the truncated law, so one pass suffices except for draws that
        # land exactly on an open bound (probability zero; a few rounds at most).
        return x, _replace_outside(self, x, lo, hi, lo_open, hi_open, rng, rng)

    def in_units(self, factor: float) -> Distribution:
        """The same law with every location/scale parameter multiplied by ``factor``."""
        return self._scaled(factor)


def _outside(x, lo, hi, lo_open, hi_open) -> np.ndarray:
    below = (x <= lo) if lo_open else (x < lo)
    above = (x >= hi) if hi_open else (x > hi)
    return below | above


def _inside(v: float, lo, hi, lo_open, hi_open) -> bool:
    """``v`` in the range (False for NaN)."""
    return (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)


def _replace_outside(d: Distribution, x: np.ndarray, lo: float, hi: float, lo_open: bool,
                     hi_open: bool, rng: np.random.Generator,
                     again: np.random.Generator) -> int:
    """Replace, in place, the draws of ``x`` outside the range by draws of ``d`` truncated
    to ``[lo, hi]`` (inverse CDF of uniforms from ``rng``); return how many were outside.

    A replacement that lands exactly on an open bound (probability zero) is drawn again,
    with uniforms from ``again``.
    """
    if x.size and _inside(float(x.min()), lo, hi, lo_open, hi_open) and _inside(
            float(x.max()), lo, hi, lo_open, hi_open):
        return 0  # the common case, told by two reductions instead of three masks
    todo = _outside(x, lo, hi, lo_open, hi_open)
    n_bad = k = int(np.count_nonzero(todo))
    for _ in range(64):
        if k == 0:
            return n_bad
        x[todo] = d._ppf_trunc(rng.random(k), lo, hi)
        todo = _outside(x, lo, hi, lo_open, hi_open)
        k = int(np.count_nonzero(todo))
        rng = again
    raise RuntimeError(  # pragma: no cover - needs 64 consecutive hits of an open bound
        f"could not draw {d!r} inside ({lo:g}, {hi:g})")


def _std_normal_trunc_ppf(u: np.ndarray, a: float, b: float) -> np.ndarray:
    """Inverse CDF of the standard normal truncated to ``[a, b]``.

    Works in the lower tail (flipping when ``a > 0``) so that a far-tail interval keeps its
    precision: ``ndtr`` resolves small probabilities, not probabilities close to 1.
    """
    flip = a > 0.0
    if flip:
        a, b = -b, -a
        u = 1.0 - u
    pa, pb = ndtr(a), ndtr(b)
    z = ndtri(pa + u * (pb - pa))
    z = np.clip(z, a, b)
    return -z if flip else z


@dataclass(frozen=True)
class Normal(Distribution):
    """Normal law ``N(mean, sd^2)``, optionally truncated to ``[lo, hi]``.

    Parameters
    ----------
    mean : float
        Mean, in ``units``.
    sd : float
        Standard deviation (>= 0), in ``units``. 0 gives the constant ``mean``.
    lo, hi : float, optional
        Truncation bounds, in ``units``. The input's physical range (e.g. a diameter > 0)
        always applies as well.
    units : str, optional
        Units of the bare numbers among ``mean``, ``sd``, ``lo``, ``hi`` (any unit pint
        knows: ``"um"``, ``"degC"``, ``"mPa s"``, ...); default: the SI unit of the input.
        Each parameter may also be a quantity with its own unit (``"50 degC"``).

    Notes
    -----
    The paper's choice for every uncertain input (Shabanian et al. 2024, Heliyon
    10:e29397, Section 3.4 and Table 4). Its "x % error" is taken there as 3 standard
    deviations.
    """

    mean: float
    sd: float
    lo: float | None = None
    hi: float | None = None
    units: str | None = None

    def __post_init__(self) -> None:
        if self._with_units():
            return  # checked in SI by to_si
        if not (math.isfinite(self.mean) and math.isfinite(self.sd) and self.sd >= 0.0):
            raise ValueError(
                f"Normal: mean = {self.mean!r} must be finite and sd = {self.sd!r} in [0, inf)"
            )
        self.bounds()

    @property
    def nominal(self) -> float:
        return float(self.mean)

    def _draw(self, rng, n):
        return self.mean + self.sd * rng.standard_normal(n)

    def _draw_into(self, rng, out):
        # bitwise the values of _draw: IEEE products and sums commute exactly
        rng.standard_normal(out=out)
        np.multiply(out, self.sd, out=out)
        np.add(out, self.mean, out=out)

    def _mass(self, lo, hi):
        if self.sd == 0.0:
            return 1.0 if lo <= self.mean <= hi else 0.0
        a, b = (lo - self.mean) / self.sd, (hi - self.mean) / self.sd
        if a > 0.0:
            return ndtr(-a) - ndtr(-b)
        return ndtr(b) - ndtr(a)

    def _ppf_trunc(self, u, lo, hi):
        if self.sd == 0.0:
            return np.full(u.shape, float(self.mean))
        a, b = (lo - self.mean) / self.sd, (hi - self.mean) / self.sd
        return np.clip(self.mean + self.sd * _std_normal_trunc_ppf(u, a, b), lo, hi)

    def _scaled(self, f):
        return replace(
            self, mean=self.mean * f, sd=self.sd * f,
            lo=None if self.lo is None else self.lo * f,
            hi=None if self.hi is None else self.hi * f, units=None,
        )


@dataclass(frozen=True)
class LogNormal(Distribution):
    """Lognormal law with the given mean and standard deviation *of the variable*.

    ``ln X ~ N(m, s^2)`` with ``s^2 = ln(1 + (sd/mean)^2)`` and ``m = ln(mean) - s^2/2``,
    so that ``E[X] = mean`` and ``sd(X) = sd``: a like-for-like alternative to
    :class:`Normal` for a positive quantity. Build from ``(m, s)`` with :meth:`from_log`.

    Parameters
    ----------
    mean : float
        Mean of the variable (> 0), in ``units``.
    sd : float
        Standard deviation of the variable (>= 0), in ``units``.
    lo, hi : float, optional
        Truncation bounds, in ``units``.
    units : str, optional
        Units of the bare numbers among the parameters (any unit pint knows); default SI.
        Each parameter may also be a quantity with its own unit (``"40 degC"``).
    """

    mean: float
    sd: float
    lo: float | None = None
    hi: float | None = None
    units: str | None = None

    def __post_init__(self) -> None:
        if self._with_units():
            return  # checked in SI by to_si
        if not (math.isfinite(self.mean) and self.mean > 0.0 and math.isfinite(self.sd)
                and self.sd >= 0.0):
            raise ValueError(
                f"LogNormal: mean = {self.mean!r} must be in (0, inf) and sd = {self.sd!r} "
                "in [0, inf)"
            )
        self.bounds()

    @classmethod
    def from_log(cls, mu_log: float, sigma_log: float, **kwargs) -> LogNormal:
        """The lognormal law with ``ln X ~ N(mu_log, sigma_log^2)`` (``sigma_log`` >= 0)."""
        if not sigma_log >= 0.0:
            raise ValueError(f"LogNormal.from_log: sigma_log = {sigma_log!r} must be >= 0")
        mean = math.exp(mu_log + 0.5 * sigma_log**2)
        sd = mean * math.sqrt(math.expm1(sigma_log**2))
        return cls(mean, sd, **kwargs)

    @property
    def log_params(self) -> tuple[float, float]:
        """``(m, s)``: mean and standard deviation of ``ln X``."""
        s2 = math.log1p((self.sd / self.mean) ** 2)
        return math.log(self.mean) - 0.5 * s2, math.sqrt(s2)

    @property
    def nominal(self) -> float:
        return float(self.mean)

    def _log_bounds(self, lo, hi):
        llo = math.log(lo) if lo > 0.0 else -math.inf
        lhi = math.log(hi) if hi > 0.0 else -math.inf
        return llo, lhi

    def _draw(self, rng, n):
        m, s = self.log_params
        return np.exp(m + s * rng.standard_normal(n))

    def _draw_into(self, rng, out):
        m, s = self.log_params
        rng.standard_normal(out=out)
        np.multiply(out, s, out=out)
        np.add(out, m, out=out)
        np.exp(out, out=out)

    def _mass(self, lo, hi):
        m, s = self.log_params
        return Normal(m, s)._mass(*self._log_bounds(lo, hi))

    def _ppf_trunc(self, u, lo, hi):
        m, s = self.log_params
        llo, lhi = self._log_bounds(lo, hi)
        return np.clip(np.exp(Normal(m, s)._ppf_trunc(u, llo, lhi)), lo, hi)

    def _scaled(self, f):
        return replace(
            self, mean=self.mean * f, sd=self.sd * f,
            lo=None if self.lo is None else self.lo * f,
            hi=None if self.hi is None else self.hi * f, units=None,
        )


@dataclass(frozen=True)
class Uniform(Distribution):
    """Uniform law on ``[low, high]``, optionally truncated to ``[lo, hi]``.

    Parameters
    ----------
    low, high : float
        Support, ``low < high``, in ``units``.
    lo, hi : float, optional
        Truncation bounds, in ``units`` (rarely needed: narrow the support instead).
    units : str, optional
        Units of the bare numbers among the parameters (any unit pint knows); default SI.
        Each parameter may also be a quantity with its own unit (``"40 degC"``).
    """

    low: float
    high: float
    lo: float | None = None
    hi: float | None = None
    units: str | None = None

    def __post_init__(self) -> None:
        if self._with_units():
            return  # checked in SI by to_si
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(
                f"Uniform: low = {self.low!r} and high = {self.high!r} must be finite, low < high"
            )
        self.bounds()

    @property
    def nominal(self) -> float:
        return 0.5 * (self.low + self.high)

    def _draw(self, rng, n):
        return rng.uniform(self.low, self.high, n)

    def _draw_into(self, rng, out):
        # numpy's uniform(low, high) is low + (high - low) * random(), bitwise
        rng.random(out=out)
        np.multiply(out, self.high - self.low, out=out)
        np.add(out, self.low, out=out)

    def _mass(self, lo, hi):
        return max(0.0, min(hi, self.high) - max(lo, self.low)) / (self.high - self.low)

    def _ppf_trunc(self, u, lo, hi):
        a, b = max(lo, self.low), min(hi, self.high)
        return a + u * (b - a)

    def _scaled(self, f):
        lo, hi = sorted((self.low * f, self.high * f))
        return replace(
            self, low=lo, high=hi,
            lo=None if self.lo is None else self.lo * f,
            hi=None if self.hi is None else self.hi * f, units=None,
        )


def to_si(name: str, dist: Distribution, si_unit: str) -> Distribution:
    """``dist`` with every parameter in ``si_unit``: parameters with a unit, and bare numbers
    when ``dist.units`` is given, converted by :func:`agglomtool.units.to_si` (locations
    as values, ``sd`` as a difference); bare numbers without ``units`` are SI already.

    Raises
    ------
    ValueError
        If ``dist`` is not a :class:`Distribution`, a unit is unknown or of another
        dimension than ``si_unit`` (naming the parameter), or the law in SI is not valid.
    """
    from .. import units

    if not isinstance(dist, Distribution):
        raise ValueError(
            f"uncertain[{name!r}] must be a Normal, LogNormal or Uniform, got {dist!r}"
        )
    if not dist._with_units():
        return dist
    law_units = getattr(dist, "units", None)  # (a user's law may have no units field)
    out: dict[str, float | str | None] = {}
    for key, value in dist._params().items():
        if value is None:
            out[key] = None
            continue
        if not (isinstance(value, str) or units.is_quantity(value)):
            if law_units is None:
                out[key] = float(value)  # SI, as typed
                continue
            value = units.quantity(key, float(value), law_units)
        try:
            out[key] = float(units.to_si(key, value, si_unit, delta=key in _SPREADS))
        except ValueError as exc:
            raise ValueError(f"uncertain[{name!r}]: {exc} (the unit of {name}: "
                             f"{si_unit!r})") from None
    if any(f.name == "units" for f in fields(dist)):
        out["units"] = None  # its numbers are now SI
    try:
        return replace(dist, **out)
    except ValueError as exc:
        raise ValueError(f"uncertain[{name!r}] in {si_unit}: {exc}") from None
