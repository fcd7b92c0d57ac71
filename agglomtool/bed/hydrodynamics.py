"""Bubbling-bed hydrodynamics: bubble size, rise velocity, bubble fraction, solids circulation
and the granular temperatures they imply.

Every function is named after the authors of its correlation, takes numpy arrays that
broadcast together (SI units) and returns an array. Input outside a correlation's domain
(a gas velocity below ``U_mf``, a negative height) raises a ``ValueError`` naming the
parameter, its value and the allowed range; input inside the domain but outside the data a
correlation was fitted to warns with :class:`agglomtool.PlausibilityWarning` naming what is
out of range (the Geldart group, ``U - U_mf``, the column diameter, a slugging bed).

The correlations are those compiled by Kunii and Levenspiel (1991), *Fluidization
Engineering*, 2nd ed., Butterworth-Heinemann, ch. 5-6, from their original papers, cited
in each function.
"""

from __future__ import annotations

import math
import warnings

import numba
import numpy as np
from numba import njit, prange, vectorize

from .._jit import CACHE, parallel_launch
from .._validate import PlausibilityWarning, check_range
from ..constants import GRAVITY

__all__ = [
    "geldart_group", "bubble_diameter_darton", "bubble_diameter_mori_wen",
    "bubble_rise_velocity_davidson_harrison", "bubble_velocity_davidson_harrison",
    "bubble_fraction_kunii_levenspiel", "solids_downflow_kunii_levenspiel",
    "granular_temperature_bubble_wake", "granular_temperature_bubbles",
    "radial_distribution_carnahan_starling",
    "granular_temperature_collisional_balance", "SLUGGING_RATIO", "MORI_WEN_RANGE",
    "bubble_domain",
]

#: A bubble wider than this fraction of the column diameter fills it: the bed slugs, and the
#: bubbling-bed correlations no longer hold (Kunii and Levenspiel 1991, ch. 5).
SLUGGING_RATIO = 0.6

#: Geldart (1973) group boundaries, with ``d_p`` in um and the density difference in g/cm3:
#: A/B where ``(rho_p - rho_g) d_p = 225``, B/D where ``(rho_p - rho_g) d_p**2 = 1e6``.
_GELDART_AB = 225.0
_GELDART_BD = 1.0e6


def _warn(message: str, stacklevel: int = 3) -> None:
    warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel)


def _float_arrays(*values) -> bool:
    """Whether every value is a float64 array or a float (no conversion needed: the
    compiled checks take them as they are; anything else takes the plain path)."""
    return all((isinstance(v, np.ndarray) and v.dtype == np.float64) or type(v) is float
               for v in values)


@vectorize(cache=CACHE)
def _excess_checked(U, Umf):  # pragma: no cover - compiled
    """``U - Umf`` of one element where ``0 <= U``, ``0 < Umf``, both finite and
    ``U > Umf``; else -1 (no excess is negative): the caller then takes the plain path,
    whose error names the field and the value. One pass, no temporaries."""
    return _excess_one(U, Umf)


@njit(inline="always", cache=CACHE)
def _flows_valid(U, Umf):  # pragma: no cover - compiled
    """Whether ``U`` and ``Umf`` are themselves accepted: ``0 <= U``, ``0 < Umf``, both
    finite (NaN is not). The rule written once for :func:`_excess_one` and the map
    passes' refusal codes (5 where it fails)."""
    return (0.0 <= U) & (U < math.inf) & (0.0 < Umf) & (Umf < math.inf)


@njit(inline="always", cache=CACHE)
def _excess_one(U, Umf):  # pragma: no cover - compiled
    """:func:`_excess_checked` of one element (shared with the map passes): the difference
    where :func:`_flows_valid` and positive, else -1; computed, then selected (no branch:
    a loop of it vectorizes)."""
    excess = U - Umf
    return excess if _flows_valid(U, Umf) & (excess > 0.0) else -1.0


def _excess(U, Umf):
    """``U - U_mf`` [m/s] after checking both, with the ``ValueError`` a bubbling-bed
    correlation gives where the bed is not fluidized."""
    if _float_arrays(U, Umf) and (np.ndim(U) or np.ndim(Umf)):
        # on a map's arrays: the checks and the difference in one compiled pass (the
        # same subtraction, so the same numbers); any bad element reruns the plain
        # checks below for their message
        with np.errstate(invalid="ignore"):  # a NaN compared: the plain path names it
            excess = _excess_checked(U, Umf)
        if excess.size and excess.min() > 0.0:
            return excess
    U = check_range("U", U, 0.0, None, unit="m/s")
    Umf = check_range("Umf", Umf, 0.0, None, lo_open=True, unit="m/s")
    excess = U - Umf
    if np.any(excess <= 0.0):
        bad = excess <= 0.0
        u = float(np.broadcast_to(U, bad.shape)[bad].flat[0])
        umf = float(np.broadcast_to(Umf, bad.shape)[bad].flat[0])
        raise ValueError(f"U = {u:g} m/s does not exceed Umf = {umf:g} m/s: a bubbling-bed "
                         "correlation needs a fluidized bed (U > Umf)")
    return excess


def _own(v):
    """``v``'s own values: where ``v`` is an array whose step along an axis is 0 (a
    broadcast view, which holds one value along that axis), the view of its first element
    along each such axis, which broadcasts back to ``v``; else ``v``. A check or a
    reduction over it costs what ``v``'s distinct values do, not its broadcast size, and
    names the same first element (the first in C order of ``v`` that a check finds lies
    at index 0 along those axes)."""
    if isinstance(v, np.ndarray) and 0 in v.strides:
        return v[tuple(slice(0, 1) if s == 0 else slice(None) for s in v.strides)]
    return v


def geldart_group(d_p, rho_p, rho_g=0.0) -> np.ndarray:
    """Geldart's (1973) powder group: ``"A"``, ``"B"`` or ``"D"`` (an array of strings).

    Parameters
    ----------
    d_p : array_like
        Particle diameter [m].
    rho_p, rho_g : array_like
        Particle and gas densities [kg/m3].

    Notes
    -----
    The boundaries of Geldart's diagram as straight lines, with ``d_p`` in um and
    ``rho_p - rho_g`` in g/cm3: group B where ``(rho_p - rho_g) d_p >= 225`` and
    ``(rho_p - rho_g) d_p**2 < 1e6``; below, A (aeratable: bubbles only above a minimum
    bubbling velocity; the cohesive group C, of the finest powders, is not told apart
    here); above, D (spoutable, large or dense). Quartz sand (2650 kg/m3) is B from about
    85 um to 615 um.

    References
    ----------
    D. Geldart (1973), Types of gas fluidization, Powder Technol. 7:285-292,
    doi:10.1016/0032-5910(73)80037-3.
    """
    d_p = check_range("d_p", d_p, 0.0, None, lo_open=True, unit="m")
    rho_p = check_range("rho_p", rho_p, 0.0, None, lo_open=True, unit="kg/m3")
    rho_g = check_range("rho_g", rho_g, 0.0, None, unit="kg/m3")
    drho = (rho_p - rho_g) * 1e-3  # g/cm3
    if np.any(drho <= 0.0):
        raise ValueError("rho_p must exceed rho_g: a particle lighter than the gas does not "
                         "fluidize")
    d_um = d_p * 1e6
    return np.where(drho * d_um < _GELDART_AB, "A",
                    np.where(drho * d_um * d_um >= _GELDART_BD, "D", "B"))


def _check_group(name: str, d_p, rho_p, rho_g, allowed=("B",), why=None) -> None:
    """Warn where the powder is outside the Geldart groups ``allowed`` of correlation
    ``name`` (``why``: the reason, default that the correlation was fitted to them)."""
    if d_p is None or rho_p is None:
        return
    d_p, rho_p, rho_g = _own(d_p), _own(rho_p), _own(rho_g)
    # the group's bounds as numbers (a string per element would cost more than the
    # correlation on a map), in one compiled pass; the first element outside is named
    rho_p, rho_g = np.asarray(rho_p, dtype=float), np.asarray(rho_g, dtype=float)
    if np.any((rho_p - rho_g) * 1e-3 <= 0.0):
        raise ValueError("rho_p must exceed rho_g: a particle lighter than the gas does not "
                         "fluidize")
    outside = _outside_groups(np.asarray(d_p, dtype=float), rho_p, rho_g,
                              "A" not in allowed, "D" not in allowed)
    if np.any(outside):
        first = np.unravel_index(int(np.argmax(outside)), outside.shape)

        def at(v):
            return float(np.broadcast_to(np.asarray(v, float), outside.shape)[first])

        group = geldart_group(at(d_p), at(rho_p), at(rho_g))
        why = why or f"the correlation was fitted to group {'/'.join(allowed)} powders"
        _warn(f"{name}: d_p = {at(d_p):g} m is a Geldart group {group} powder; {why}",
              stacklevel=4)


@vectorize(cache=CACHE)
def _outside_groups(d_p, rho_p, rho_g, below_a, above_d):  # pragma: no cover - compiled
    """Whether one powder is outside the allowed groups: Geldart's A/B and B/D bounds of
    :func:`geldart_group`, ``below_a`` / ``above_d`` saying whether A / D are outside."""
    d_um = d_p * 1e6
    x = (rho_p - rho_g) * 1e-3 * d_um
    return (below_a and x < _GELDART_AB) or (above_d and x * d_um >= _GELDART_BD)


def bubble_diameter_darton(U, Umf, h, A0=0.0, *, d_p=None, rho_p=None, rho_g=0.0):
    """Bubble diameter at height ``h`` above the distributor, Darton et al. (1977) [m].

    Parameters
    ----------
    U, Umf : array_like
        Superficial gas velocity and minimum fluidization velocity [m/s], ``U > Umf``.
    h : array_like
        Height above the distributor [m], ``>= 0``.
    A0 : array_like
        Distributor area per orifice [m2]; 0 for a porous plate.
    d_p, rho_p, rho_g : array_like, optional
        Particle diameter [m], particle and gas densities [kg/m3]: given, a powder outside
        Geldart group B warns.

    Returns
    -------
    numpy.ndarray
        ``d_b`` [m], the diameter of the sphere of the bubble's volume.

    Notes
    -----
    Bubbles grow by coalescence as they rise::

        d_b = 0.54 (U - Umf)**0.4 (h + 4 sqrt(A0))**0.8 / g**0.2

    (SI units; ``4 sqrt(A0)`` is the height at which bubbles from neighbouring orifices
    have merged). Fitted to Geldart group B beds; no maximum size: where ``d_b`` exceeds
    0.6 of the column diameter the bed slugs (see
    :func:`bubble_rise_velocity_davidson_harrison`).

    References
    ----------
    R. C. Darton, R. D. LaNauze, J. F. Davidson, D. Harrison (1977), Bubble growth due to
    coalescence in fluidised beds, Trans. IChemE 55:274-280; Kunii and Levenspiel (1991),
    Fluidization Engineering, 2nd ed., ch. 6.
    """
    excess = _excess(U, Umf)
    h = check_range("h", h, 0.0, None, unit="m")
    A0 = check_range("A0", A0, 0.0, None, unit="m2")
    _check_group("bubble_diameter_darton", d_p, rho_p, rho_g)
    return 0.54 * excess**0.4 * (h + 4.0 * np.sqrt(A0)) ** 0.8 * GRAVITY**-0.2


#: The data of Mori and Wen (1975), as they state them (SI): column diameters up to 1.3 m,
#: U_mf 0.5-20 cm/s, particle diameters 60-450 um, U - U_mf up to 48 cm/s. Secondary
#: sources differ on the smallest column in the data (7 cm or 30 cm); 0.3 m is used here.
MORI_WEN_RANGE = {"D_t": (0.3, 1.3), "Umf": (0.005, 0.20), "d_p": (60e-6, 450e-6),
                  "excess": (0.0, 0.48)}


#: Mori and Wen's coefficients, stated in cm, cm/s and cm2, in SI: a length in cm is 100 x
#: the one in m, and (area x velocity) in cm2 cm/s is 1e6 x the one in m2 m/s.
_MW_MAX = 0.652 * 1e6**0.4 / 100.0         # 1.6378
_MW_PERFORATED = 0.347 * 1e6**0.4 / 100.0  # 0.87163
_MW_POROUS = 0.00376 * 100.0**2 / 100.0    # 0.376, (cm/s)**2 -> (m/s)**2, cm -> m


def bubble_diameter_mori_wen(U, Umf, h, D_t, A0=0.0, *, d_p=None):
    """Bubble diameter at height ``h`` above the distributor, Mori and Wen (1975) [m].

    Parameters
    ----------
    U, Umf : array_like
        Superficial gas velocity and minimum fluidization velocity [m/s], ``U > Umf``.
    h : array_like
        Height above the distributor [m], ``>= 0``.
    D_t : array_like
        Column diameter [m].
    A0 : array_like
        Distributor area per orifice [m2] (the bed's cross-section over the number of
        orifices); 0 for a porous plate.
    d_p : array_like, optional
        Particle diameter [m]: given, a size outside the data warns.

    Returns
    -------
    numpy.ndarray
        ``d_b`` [m].

    Notes
    -----
    Bubbles start at ``d_b0`` on the distributor and grow towards a maximum ``d_bm``, the
    size all the excess gas would make as one bubble::

        d_b  = d_bm - (d_bm - d_b0) exp(-0.3 h / D_t)
        d_bm = 1.6378 (A_t (U - Umf))**0.4             A_t = pi D_t**2 / 4
        d_b0 = 0.87163 (A0 (U - Umf))**0.4             perforated plate
        d_b0 = 0.376 (U - Umf)**2                      porous plate (A0 = 0)

    in SI units; the paper states them in cm, cm/s and cm2 with the coefficients 0.652,
    0.347 and 0.00376 (0.652 x 10**2.4 / 100 = 1.6378, 0.347 x 10**2.4 / 100 = 0.87163,
    0.00376 x 100 = 0.376). Calibrated range (:data:`MORI_WEN_RANGE`): column diameters
    up to 1.3 m, ``U_mf`` 0.5-20 cm/s, ``d_p`` 60-450 um, ``U - U_mf`` up to 48 cm/s;
    outside it a :class:`~agglomtool.PlausibilityWarning`.

    References
    ----------
    S. Mori, C. Y. Wen (1975), Estimation of bubble diameter in gaseous fluidized beds,
    AIChE J. 21:109-115, doi:10.1002/aic.690210114.
    """
    excess = _excess(U, Umf)
    h = check_range("h", h, 0.0, None, unit="m")
    D_t = check_range("D_t", D_t, 0.0, None, lo_open=True, unit="m")
    A0 = check_range("A0", A0, 0.0, None, unit="m2")
    A_t = 0.25 * math.pi * D_t * D_t
    if np.any(A0 > A_t):
        raise ValueError(f"A0 = {float(np.max(A0)):g} m2 is larger than the column's "
                         "cross-section: fewer than one orifice")
    _mori_wen_ranges(D_t, Umf, excess, d_p)
    # the growth factor exp(-0.3 h / D_t) over the broadcast of h and D_t alone (on a map
    # a few values, not one per element: its exp was a third of the law's time), by the
    # same compiled exp, so the same numbers
    growth = _mori_wen_growth(h, D_t)
    if np.ndim(excess) == 0:
        return _mori_wen(excess, A_t, A0, growth)
    return _mori_wen_arrays(excess, A_t, A0, growth)


def _mori_wen_ranges(D_t, Umf, excess, d_p) -> None:
    """Warn where ``D_t``, ``Umf``, ``U - Umf`` (``excess``: the array, or its least and
    largest values, no NaN among them) or ``d_p`` leave the data of Mori and Wen (1975),
    naming the first such input and its extreme value."""
    rng = MORI_WEN_RANGE
    D_t, Umf, d_p = _own(D_t), _own(Umf), _own(d_p)
    checks = [("D_t", D_t, "m"), ("Umf", np.asarray(Umf, float), "m/s"),
              ("U - Umf", excess, "m/s")] + ([("d_p", np.asarray(d_p, float), "m")]
                                             if d_p is not None else [])
    for name, val, unit in checks:
        lo, hi = rng["excess" if name == "U - Umf" else name]
        # two reductions, no temporaries; with a NaN among the values (its minimum is
        # NaN) the element-wise comparisons, which skip it
        mn, mx = val if type(val) is tuple else (np.min(val), np.max(val))
        if mn != mn:
            out_lo, out_hi = bool(np.any(val < lo)), bool(np.any(val > hi))
        else:
            out_lo, out_hi = bool(mn < lo), bool(mx > hi)
        if out_lo or out_hi:
            out = float(mn) if out_lo else float(mx)
            # stacklevel: _warn, here, the correlation (or the map pass), its caller
            _warn(f"bubble_diameter_mori_wen: {name} = {out:g} {unit} is outside the data "
                  f"of Mori and Wen (1975), {lo:g}-{hi:g} {unit}", stacklevel=4)


def _mori_wen_arrays(excess, A_t, A0, growth):
    """:func:`_mori_wen` on a map's arrays, in numpy: the same operations in the same
    order, the powers by numpy's vectorized ``pow`` (SIMD where the processor has it; it
    may differ from the C library's by 1 ulp, 2.2e-16 relative) rather than one C library
    call per element (two thirds of the correlation's time); in place where it can."""
    d_bm = np.multiply(A_t, excess)
    np.power(d_bm, 0.4, out=d_bm)
    d_bm *= _MW_MAX
    if np.ndim(A0) == 0:  # one distributor (a map's usual case): one form
        if A0 > 0.0:
            d_b0 = np.multiply(A0, excess)
            np.power(d_b0, 0.4, out=d_b0)
            d_b0 *= _MW_PERFORATED
        else:
            d_b0 = np.multiply(excess, excess)
            d_b0 *= _MW_POROUS
    else:
        d_b0 = np.where(A0 > 0.0, _MW_PERFORATED * np.power(A0 * excess, 0.4),
                        _MW_POROUS * (excess * excess))
    shape = np.broadcast_shapes(d_bm.shape, d_b0.shape, np.shape(growth))
    out = np.subtract(d_bm, d_b0, out=d_b0 if d_b0.shape == shape else None)  # d_b0's own
    here = out if out.shape == shape else None
    out = np.multiply(out, growth, out=here)
    return np.subtract(d_bm, out, out=out)


@vectorize(cache=CACHE)
def _mori_wen_growth(h, D_t):  # pragma: no cover - compiled
    """``exp(-0.3 h / D_t)``: how far bubbles at height ``h`` are from Mori and Wen's
    initial size towards their maximum (compiled)."""
    return math.exp(-0.3 * h / D_t)


@vectorize(cache=CACHE)
def _mori_wen(excess, A_t, A0, growth):  # pragma: no cover - compiled
    """Mori and Wen's ``d_b`` of one element, ``growth`` its :func:`_mori_wen_growth`
    (compiled: one pass, no temporaries)."""
    d_bm = _MW_MAX * (A_t * excess) ** 0.4
    if A0 > 0.0:
        d_b0 = _MW_PERFORATED * (A0 * excess) ** 0.4
    else:
        d_b0 = _MW_POROUS * (excess * excess)
    return d_bm - (d_bm - d_b0) * growth


def bubble_rise_velocity_davidson_harrison(d_b, D_t=None):
    """Rise velocity of a single bubble in a fluidized bed, Davidson and Harrison [m/s].

    Parameters
    ----------
    d_b : array_like
        Bubble diameter [m].
    D_t : array_like, optional
        Column diameter [m]: given, the wall slows bubbles wider than 0.125 ``D_t``.

    Returns
    -------
    numpy.ndarray
        ``u_br`` [m/s].

    Notes
    -----
    A bubble rises like a spherical-cap bubble in a liquid::

        u_br = 0.711 sqrt(g d_b)                              d_b / D_t < 0.125
        u_br = 0.711 sqrt(g d_b) 1.2 exp(-1.49 d_b / D_t)     0.125 <= d_b / D_t < 0.6

    (the wall factor is Wallis's, as Kunii and Levenspiel give it). Where
    ``d_b >= 0.6 D_t`` the bed slugs: a :class:`~agglomtool.PlausibilityWarning`, and the
    rise velocity of a slug, ``0.35 sqrt(g D_t)``, is returned instead.

    References
    ----------
    J. F. Davidson, D. Harrison (1963), Fluidised Particles, Cambridge University Press;
    Kunii and Levenspiel (1991), Fluidization Engineering, 2nd ed., ch. 5 (wall effect,
    after G. B. Wallis (1969), One-dimensional Two-phase Flow, McGraw-Hill).
    """
    d_b = check_range("d_b", d_b, 0.0, None, lo_open=True, unit="m")
    if D_t is None:
        return 0.711 * np.sqrt(GRAVITY * d_b)
    D_t = check_range("D_t", D_t, 0.0, None, lo_open=True, unit="m")
    _check_slugging(d_b, D_t)
    return _rise_with_wall(d_b, D_t)


def _check_slugging(d_b, D_t, stacklevel=4, worst=None) -> None:
    """Warn where bubbles fill 0.6 of the column or more, naming the largest ratio
    (``worst``, the largest ``d_b / D_t``, where the caller has it)."""
    # a scalar column: the largest bubble over it (division by a positive number keeps
    # the order, so the same number without a full-size quotient)
    if worst is None:
        worst = float(np.max(d_b) / D_t) if D_t.ndim == 0 else float(np.max(d_b / D_t))
    if worst >= SLUGGING_RATIO:
        _warn(f"bubbles of d_b = {worst:.3g} D_t: the bed slugs (d_b >= {SLUGGING_RATIO:g} "
              "D_t), outside the bubbling-bed correlations; the rise velocity of slugs, "
              "0.35 sqrt(g D_t), is used there. A wider column, a lower U or a shallower "
              "height of interest gives bubbling", stacklevel=stacklevel)


@vectorize(cache=CACHE)
def _rise_with_wall(d_b, D_t):  # pragma: no cover - compiled
    """Davidson and Harrison's rise velocity with Wallis's wall factor, or a slug's, of one
    element (compiled)."""
    return _rise_one(d_b, D_t)


@njit(cache=CACHE, error_model="numpy")
def _rise_one(d_b, D_t):  # pragma: no cover - compiled
    """The rise velocity of one bubble (shared by the vectorized forms)."""
    return _rise_of(d_b, D_t, _wall_of(d_b, D_t))


@njit(cache=CACHE, error_model="numpy")
def _wall_regime(ratio):  # pragma: no cover - compiled
    """Whether a bubble of ``d_b / D_t = ratio`` rises with Wallis's wall factor
    (``0.125 <= ratio < 0.6``; a NaN too, as the comparisons leave it there)."""
    return not ratio >= SLUGGING_RATIO and not ratio < 0.125


@njit(cache=CACHE, error_model="numpy")
def _wall_of(d_b, D_t):  # pragma: no cover - compiled
    """``exp(-1.49 d_b / D_t)`` where :func:`_wall_regime`, else 0 (not used there)."""
    ratio = d_b / D_t
    return math.exp(-1.49 * ratio) if _wall_regime(ratio) else 0.0


@njit(cache=CACHE, error_model="numpy")
def _rise_of(d_b, D_t, wall):  # pragma: no cover - compiled
    """The rise velocity of one bubble, ``wall`` its :func:`_wall_of`: every form
    computed and the one that applies selected (no branch: a loop of these vectorizes;
    no form can raise, so the numpy error model, which checks no division)."""
    ratio = d_b / D_t
    slug = 0.35 * math.sqrt(GRAVITY * D_t)
    free = 0.711 * math.sqrt(GRAVITY * d_b)
    rise = free if ratio < 0.125 else free * (1.2 * wall)
    return slug if ratio >= SLUGGING_RATIO else rise


def bubble_velocity_davidson_harrison(U, Umf, d_b, D_t=None):
    """Rise velocity of bubbles in a bubbling bed, Davidson and Harrison [m/s].

    ``u_b = U - Umf + u_br(d_b)``: a single bubble's rise velocity
    (:func:`bubble_rise_velocity_davidson_harrison`) plus the excess gas's upflow.

    Parameters
    ----------
    U, Umf : array_like
        Superficial and minimum fluidization velocities [m/s], ``U > Umf``.
    d_b : array_like
        Bubble diameter [m].
    D_t : array_like, optional
        Column diameter [m] (wall effect and slugging).

    References
    ----------
    J. F. Davidson, D. Harrison (1963), Fluidised Particles, Cambridge University Press;
    Kunii and Levenspiel (1991), ch. 6.
    """
    return _excess(U, Umf) + bubble_rise_velocity_davidson_harrison(d_b, D_t)


def bubble_fraction_kunii_levenspiel(U, Umf, u_b, eps_mf):
    """Fraction of the bed's volume in bubbles, Kunii and Levenspiel [-].

    Parameters
    ----------
    U, Umf : array_like
        Superficial and minimum fluidization velocities [m/s], ``U > Umf``.
    u_b : array_like
        Bubble rise velocity [m/s].
    eps_mf : array_like
        Voidage at minimum fluidization [-].

    Returns
    -------
    numpy.ndarray
        ``delta`` in (0, 1).

    Notes
    -----
    The excess gas flows as bubbles; how much gas the bubbles carry through their clouds
    depends on how fast they rise against the emulsion gas ``u_f = Umf / eps_mf``
    (Kunii and Levenspiel's eqs. 6.26-6.29)::

        delta = (U - Umf) / (u_b + 2 Umf)    u_b < u_f              (slow bubbles)
        delta = (U - Umf) / (u_b + Umf)      u_b ~ u_f              (u_f <= u_b < 3 u_f)
        delta = (U - Umf) / u_b              u_b ~ 5 u_f            (3 u_f <= u_b <= 5 u_f)
        delta = (U - Umf) / (u_b - Umf)      u_b > 5 u_f            (fast, up to 10 u_f)
        delta = U / u_b                      u_b >> u_f             (10 u_f < u_b)

    In very fast bubbling the emulsion gas is dragged down with the solids and the
    bubbles carry all of the gas, hence ``U`` rather than ``U - Umf`` in the last form.
    The limits between the named cases (3, 5 and 10 ``u_f``) are those of the chemics
    package's implementation of the same equations, against which this one is tested;
    the forms do not join at them. A fraction of 1 or more (the gas cannot pass as
    bubbles this slow) raises a ``ValueError``.

    References
    ----------
    D. Kunii, O. Levenspiel (1991), Fluidization Engineering, 2nd ed., Butterworth-
    Heinemann, ch. 6 (bubble fraction in the bubbling-bed model, eqs. 6.26-6.29);
    O. Levenspiel (1999), Chemical Reaction Engineering, 3rd ed., Wiley, ch. 20
    (``delta = u0 / u_b`` for fast bubbles).
    """
    excess = _excess(U, Umf)
    Umf = np.asarray(Umf, dtype=float)
    u_b = check_range("u_b", u_b, 0.0, None, lo_open=True, unit="m/s")
    eps_mf = check_range("eps_mf", eps_mf, 0.0, 1.0, lo_open=True, hi_open=True)
    delta = _fraction(excess, Umf, u_b, eps_mf)
    worst = np.max(delta)  # one reduction (every input checked finite: no NaN in delta)
    if worst >= 1.0:
        raise ValueError(f"bubble fraction delta = {float(worst):.3g} >= 1: bubbles "
                         "rising this slowly cannot carry U - Umf; outside the bubbling-bed "
                         "model")
    return delta


@vectorize(cache=CACHE)
def _fraction(excess, Umf, u_b, eps_mf):  # pragma: no cover - compiled
    """Kunii and Levenspiel's bubble fraction of one element, its regime by ``u_b / u_f``
    (compiled: the one form that applies is evaluated, not all five)."""
    return _fraction_one(excess, Umf, u_b, eps_mf)


@njit(cache=CACHE, error_model="numpy")
def _fraction_one(excess, Umf, u_b, eps_mf):  # pragma: no cover - compiled
    """The bubble fraction of one element (shared by the vectorized forms): the regime's
    numerator and denominator selected, one division (no branch)."""
    ratio = u_b / (Umf / eps_mf)
    num = excess if ratio <= 10.0 else excess + Umf
    den = (u_b + 2.0 * Umf if ratio < 1.0 else u_b + Umf if ratio < 3.0
           else u_b if ratio <= 5.0 else u_b - Umf if ratio <= 10.0 else u_b)
    return num / den


def solids_downflow_kunii_levenspiel(delta, u_b, wake_fraction):
    """Downflow velocity of the emulsion solids, Kunii and Levenspiel [m/s].

    Solids carried up in the bubbles' wakes (volume ``wake_fraction`` of each bubble's)
    return down through the emulsion; with no net flow of solids::

        u_s = f_w delta u_b / (1 - delta - f_w delta)

    Parameters
    ----------
    delta : array_like
        Bubble fraction [-].
    u_b : array_like
        Bubble rise velocity [m/s].
    wake_fraction : array_like
        ``f_w``, wake volume over bubble volume [-].

    References
    ----------
    Kunii and Levenspiel (1991), Fluidization Engineering, 2nd ed., ch. 6.
    """
    delta = check_range("delta", delta, 0.0, 1.0, hi_open=True)
    f_w = check_range("wake_fraction", wake_fraction, 0.0, None, lo_open=True)
    emulsion = 1.0 - delta - f_w * delta
    if np.any(emulsion <= 0.0):
        raise ValueError(f"wake_fraction = {float(np.max(f_w)):g}: bubbles and their wakes "
                         f"fill the bed (delta = {float(np.max(delta)):.3g}); no emulsion "
                         "is left for the solids' downflow: U - Umf is beyond a bubbling "
                         "bed (lower U, a smaller wake_fraction, or another speed model)")
    return f_w * delta * np.asarray(u_b, float) / emulsion


def granular_temperature_bubble_wake(delta, u_b, wake_fraction):
    """Granular temperature of the solids' circulation by bubble wakes [m2/s2].

    Parameters
    ----------
    delta : array_like
        Bubble fraction [-].
    u_b : array_like
        Bubble rise velocity [m/s].
    wake_fraction : array_like
        Wake volume over bubble volume [-].

    Returns
    -------
    numpy.ndarray
        ``Theta_b`` [m2/s2], the variance per velocity component.

    Notes
    -----
    In the bubbling-bed model of Kunii and Levenspiel a fraction
    ``phi = f_w delta / (1 - delta)`` of the solids rides up in the wakes at ``u_b`` and the
    rest sinks at ``u_s = phi u_b / (1 - phi)``
    (:func:`solids_downflow_kunii_levenspiel`). The variance of the solids' vertical
    velocity is then ``phi u_b**2 / (1 - phi)``; this function returns a third of it, the
    granular temperature ``<C.C>/3`` of a velocity field that moves only vertically. It is
    the "bubble-like" granular temperature of Jung, Gidaspow and Gamwo (2005) (the
    variance of the solids' mean motion by bubbles) computed from the bubbling-bed model
    rather than measured; they found it much larger than the particles' own
    ("laminar") granular temperature, and the vertical normal stress about 8 times the
    lateral one.

    References
    ----------
    Kunii and Levenspiel (1991), Fluidization Engineering, 2nd ed., ch. 6; J. Jung,
    D. Gidaspow, I. K. Gamwo (2005), Measurement of two kinds of granular temperatures,
    stresses, and dispersion in bubbling beds, Ind. Eng. Chem. Res. 44:1329-1341,
    doi:10.1021/ie0496838.
    """
    if _float_arrays(delta, u_b, wake_fraction) and (np.ndim(delta) or np.ndim(u_b)):
        # on a map's arrays: the checks and the formula in one compiled pass (the same
        # operations in the same order, so the same numbers); any bad element reruns the
        # plain checks below for their message
        with np.errstate(invalid="ignore"):  # a NaN compared: the plain path names it
            theta = _wake_checked(delta, u_b, wake_fraction)
        if theta.size and theta.min() >= 0.0:
            return theta
    delta = check_range("delta", delta, 0.0, 1.0, hi_open=True)
    f_w = check_range("wake_fraction", wake_fraction, 0.0, None, lo_open=True)
    u_b = check_range("u_b", u_b, 0.0, None, unit="m/s")
    if np.any(1.0 - delta - f_w * delta <= 0.0):
        solids_downflow_kunii_levenspiel(delta, u_b, f_w)  # raises, naming the cause
    phi = f_w * delta / (1.0 - delta)
    return phi * u_b * u_b / (3.0 * (1.0 - phi))


@vectorize(cache=CACHE)
def _wake_checked(delta, u_b, f_w):  # pragma: no cover - compiled
    """The wakes' granular temperature of one element where ``0 <= delta < 1``,
    ``0 <= u_b``, ``0 < f_w``, both finite, and the wakes leave an emulsion; else -1 (no
    temperature is negative): the caller then takes the plain path for the message."""
    return _wake_one(delta, u_b, f_w)


@njit(cache=CACHE, error_model="numpy")
def _wake_one(delta, u_b, f_w):  # pragma: no cover - compiled
    """The wakes' granular temperature of one element, or -1 outside the domain (computed,
    then selected: no branch)."""
    ok = ((0.0 <= delta) & (delta < 1.0) & (0.0 <= u_b) & (u_b < math.inf) & (0.0 < f_w)
          & (f_w < math.inf) & (1.0 - delta - f_w * delta > 0.0))
    phi = f_w * delta / (1.0 - delta)
    theta = phi * u_b * u_b / (3.0 * (1.0 - phi))
    return theta if ok else -1.0


@vectorize(cache=CACHE)
def _bubble_chain(excess, Umf, d_b, D_t, eps_mf, f_w):  # pragma: no cover - compiled
    """Rise velocity, bubble fraction and the wakes' granular temperature of one element in
    one pass: the same compiled operations as :func:`bubble_velocity_davidson_harrison`,
    :func:`bubble_fraction_kunii_levenspiel` and :func:`granular_temperature_bubble_wake`
    in turn, or -1 where any of their checks would object (the caller then takes them in
    turn for the message)."""
    return _chain_steps(excess, Umf, d_b, D_t, eps_mf, f_w)


@njit(cache=CACHE, error_model="numpy")
def _chain_steps(excess, Umf, d_b, D_t, eps_mf, f_w):  # pragma: no cover - compiled
    """The chain's steps of one element (:func:`_chain_given` with its wall factor)."""
    return _chain_given(excess, Umf, d_b, D_t, eps_mf, f_w, _wall_of(d_b, D_t))


@njit(cache=CACHE, error_model="numpy")
def _chain_given(excess, Umf, d_b, D_t, eps_mf, f_w, wall):  # pragma: no cover - compiled
    """The chain's steps of one element, ``wall`` the bubble's :func:`_wall_of`, written
    once for :func:`_bubble_chain` and the map pass: the granular temperature, or -1 where
    a check objects. Every step computed and the checks combined (no branch: the map
    pass's loop of these vectorizes; a step past a failed check gives a number that is
    not used, and none raises)."""
    ok = ((0.0 < d_b) & (d_b < math.inf) & (0.0 < D_t) & (D_t < math.inf) & (0.0 < eps_mf)
          & (eps_mf < 1.0))
    u_b = excess + _rise_of(d_b, D_t, wall)
    ok = ok & (0.0 < u_b) & (u_b < math.inf)
    delta = _fraction_one(excess, Umf, u_b, eps_mf)
    theta = _wake_one(delta, u_b, f_w)
    return theta if ok & (delta < 1.0) else -1.0


@vectorize(cache=CACHE)
def bubble_domain(excess, Umf, d_b, D_t, eps_mf, f_w):  # pragma: no cover - compiled
    """Where the bubbling-bed chain of ``granular_temperature_bubbles`` has an answer,
    per element: 0 where it has; 2 where Kunii and Levenspiel's bubble fraction is 1 or
    more (:func:`bubble_fraction_kunii_levenspiel` refuses); 3 where bubbles and their
    wakes leave no emulsion (:func:`solids_downflow_kunii_levenspiel` refuses); 4 for any
    other input the chain refuses. ``excess`` is ``U - Umf`` (> 0), ``d_b`` the bubble
    size. The same compiled operations as the chain, so the same verdict."""
    return _domain_code(excess, Umf, d_b, D_t, eps_mf, f_w)


@njit(cache=CACHE)
def _domain_code(excess, Umf, d_b, D_t, eps_mf, f_w):  # pragma: no cover - compiled
    """:func:`bubble_domain`'s code of one element, written once for it and the map
    pass's :func:`_chain_code`."""
    if not (0.0 < d_b < math.inf and 0.0 < D_t < math.inf and 0.0 < eps_mf < 1.0
            and 0.0 < excess < math.inf and 0.0 < f_w < math.inf):
        return 4
    u_b = excess + _rise_one(d_b, D_t)
    if not 0.0 < u_b < math.inf:
        return 4
    delta = _fraction_one(excess, Umf, u_b, eps_mf)
    if not delta < 1.0:
        return 2
    if not 1.0 - delta - f_w * delta > 0.0:
        return 3
    return 0


def granular_temperature_bubbles(U, Umf, d_b, D_t, eps_mf, wake_fraction):
    """Granular temperature of the solids' circulation by bubbles of diameter ``d_b``
    [m2/s2]: :func:`bubble_velocity_davidson_harrison`,
    :func:`bubble_fraction_kunii_levenspiel` and :func:`granular_temperature_bubble_wake`
    in turn (their checks, errors and warnings), on a map's arrays in one compiled pass
    with the same numbers.

    Parameters
    ----------
    U, Umf : array_like
        Superficial and minimum fluidization velocities [m/s], ``U > Umf``.
    d_b : array_like
        Bubble diameter [m].
    D_t : array_like
        Column diameter [m].
    eps_mf : array_like
        Voidage of the emulsion [-].
    wake_fraction : array_like
        Wake volume over bubble volume [-].
    """
    if (_float_arrays(U, Umf, d_b, D_t, eps_mf, wake_fraction)
            and (np.ndim(U) or np.ndim(Umf) or np.ndim(d_b))):
        excess = _excess(U, Umf)
        with np.errstate(invalid="ignore"):  # a NaN compared: the plain path names it
            theta = _bubble_chain(excess, Umf, d_b, D_t, eps_mf, wake_fraction)
        if theta.size and theta.min() >= 0.0:
            _check_slugging(np.asarray(d_b), np.asarray(D_t), stacklevel=4)
            return theta
    u_b = bubble_velocity_davidson_harrison(U, Umf, d_b, D_t)
    delta = bubble_fraction_kunii_levenspiel(U, Umf, u_b, eps_mf)
    return granular_temperature_bubble_wake(delta, u_b, wake_fraction)


def radial_distribution_carnahan_starling(eps_s):
    """Radial distribution function at contact of hard spheres, Carnahan and Starling [-].

    ``g0 = (1 - eps_s / 2) / (1 - eps_s)**3`` for the solids fraction ``eps_s`` in [0, 1).

    References
    ----------
    N. F. Carnahan, K. E. Starling (1969), Equation of state for nonattracting rigid
    spheres, J. Chem. Phys. 51:635-636, doi:10.1063/1.1672048.
    """
    eps_s = check_range("eps_s", eps_s, 0.0, 1.0, hi_open=True)
    return (1.0 - 0.5 * eps_s) / (1.0 - eps_s) ** 3


def granular_temperature_collisional_balance(U, Umf, d_p, rho_p, rho_g, eps_mf, e):
    """Granular temperature at which collisions dissipate the excess gas's power [m2/s2].

    Parameters
    ----------
    U, Umf : array_like
        Superficial and minimum fluidization velocities [m/s], ``U > Umf``.
    d_p : array_like
        Particle diameter [m].
    rho_p, rho_g : array_like
        Particle and gas densities [kg/m3].
    eps_mf : array_like
        Voidage of the emulsion (at minimum fluidization) [-].
    e : array_like
        Restitution coefficient of particle collisions [-], below 1.

    Returns
    -------
    numpy.ndarray
        ``Theta`` [m2/s2].

    Notes
    -----
    The gas in excess of ``U_mf`` crosses the bed against its weight: it delivers the
    power ``(U - Umf) (1 - eps_mf) (rho_p - rho_g) g`` per unit bed volume. The kinetic
    theory of granular flow dissipates fluctuation energy in inelastic collisions at the
    rate ``12 (1 - e**2) eps_s**2 rho_p g0 Theta**1.5 / (d_p sqrt(pi))`` (Lun et al. 1984,
    as in Gidaspow 1994, ch. 9), ``eps_s = 1 - eps_mf``, ``g0`` of Carnahan and Starling.
    Equating the two::

        Theta**1.5 = (U - Umf) (1 - rho_g/rho_p) g d_p sqrt(pi) / (12 (1 - e**2) eps_s g0)

    This balance is this package's construction from the two cited pieces, not a published
    correlation: it puts all of the excess gas's power into particle-scale fluctuations,
    while part of it drives the bed's mean circulation and part is lost to the gas's
    viscous damping of the fluctuations (neglected; small for Geldart B and D particles,
    large for fine ones): an upper bound of the particles' own granular temperature. A
    Geldart group A powder, where the neglected damping is large, warns
    (:class:`~agglomtool.PlausibilityWarning`).

    References
    ----------
    C. K. K. Lun, S. B. Savage, D. J. Jeffrey, N. Chepurniy (1984), Kinetic theories for
    granular flow, J. Fluid Mech. 140:223-256, doi:10.1017/S0022112084000586;
    D. Gidaspow (1994), Multiphase Flow and Fluidization, Academic Press, ch. 9.
    """
    excess = _excess(U, Umf)
    d_p = check_range("d_p", d_p, 0.0, None, lo_open=True, unit="m")
    rho_p = check_range("rho_p", rho_p, 0.0, None, lo_open=True, unit="kg/m3")
    rho_g = check_range("rho_g", rho_g, 0.0, None, unit="kg/m3")
    e = check_range("e", e, 0.0, 1.0, hi_open=True)
    eps_s = 1.0 - check_range("eps_mf", eps_mf, 0.0, 1.0, lo_open=True, hi_open=True)
    if np.any(rho_p <= rho_g):
        raise ValueError("rho_p must exceed rho_g: a particle lighter than the gas does not "
                         "fluidize")
    _check_group("granular_temperature_collisional_balance", d_p, rho_p, rho_g,
                 allowed=("B", "D"), why="the balance neglects the gas's viscous damping of "
                 "the particles' fluctuations, large for such fine powders")
    g0 = radial_distribution_carnahan_starling(eps_s)
    power = excess * (1.0 - rho_g / rho_p) * GRAVITY * d_p * math.sqrt(math.pi)
    return (power / (12.0 * (1.0 - e * e) * eps_s * g0)) ** (2.0 / 3.0)


# --- the laws on a map's arrays: compiled parallel passes --------------------------------
#
# On a map (10**5-10**6 points a block) the correlations above each take a full-size pass
# or more, single-threaded, while the collisions run on every core. The passes below give
# the same numbers on every thread, reading each input by its broadcast steps (no
# full-size copy of an input that varies along some axes only). The powers stay numpy's
# (its vectorized ``pow``, as the plain path takes them, in pieces on the threads): the C
# library's ``pow``, which a compiled loop calls, costs 23 ns an element here against
# numpy's 2.6, and differs from numpy's by 1 ulp in about one element of 20. Then one pass
# takes the rest of the law, the bounds its warnings need and the ``speed_flag`` codes.
# Any element refused otherwise than by the model's domain, or an input the checks
# refuse, gives ``None``: the caller then takes the plain path, whose errors are the only
# ones.

#: Elements of a map below which the laws take the plain path (a parallel launch costs
#: tens of microseconds; a single Scene never takes these passes).
MAP_PASS_MIN = 4096
#: Blocks per thread of a pass (the elements cost alike; a few blocks each evens out a
#: thread that was descheduled).
_BLOCKS_PER_THREAD = 4
#: The longest piece of a row a pass takes in one go [elements] (its buffers stay in the
#: processor's first-level cache).
_PIECE = 1024
#: Darton's constant factor ``g**-0.2``, as the plain expression takes it (a Python float).
_G_M02 = GRAVITY**-0.2


def _map_inputs(values, shape) -> tuple | None:
    """``values`` (float64 arrays or floats broadcasting to ``shape``) as the passes read
    them: ``(arrays, st, shp)``, ``arrays`` a tuple of flat C-contiguous float64 arrays,
    each the input's own elements (no broadcast copy), ``st[i, d]`` the step in elements
    of input ``i`` along axis ``d`` of ``shp`` (0 where it broadcasts), ``shp`` the shape
    with its axes of one dropped and neighbours that every input steps through alike
    merged (numpy's iterator coalescing). None where an input is not float64."""
    flat, steps = [], []
    for v in values:
        if type(v) is float or type(v) is np.float64:
            a = np.array([v], dtype=np.float64)
        elif isinstance(v, np.ndarray) and v.dtype == np.float64:
            a = v if v.flags.c_contiguous and v.flags.writeable else np.array(v, order="C")
        else:
            return None
        # the steps of the broadcast view, from the input's own (its axes are the shape's
        # last ones; an axis of one, or one it lacks, has step 0)
        lead = len(shape) - a.ndim
        steps.append([0 if d < lead or a.shape[d - lead] == 1 else a.strides[d - lead] // 8
                      for d in range(len(shape))])
        flat.append(a.reshape(-1))
    dims: list[int] = []
    cols: list[list[int]] = []
    for d, m in enumerate(shape):
        if m == 1:
            continue
        col = [row[d] for row in steps]
        if dims and all(o == i * m for o, i in zip(cols[-1], col, strict=True)):
            dims[-1] *= m  # the outer axis steps as the inner one run on: one axis
            cols[-1] = col
        else:
            dims.append(m)
            cols.append(col)
    st = np.array(cols, dtype=np.int64).T.reshape(len(values), len(dims)).copy()
    return tuple(flat), st, np.array(dims, dtype=np.int64)


def _plan(shp) -> tuple[tuple[int, int, int], int]:
    """How a pass splits the elements of ``shp`` (the shape of :func:`_map_inputs`):
    ``((chunk, per_row, per_block), blocks)``. A pass runs along the last axis (a row) in
    pieces of at most ``chunk`` elements, ``per_row`` pieces a row, ``per_block`` pieces a
    block, ``blocks`` blocks (a few a thread)."""
    n = math.prod(int(m) for m in shp)
    row = int(shp[-1])
    lanes = numba.get_num_threads() * _BLOCKS_PER_THREAD
    chunk = min(row, _PIECE)
    per_row = -(-row // chunk)
    pieces = (n // row) * per_row
    per_block = -(-pieces // lanes)
    return (chunk, per_row, per_block), -(-pieces // per_block)


@njit(cache=CACHE)
def _row_offsets(off, st, shp, row, j0):  # pragma: no cover - compiled
    """``off[i]``: input ``i``'s offset at element ``j0`` of row ``row`` (the rows in C order
    of the axes of ``shp`` but the last)."""
    last = shp.shape[0] - 1
    for i in range(st.shape[0]):
        off[i] = j0 * st[i, last]
    for d in range(last - 1, -1, -1):
        q = row // shp[d]
        m = row - q * shp[d]
        row = q
        for i in range(st.shape[0]):
            off[i] += m * st[i, d]


@njit(parallel=True, cache=CACHE)
def _bubble_pass(ins, st, shp, plan, mori_wen, theta, code, stats):  # pragma: no cover
    """The bubble size and :func:`_bubble_chain` of every element into ``theta``, and
    into ``code`` (zeros on entry) where it has no answer: the
    :data:`.speed_models.SPEED_FLAGS` code of :func:`.speed_models.speed_domain` (1 where
    ``U <= Umf``; 2, 3 or 4 as :func:`bubble_domain`), or 5 where ``U`` or ``Umf`` is
    itself refused (negative, not finite). ``theta`` is NaN there.

    ``ins``: U, Umf, P, Q, A0, fac, D_t, eps_mf, f_w. Darton: ``P`` is ``(U - Umf)**0.4``,
    ``fac`` ``(h + 4 sqrt(A0))**0.8``; Mori and Wen (``mori_wen``): ``P`` is
    ``(A_t (U - Umf))**0.4``, ``Q`` ``(A0 (U - Umf))**0.4``, ``fac`` the growth factor.
    The operations of :func:`bubble_diameter_darton` and :func:`_mori_wen` in their
    order. ``stats[blk]``: the counts of codes 1 to 5, the largest ``d_b / D_t``
    (slugging), the least and the largest ``U - Umf``."""
    for blk in prange(stats.shape[0]):  # each block a serial loop: a small
        # parallel body compiles faster
        _bubble_block(ins, st, shp, plan, mori_wen, theta, code, stats, blk)


@njit(cache=CACHE, error_model="numpy")
def _bubble_block(ins, st, shp, plan, mori_wen, theta, code, stats, blk):  # pragma: no cover
    """Block ``blk`` of :func:`_bubble_pass`."""
    chunk, per_row, per_block = plan
    last = shp.shape[0] - 1
    row_len = shp[last]
    pieces = (theta.shape[0] // row_len) * per_row
    s0, s1, s2, s3, s4 = st[0, last], st[1, last], st[2, last], st[3, last], st[4, last]
    s5, s6, s7, s8 = st[5, last], st[6, last], st[7, last], st[8, last]
    x0, x1, x2, x3, x4, x5, x6, x7, x8 = ins
    off = np.empty(9, np.int64)
    # a piece's excess gas and bubble sizes first, then the wall factors its chain
    # takes, then its chain, each a loop of its own: the chain's loop has no branch and
    # no call (the exp, a call to the C library, has its loop), so the compiler
    # vectorizes it
    ex_buf = np.empty(chunk)
    db_buf = np.empty(chunk)
    wall_buf = np.empty(chunk)
    at = np.empty(chunk, np.int64)
    umf_buf = np.empty(chunk)
    dt_buf = np.empty(chunk)
    eps_buf = np.empty(chunk)
    fw_buf = np.empty(chunk)
    counts = np.zeros(6, np.int64)
    worst = -math.inf
    lo = math.inf
    hi = -math.inf
    for piece in range(blk * per_block, min(pieces, (blk + 1) * per_block)):
        row = piece // per_row
        j0 = (piece - row * per_row) * chunk
        _row_offsets(off, st, shp, row, j0)
        o0, o1, o2, o3, o4 = off[0], off[1], off[2], off[3], off[4]
        o5, o6, o7, o8 = off[5], off[6], off[7], off[8]
        k = row * row_len + j0
        m = min(row_len - j0, chunk)
        if s0 == 1 and s2 == 1 and s1 == 0 and s4 == 0 and s5 == 0:
            # a map's usual row: U and the powers run along it, U_mf, the plate and
            # the growth factor do not: a loop without branches, which the compiler
            # vectorizes (_excess_one is a selection)
            Umf = x1[o1]
            fac = x5[o5]
            perforated = x4[o4] > 0.0
            for j in range(m):
                excess = _excess_one(x0[o0 + j], Umf)
                P = x2[o2 + j]
                if mori_wen:
                    d_bm = P * _MW_MAX
                    d_b0 = (x3[o3 + j * s3] * _MW_PERFORATED if perforated
                            else (excess * excess) * _MW_POROUS)
                    d_b = d_bm - (d_bm - d_b0) * fac
                else:
                    d_b = 0.54 * P * fac * _G_M02
                ex_buf[j] = excess
                db_buf[j] = d_b
        else:
            for j in range(m):
                excess = _excess_one(x0[o0 + j * s0], x1[o1 + j * s1])
                P = x2[o2 + j * s2]
                fac = x5[o5 + j * s5]
                if mori_wen:
                    d_bm = P * _MW_MAX
                    if x4[o4 + j * s4] > 0.0:
                        d_b0 = x3[o3 + j * s3] * _MW_PERFORATED
                    else:
                        d_b0 = (excess * excess) * _MW_POROUS
                    d_b = d_bm - (d_bm - d_b0) * fac
                else:
                    d_b = 0.54 * P * fac * _G_M02
                ex_buf[j] = excess
                db_buf[j] = d_b
        # the wall factor where the chain takes it: the elements listed first (no
        # branch), then one exp each (the C library's, as before)
        n_wall = 0
        for j in range(m):
            wall_buf[j] = 0.0
            at[n_wall] = j
            n_wall += _wall_regime(db_buf[j] / x6[o6 + j * s6])
        for i in range(n_wall):
            j = at[i]
            wall_buf[j] = _wall_of(db_buf[j], x6[o6 + j * s6])
        # the chain: where U_mf and the bed do not vary along the row (a map's usual
        # row), read once; else by their steps
        refused = 0
        if s1 == 0 and s6 == 0 and s7 == 0 and s8 == 0:
            Umf, D_t, eps_mf, f_w = x1[o1], x6[o6], x7[o7], x8[o8]
            for j in range(m):
                t = _chain_one(ex_buf[j], Umf, db_buf[j], D_t, eps_mf, f_w, wall_buf[j])
                refused += not t >= 0.0
                theta[k + j] = t
        else:  # gathered into buffers first, so that the chain's loop reads them in
            # steps of one (a loop of varying steps does not vectorize)
            for j in range(m):
                umf_buf[j] = x1[o1 + j * s1]
                dt_buf[j] = x6[o6 + j * s6]
                eps_buf[j] = x7[o7 + j * s7]
                fw_buf[j] = x8[o8 + j * s8]
            for j in range(m):
                t = _chain_one(ex_buf[j], umf_buf[j], db_buf[j], dt_buf[j], eps_buf[j],
                               fw_buf[j], wall_buf[j])
                refused += not t >= 0.0
                theta[k + j] = t
        # the least and largest excess (Mori and Wen's ranges) and the largest bubble
        largest = -math.inf
        if mori_wen:
            for j in range(m):
                lo = min(lo, ex_buf[j])
                hi = max(hi, ex_buf[j])
                largest = max(largest, db_buf[j])
        else:
            for j in range(m):
                largest = max(largest, db_buf[j])
        # the largest d_b / D_t: over one column, the largest bubble over it (a
        # division by a positive number keeps the order: the same number)
        if s6 == 0:
            worst = max(worst, largest / x6[o6])
        else:
            for j in range(m):
                worst = max(worst, db_buf[j] / x6[o6 + j * s6])
        for j in range(m if refused else 0):
            if not theta[k + j] >= 0.0:  # no answer: why (the plain path's order)
                Umf = x1[o1 + j * s1]
                if ex_buf[j] < 0.0:  # refused by _excess_one
                    U = x0[o0 + j * s0]
                    c = 1 if _flows_valid(U, Umf) else 5
                else:
                    c = _chain_code(ex_buf[j], Umf, db_buf[j], x6[o6 + j * s6],
                                    x7[o7 + j * s7], x8[o8 + j * s8])
                counts[c] += 1
                theta[k + j] = math.nan
                code[k + j] = c
    for c in range(1, 6):
        stats[blk, c - 1] = counts[c]
    stats[blk, 5] = worst
    stats[blk, 6] = lo
    stats[blk, 7] = hi


@njit(cache=CACHE, error_model="numpy")
def _chain_one(excess, Umf, d_b, D_t, eps_mf, f_w, wall):  # pragma: no cover - compiled
    """:func:`_bubble_chain` of one element (``excess`` -1 where :func:`_excess_one`
    refused it; ``wall`` its :func:`_wall_of`): its granular temperature, or -1 where a
    check objects (no branch)."""
    theta = _chain_given(excess, Umf, d_b, D_t, eps_mf, f_w, wall)
    return theta if 0.0 < excess else -1.0


@njit(cache=CACHE)
def _chain_code(excess, Umf, d_b, D_t, eps_mf, f_w):  # pragma: no cover - compiled
    """The :func:`bubble_domain` code of an element :func:`_chain_one` refuses (the same
    checks in the same order: the same verdict); 4 for any refusal it does not name."""
    code = _domain_code(excess, Umf, d_b, D_t, eps_mf, f_w)
    return 4 if code == 0 else code


def _run(kernel, ins, st, shp, *args, columns=1):
    """Launch pass ``kernel`` over the inputs ``ins, st, shp`` of :func:`_map_inputs` with
    its other arguments ``args`` (flags, outputs); its per-block statistics, ``columns``
    wide."""
    plan, blocks = _plan(shp)
    stats = np.empty((blocks, columns))
    parallel_launch(kernel, ins, st, shp, plan, *args, stats)
    return stats


def _map_shape(*values) -> tuple | None:
    """The broadcast shape of ``values`` where it is a map's (at least
    :data:`MAP_PASS_MIN` elements) and ``U - Umf`` (the first two) spans all of it (the
    powers then run on full-size arrays, as on the plain path); else None."""
    try:
        shape = np.broadcast_shapes(*(np.shape(v) for v in values))
    except ValueError:
        return None
    if (math.prod(shape) < MAP_PASS_MIN
            or np.broadcast_shapes(np.shape(values[0]), np.shape(values[1])) != shape):
        return None
    return shape


def bubble_theta_map(correlation, U, Umf, h, A0, D_t, eps_mf, wake_fraction, *, d_p,
                     rho_p, rho_g, partial=False):
    """The bubble models' granular temperature on a map's arrays [m2/s2]: the bubble size
    by ``correlation`` (``"darton"`` or ``"mori-wen"``), then
    :func:`granular_temperature_bubbles`; numpy's excess gas and powers, then one compiled
    parallel pass (:func:`_bubble_pass`).
    The same numbers, warnings and (through the plain path) errors as
    :func:`bubble_diameter_darton` or :func:`bubble_diameter_mori_wen` followed by
    :func:`granular_temperature_bubbles`. None (nothing warned) where an element is
    outside the domain, an input is refused or the arrays are not a map's: the caller
    then takes that plain path.

    With ``partial``, :func:`.speed_models.speed_law_partial`'s answer instead: ``(theta,
    flag)``, ``theta`` NaN where ``flag`` (the :func:`.speed_models.speed_domain` codes,
    int8) is not 0, ``flag`` None where every element answers; the warnings those of the
    plain path's first attempt. None where an element is refused otherwise than by the
    model's domain (code 4 or 5 of :func:`_bubble_pass`): the plain path then."""
    values = (U, Umf, h, A0, D_t, eps_mf, wake_fraction)
    shape = _map_shape(*values)
    if shape is None:
        return None
    # the inputs beside U and U_mf by their own values (a broadcast view's checks and
    # copies cost its distinct values; they broadcast to the same shape)
    h, A0, D_t, eps_mf, wake_fraction, d_p, rho_p, rho_g = (
        _own(v) for v in (h, A0, D_t, eps_mf, wake_fraction, d_p, rho_p, rho_g))
    mori_wen = correlation == "mori-wen"
    try:  # the small inputs' checks, as the plain path makes them (it raises for them)
        h = check_range("h", h, 0.0, None, unit="m")
        A0 = check_range("A0", A0, 0.0, None, unit="m2")
        if mori_wen:
            D_t = check_range("D_t", D_t, 0.0, None, lo_open=True, unit="m")
        elif d_p is not None and rho_p is not None and np.any(
                (np.asarray(rho_p, float) - np.asarray(rho_g, float)) * 1e-3 <= 0.0):
            return None  # Darton's powder check raises
    except ValueError:
        return None
    two = False
    if mori_wen:
        A_t = 0.25 * math.pi * D_t * D_t
        if np.any(A0 > A_t):
            return None
        fac = _mori_wen_growth(h, D_t)
        two = bool(np.any(A0 > 0.0))
        a, b = A_t, A0  # _mori_wen_arrays' A_t (U - Umf) and A0 (U - Umf)
    else:
        fac = (h + 4.0 * np.sqrt(A0)) ** 0.8
        a, b = None, None  # bubble_diameter_darton's U - Umf
    P = np.empty(shape)
    Q = np.empty(shape) if two else None

    # U - Umf, times A_t (and A0) for Mori and Wen, to the 0.4: the plain path's numpy
    # operations, on the calling thread (a bad element: the pass below refuses it). In
    # pieces on a pool of Python threads they had been slower, not faster: 4-6 ms per
    # 1e6 points on 2 threads against 3.4 ms in one call, and 7.6 ms on 16 (the pieces
    # compete with the compiled passes' waiting threads)
    with np.errstate(invalid="ignore"):
        p = np.subtract(U, Umf, out=P)
        if Q is not None:
            np.power(np.multiply(b, p, out=Q), 0.4, out=Q)
        if mori_wen:
            np.multiply(a, p, out=p)
        np.power(p, 0.4, out=p)
    ins = _map_inputs((U, Umf, P, 0.0 if Q is None else Q, A0, fac, D_t, eps_mf,
                       wake_fraction), shape)
    if ins is None:
        return None
    theta = np.empty(shape)
    code = np.zeros(shape, dtype=np.int8)  # the pass writes the nonzero codes
    stats = _run(_bubble_pass, *ins, mori_wen, theta.reshape(-1), code.reshape(-1),
                 columns=8)
    n1, n2, n3, n4, n5 = stats[:, :5].sum(axis=0)
    if n4 or n5 or ((n1 or n2 or n3) and not partial):
        return None  # the plain path names the refused input, or raises for the points
    if not n1:
        # the warnings the plain path gives (before it raises for the points with no
        # answer, if any; where U does not exceed Umf it raises first, with none): the
        # powder, Mori and Wen's data, slugging, in its order
        if mori_wen:
            _mori_wen_ranges(D_t, Umf, (float(stats[:, 6].min()), float(stats[:, 7].max())),
                             d_p)
        else:
            _check_group("bubble_diameter_darton", d_p, rho_p, rho_g)
        _check_slugging(None, None, stacklevel=4, worst=float(stats[:, 5].max()))
    if partial:
        return theta, (code if n1 or n2 or n3 else None)
    return theta



@njit(parallel=True, cache=CACHE)
def _collisional_pass(ins, st, shp, plan, out, code, stats):  # pragma: no cover
    """The collisional balance's ``Theta**1.5`` of every element into ``out`` (``ins``: U,
    Umf, ``1 - rho_g / rho_p``, d_p, and the denominator ``12 (1 - e**2) eps_s g0``), the
    operations of :func:`granular_temperature_collisional_balance` in their order, and
    into ``code``: 0, 1 where ``U <= Umf`` (``out`` NaN there), or 5 where ``U`` or
    ``Umf`` is itself refused; ``stats[blk]``: the counts of codes 1 and 5."""
    for blk in prange(stats.shape[0]):  # each block a serial loop: a small
        # parallel body compiles faster
        _collisional_block(ins, st, shp, plan, out, code, stats, blk)


@njit(cache=CACHE, error_model="numpy")
def _collisional_block(ins, st, shp, plan, out, code, stats, blk):  # pragma: no cover
    """Block ``blk`` of :func:`_collisional_pass`."""
    chunk, per_row, per_block = plan
    last = shp.shape[0] - 1
    row_len = shp[last]
    pieces = (out.shape[0] // row_len) * per_row
    s0, s1, s2, s3, s4 = st[0, last], st[1, last], st[2, last], st[3, last], st[4, last]
    x0, x1, x2, x3, x4 = ins
    sqrt_pi = math.sqrt(math.pi)
    off = np.empty(5, np.int64)
    buf = np.empty((5, chunk))
    n1 = 0
    n5 = 0
    for piece in range(blk * per_block, min(pieces, (blk + 1) * per_block)):
        row = piece // per_row
        j0 = (piece - row * per_row) * chunk
        _row_offsets(off, st, shp, row, j0)
        o0, o1, o2, o3, o4 = off[0], off[1], off[2], off[3], off[4]
        k = row * row_len + j0
        m = min(row_len - j0, chunk)
        # without branches (selections), which the compiler vectorizes where the steps
        # are known: a map's usual row, U along it and the rest constant
        if s0 == 1 and s1 == 0 and s2 == 0 and s3 == 0 and s4 == 0:
            Umf, a, d_p, den = x1[o1], x2[o2], x3[o3], x4[o4]
            for j in range(m):
                t, c = _collisional_one(x0[o0 + j], Umf, a, d_p, den, sqrt_pi)
                out[k + j] = t
                n1 += c == 1
                n5 += c == 5
                code[k + j] = c
        else:  # gathered into buffers first (a loop of varying steps stays scalar)
            for j in range(m):
                buf[0, j] = x0[o0 + j * s0]
                buf[1, j] = x1[o1 + j * s1]
                buf[2, j] = x2[o2 + j * s2]
                buf[3, j] = x3[o3 + j * s3]
                buf[4, j] = x4[o4 + j * s4]
            for j in range(m):
                t, c = _collisional_one(buf[0, j], buf[1, j], buf[2, j], buf[3, j],
                                        buf[4, j], sqrt_pi)
                out[k + j] = t
                n1 += c == 1
                n5 += c == 5
                code[k + j] = c
    stats[blk, 0] = n1
    stats[blk, 1] = n5


@njit(cache=CACHE, error_model="numpy")
def _collisional_one(U, Umf, a, d_p, den, sqrt_pi):  # pragma: no cover - compiled
    """:func:`_collisional_pass` of one element (``a`` is ``1 - rho_g / rho_p``, ``den``
    the denominator): ``(Theta**1.5, code)``, NaN and 1 or 5 where refused; the excess is
    :func:`_excess_one`'s (selections, no branch; the denominator is positive)."""
    excess = _excess_one(U, Umf)
    valid = _flows_valid(U, Umf)
    ok = excess > 0.0
    power = excess * a * GRAVITY * d_p * sqrt_pi
    return (power / den if ok else math.nan), (0 if ok else (1 if valid else 5))


def collisional_theta_map(U, Umf, d_p, rho_p, rho_g, eps_mf, e, *, partial=False):
    """:func:`granular_temperature_collisional_balance` on a map's arrays: a compiled
    parallel pass and numpy's power, the same numbers and warnings; None (nothing
    warned) where the plain path would raise or the arrays are not a map's.

    With ``partial``, :func:`.speed_models.speed_law_partial`'s answer: ``(theta, flag)``,
    ``flag`` 1 (NaN ``theta``) where ``U`` does not exceed ``Umf``, or None where every
    element answers (None, the plain path, for any other refusal)."""
    shape = _map_shape(U, Umf, d_p, rho_p, rho_g, eps_mf, e)
    if shape is None:
        return None
    d_p, rho_p, rho_g, eps_mf, e = (_own(v) for v in (d_p, rho_p, rho_g, eps_mf, e))
    try:  # the plain path's checks (it raises for them), in its order
        d_p = check_range("d_p", d_p, 0.0, None, lo_open=True, unit="m")
        rho_p = check_range("rho_p", rho_p, 0.0, None, lo_open=True, unit="kg/m3")
        rho_g = check_range("rho_g", rho_g, 0.0, None, unit="kg/m3")
        e = check_range("e", e, 0.0, 1.0, hi_open=True)
        eps_s = 1.0 - check_range("eps_mf", eps_mf, 0.0, 1.0, lo_open=True, hi_open=True)
    except ValueError:
        return None
    if np.any(rho_p <= rho_g):
        return None
    # the factors that do not vary with U - Umf, on their own (small) broadcasts, as the
    # plain path takes them
    g0 = radial_distribution_carnahan_starling(eps_s)
    ins = _map_inputs((U, Umf, 1.0 - rho_g / rho_p, d_p, 12.0 * (1.0 - e * e) * eps_s * g0),
                      shape)
    if ins is None:
        return None
    out = np.empty(shape)
    code = np.empty(shape, dtype=np.int8)
    n1, n5 = _run(_collisional_pass, *ins, out.reshape(-1), code.reshape(-1),
                  columns=2).sum(axis=0)
    if n5 or (n1 and not partial):
        return None
    if not n1:  # where U does not exceed Umf, the plain path raises before this warning
        _check_group("granular_temperature_collisional_balance", d_p, rho_p, rho_g,
                     allowed=("B", "D"), why="the balance neglects the gas's viscous "
                     "damping of the particles' fluctuations, large for such fine powders")
    np.power(out, 2.0 / 3.0, out=out)  # the plain path's ** (2.0 / 3.0), numpy's pow
    if partial:
        return out, (code if n1 else None)
    return out
