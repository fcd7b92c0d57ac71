"""Pure-gas viscosity and density from CoolProp, fast over large arrays.

CoolProp's Helmholtz-energy backend (``HEOS``) is the reference; calling it costs about
10-25 us per state. For arrays this module builds, once per species and lazily, a table on a
grid uniform in ``ln T`` and ``ln P`` holding ``ln mu`` and the compressibility factor ``Z``
(both nearly linear in those coordinates for a gas) and interpolates bilinearly. The table
is built from HEOS itself, and every cell is checked against HEOS at its centre, where the
bilinear error of a smooth function peaks: a cell is used only if its four corners are gas
and its centre error is below :data:`CELL_TOL` in both ``mu`` and ``rho``. States in other
cells (close to a saturation line or a critical point) or outside the grid are sent to HEOS
one by one.

A table takes about a second to build, and importing CoolProp takes one or two more, which a
command-line call pays on every start. Each species' table and limits are therefore kept on
disk (:func:`cache_dir`), keyed by the CoolProp version and the table's grid and tolerance;
a state inside a valid cell of a cached table is then answered without importing CoolProp.
Where no directory is writable, tables are built in memory as before.

Species without a CoolProp viscosity model (carbon monoxide) take their dilute-gas viscosity
from ``thermo`` (DIPPR correlation, Perry's 8th ed.), pressure independent.
"""

from __future__ import annotations

import atexit
import hashlib
import math
import os
import tempfile
from dataclasses import dataclass, field
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from ..constants import R_GAS

__all__ = ["SPECIES_FORMULAS", "CondensedPhaseError", "OutOfRangeError", "check_species",
           "species_state", "species_info"]

#: Maximum accepted relative bilinear error at a cell centre (mu and rho) [-].
CELL_TOL = 2e-4

#: Table grid: temperature [K] and pressure [Pa] limits, and node counts.
T_GRID = (200.0, 2000.0, 121)
P_GRID = (1.0e2, 1.0e7, 61)


@cache
def _cp():
    """CoolProp's low-level module, imported on first use (it costs about a second)."""
    import CoolProp.CoolProp as CP

    return CP


def _gas_phases() -> set:
    """Phases CoolProp may report for a state this package accepts as a gas."""
    CP = _cp()
    return {CP.iphase_gas, CP.iphase_supercritical_gas, CP.iphase_supercritical}


class CondensedPhaseError(ValueError):
    """A requested gas state lies in the liquid or two-phase region of a species."""

    def __init__(self, species: str, T: float, P: float, phase: str):
        self.species, self.T, self.P, self.phase = species, T, P, phase
        super().__init__(
            f"{species} at T = {T:g} K, P = {P:g} Pa is {phase}, not a gas "
            "(below its dew point or saturation line)"
        )


class OutOfRangeError(ValueError):
    """A requested state lies outside the validated range of the species' models.

    ``remedy`` is the part of the message that tells a caller of :func:`gas_properties`
    how to go on (callers that do not offer that option leave it out: ``str(exc.problem)``).
    """

    def __init__(self, problem: str, remedy: str = ""):
        self.problem, self.remedy = problem, remedy
        super().__init__(problem + (f"; {remedy}" if remedy else ""))


@dataclass(frozen=True)
class Species:
    """One gas species: its CoolProp name and where its viscosity comes from."""

    formula: str
    coolprop: str
    #: CAS number, for ``thermo`` when CoolProp has no viscosity model.
    cas: str = ""
    #: Source of the viscosity: "coolprop" or a ``thermo.ViscosityGas`` method name.
    viscosity: str = "coolprop"
    #: Upper validity of the viscosity source when it is not CoolProp [K].
    viscosity_tmax: float = math.inf
    #: Limits from CoolProp (molar mass [kg/mol], T [K], p [Pa]); asked for when 0.
    molar_mass: float = field(default=0.0)
    t_min: float = field(default=0.0)
    t_max: float = field(default=0.0)
    p_max: float = field(default=0.0)

    def __post_init__(self) -> None:
        if self.molar_mass > 0.0:
            return
        st = _cp().AbstractState("HEOS", self.coolprop)
        object.__setattr__(self, "molar_mass", st.molar_mass())
        object.__setattr__(self, "t_min", st.Tmin())
        object.__setattr__(self, "t_max", min(st.Tmax(), self.viscosity_tmax))
        object.__setattr__(self, "p_max", st.pmax())


#: The species a composition may name, keyed by formula: the arguments of :class:`Species`
#: (whose records ask CoolProp for limits, so they are built on first use). ``Air`` is Lemmon
#: et al.'s pseudo-pure fluid (doi:10.1063/1.1285884), with the Lemmon-Jacobsen (2004)
#: viscosity.
_SPECIES_ARGS: dict[str, tuple[Any, ...]] = {
    "Air": ("Air",),
    "N2": ("Nitrogen",),
    "O2": ("Oxygen",),
    "CO2": ("CarbonDioxide",),
    "H2O": ("Water",),
    "Ar": ("Argon",),
    "CO": ("CarbonMonoxide", "630-08-0", "DIPPR_PERRY_8E", 1250.0),
    "H2": ("Hydrogen",),
    "CH4": ("Methane",),
}
#: Formulas of the known species.
SPECIES_FORMULAS = tuple(_SPECIES_ARGS)


def check_species(formula: str) -> str:
    """``formula`` if it names a known species, else a ValueError naming the known ones
    (no CoolProp call: the materials loader validates gas entries with it)."""
    if formula not in _SPECIES_ARGS:
        raise ValueError(
            f"unknown gas species {formula!r}; known: {', '.join(sorted(_SPECIES_ARGS))}"
        )
    return formula


@cache
def species_info(formula: str) -> Species:
    """The :class:`Species` record for ``formula``; ValueError naming the known ones."""
    check_species(formula)
    cached = _load_cached(formula)
    if cached is not None:
        return cached[0]
    return Species(formula, *_SPECIES_ARGS[formula])


# ---------------------------------------------------------------------------------------
# The disk cache of tables


def cache_dir() -> Path | None:
    """Where tables are kept: ``$AGGLOMTOOL_CACHE_DIR``, else ``$XDG_CACHE_HOME/agglomtool``
    or ``~/.cache/agglomtool``; ``None`` (no disk cache) if it cannot be created."""
    env = os.environ.get("AGGLOMTOOL_CACHE_DIR")
    if env:
        path = Path(env)
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"),
                                                                 ".cache")
        path = Path(base) / "agglomtool"
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return path if os.access(path, os.W_OK) else None


def _cache_file(formula: str) -> Path | None:
    folder = cache_dir()
    if folder is None:
        return None
    try:
        version = metadata.version("CoolProp")
    except metadata.PackageNotFoundError:  # pragma: no cover - CoolProp is a dependency
        version = "unknown"
    key = repr((formula, _SPECIES_ARGS[formula], version, T_GRID, P_GRID, CELL_TOL, 1))
    digest = hashlib.sha256(key.encode()).hexdigest()[:16]
    return folder / f"gas-table-{formula}-{digest}.npz"


_LIMITS = ("molar_mass", "t_min", "t_max", "p_max")
_TABLE_FIELDS = ("lnT0", "dlnT", "lnP0", "dlnP", "ln_mu", "z", "cell_ok")


@cache
def _load_cached(formula: str):
    """``(Species, _Table)`` from the disk cache, or ``None`` (missing or unreadable)."""
    path = _cache_file(formula)
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path) as data:
            limits: dict[str, Any] = {k: float(data[k]) for k in _LIMITS}
            arrays = {k: data[k] for k in _TABLE_FIELDS}
    except (OSError, ValueError, KeyError):
        return None  # corrupt or from another layout: rebuilt and rewritten
    sp = Species(formula, *_SPECIES_ARGS[formula], **limits)
    fields: dict[str, Any] = {k: (float(v) if v.ndim == 0 else v) for k, v in arrays.items()}
    tab = _Table(**fields)
    return sp, tab


def _save_cached(formula: str, sp: Species, tab: _Table) -> None:
    path = _cache_file(formula)
    if path is None:
        return
    payload = {k: getattr(sp, k) for k in _LIMITS}
    payload.update({k: getattr(tab, k) for k in _TABLE_FIELDS})
    try:  # atomic: a reader sees the whole file or none
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".npz.tmp")
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **payload)
        os.replace(tmp, path)
    except OSError:
        return


@cache
def _thermo_viscosity(cas: str, method: str):
    from thermo import ViscosityGas

    model = ViscosityGas(CASRN=cas)
    return lambda T: model.calculate(float(T), method)


@cache
def _state(coolprop: str):
    return _cp().AbstractState("HEOS", coolprop)


# CoolProp's states are released before the interpreter tears its modules down: a state
# still held then makes CoolProp's binding layer print a "leaked instances" report on exit
atexit.register(_state.cache_clear)


def _phase_name(index: int) -> str:
    CP = _cp()
    return {
        CP.iphase_liquid: "liquid",
        CP.iphase_twophase: "two-phase",
        CP.iphase_supercritical_liquid: "a compressed liquid (above the critical pressure)",
    }.get(index, f"in CoolProp phase {index}")


def heos_point(sp: Species, T: float, P: float) -> tuple[float, float]:
    """Viscosity [Pa s] and density [kg/m3] of one gas state from CoolProp HEOS.

    Raises :class:`CondensedPhaseError` when the state is not a gas.
    """
    st = _state(sp.coolprop)
    try:
        st.update(_cp().PT_INPUTS, float(P), float(T))
    except ValueError as exc:
        raise OutOfRangeError(
            f"CoolProp HEOS cannot evaluate {sp.formula} at T = {T:g} K, P = {P:g} Pa: {exc}"
        ) from exc
    phase = st.phase()
    if phase not in _gas_phases():
        raise CondensedPhaseError(sp.formula, float(T), float(P), _phase_name(phase))
    rho = st.rhomass()
    if sp.viscosity == "coolprop":
        mu = st.viscosity()
    else:
        mu = _thermo_viscosity(sp.cas, sp.viscosity)(T)
    return mu, rho


@dataclass(frozen=True)
class _Table:
    lnT0: float
    dlnT: float
    lnP0: float
    dlnP: float
    ln_mu: np.ndarray  # (nT, nP)
    z: np.ndarray  # (nT, nP)
    cell_ok: np.ndarray  # (nT - 1, nP - 1)


def _grid_values(sp: Species, T: np.ndarray, P: np.ndarray):
    """HEOS ln(mu), Z and a gas flag on the outer product of T and P."""
    ln_mu = np.full((T.size, P.size), np.nan)
    z = np.full_like(ln_mu, np.nan)
    for i, t in enumerate(T):
        for j, p in enumerate(P):
            try:
                mu, rho = heos_point(sp, t, p)
            except ValueError:
                continue
            ln_mu[i, j] = math.log(mu)
            z[i, j] = p * sp.molar_mass / (rho * R_GAS * t)
    return ln_mu, z


@cache
def _table(formula: str) -> _Table:
    cached = _load_cached(formula)
    if cached is not None:
        return cached[1]
    sp = species_info(formula)
    tab = _build_table(sp)
    _save_cached(formula, sp, tab)
    return tab


def _build_table(sp: Species) -> _Table:
    t_lo = max(T_GRID[0], sp.t_min)
    lnT = np.linspace(math.log(t_lo), math.log(T_GRID[1]), T_GRID[2])
    lnP = np.linspace(math.log(P_GRID[0]), math.log(P_GRID[1]), P_GRID[2])
    T, P = np.exp(lnT), np.exp(lnP)
    ln_mu, z = _grid_values(sp, T, P)
    # Check every cell at its centre against HEOS.
    Tc, Pc = np.exp(0.5 * (lnT[1:] + lnT[:-1])), np.exp(0.5 * (lnP[1:] + lnP[:-1]))
    ln_mu_c, z_c = _grid_values(sp, Tc, Pc)
    corners_mu = 0.25 * (ln_mu[:-1, :-1] + ln_mu[1:, :-1] + ln_mu[:-1, 1:] + ln_mu[1:, 1:])
    corners_z = 0.25 * (z[:-1, :-1] + z[1:, :-1] + z[:-1, 1:] + z[1:, 1:])
    with np.errstate(invalid="ignore"):
        err_mu = np.abs(np.expm1(corners_mu - ln_mu_c))
        err_rho = np.abs(z_c / corners_z - 1.0)
        ok = (err_mu < CELL_TOL) & (err_rho < CELL_TOL)
    ok &= np.isfinite(corners_mu) & np.isfinite(corners_z)
    ok &= np.isfinite(ln_mu_c) & np.isfinite(z_c)
    return _Table(lnT[0], lnT[1] - lnT[0], lnP[0], lnP[1] - lnP[0], ln_mu, z, ok)


def _check_range(sp: Species, T: np.ndarray, P: np.ndarray, beyond_range: str) -> None:
    low = T < sp.t_min
    if low.any():
        raise OutOfRangeError(
            f"T = {T[low].flat[0]:g} K is below the lower limit {sp.t_min:g} K of the "
            f"CoolProp equation of state for {sp.formula}"
        )
    if (P > sp.p_max).any():
        raise OutOfRangeError(
            f"P = {P[P > sp.p_max].flat[0]:g} Pa is above the upper limit {sp.p_max:g} Pa "
            f"of the CoolProp equation of state for {sp.formula}"
        )
    high = T > sp.t_max
    if high.any() and beyond_range != "extrapolate":
        raise OutOfRangeError(
            f"T = {T[high].flat[0]:g} K is above {sp.t_max:g} K, the upper limit of the "
            f"validated models for {sp.formula} (CoolProp equation of state"
            + ("" if sp.viscosity == "coolprop" else f", {sp.viscosity} viscosity") + ")",
            "pass beyond_range='extrapolate' to extrapolate them (documented fallback)",
        )
    if (T > T_GRID[1]).any():
        raise OutOfRangeError(
            f"T = {T[T > T_GRID[1]].flat[0]:g} K is above {T_GRID[1]:g} K, beyond which no "
            f"gas model is provided for {sp.formula}"
        )


def species_state(
    formula: str,
    T: np.ndarray,
    P: np.ndarray,
    *,
    method: str = "table",
    beyond_range: str = "raise",
) -> tuple[np.ndarray, np.ndarray]:
    """Viscosity [Pa s] and density [kg/m3] of a pure gas species at ``T`` [K], ``P`` [Pa].

    ``T`` and ``P`` are 1-d float arrays of one length. ``method="table"`` interpolates the
    checked table where it is valid and falls back to HEOS elsewhere; ``method="heos"``
    evaluates HEOS for every state. Raises :class:`CondensedPhaseError` for non-gas states
    and :class:`OutOfRangeError` outside the validated range.
    """
    sp = species_info(formula)
    _check_range(sp, T, P, beyond_range)
    mu = np.empty(T.shape)
    rho = np.empty(T.shape)
    if method == "table":
        tab = _table(formula)
        fi = (np.log(T) - tab.lnT0) / tab.dlnT
        fj = (np.log(P) - tab.lnP0) / tab.dlnP
        n_i, n_j = tab.cell_ok.shape
        inside = (fi >= 0.0) & (fi <= n_i) & (fj >= 0.0) & (fj <= n_j)
        i = np.clip(np.floor(fi).astype(np.intp), 0, n_i - 1)
        j = np.clip(np.floor(fj).astype(np.intp), 0, n_j - 1)
        fast = inside & tab.cell_ok[i, j]
        i, j, u, v = i[fast], j[fast], fi[fast] - i[fast], fj[fast] - j[fast]

        def bilinear(a):
            return (1.0 - u) * ((1.0 - v) * a[i, j] + v * a[i, j + 1]) + u * (
                (1.0 - v) * a[i + 1, j] + v * a[i + 1, j + 1]
            )

        mu[fast] = np.exp(bilinear(tab.ln_mu))
        rho[fast] = P[fast] * sp.molar_mass / (R_GAS * T[fast] * bilinear(tab.z))
        slow = ~fast
    elif method == "heos":
        slow = np.ones(T.shape, dtype=bool)
    else:
        raise ValueError(f"method = {method!r} is not one of 'table', 'heos'")
    for k in np.flatnonzero(slow):
        mu[k], rho[k] = heos_point(sp, T[k], P[k])
    return mu, rho
