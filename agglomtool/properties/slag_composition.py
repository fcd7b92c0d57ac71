"""Oxide compositions of slags and ash melts: names, molar masses, wt % to mole fractions."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from functools import cache

from chemicals.elements import molecular_weight, simple_formula_parser

from .._validate import check_range

__all__ = ["OXIDES", "oxide_info", "molar_mass", "mole_fractions", "normalise_wt"]

#: The components a melt composition may name.
OXIDES = (
    "SiO2", "TiO2", "Al2O3", "Fe2O3", "FeO", "MnO", "MgO", "CaO", "Na2O", "K2O",
    "P2O5", "H2O", "CaF2", "B2O3", "ZrO2", "Li2O", "BaO", "SrO",
)  # fmt: skip


def oxide_info(name: str) -> str:
    """Return ``name`` if it is a known oxide; ValueError naming the known ones otherwise."""
    if name not in OXIDES:
        raise ValueError(f"unknown oxide {name!r}; known: {', '.join(OXIDES)}")
    return name


@cache
def molar_mass(oxide: str) -> float:
    """Molar mass [kg/mol] of an oxide, from IUPAC atomic weights via ``chemicals``."""
    return molecular_weight(simple_formula_parser(oxide_info(oxide))) / 1000.0


def normalise_wt(composition: Mapping[str, float], *, tol: float = 2.0) -> dict[str, float]:
    """Validate a composition in wt % and scale it to sum to exactly 100.

    A sum further than ``tol`` from 100 is an error (a composition in fractions rather
    than percent, or a missing major oxide); a smaller deviation warns and is rescaled.
    """
    if not isinstance(composition, Mapping) or not composition:
        raise ValueError(f"composition must be a non-empty dict of oxide -> wt %, got "
                         f"{composition!r}")
    wt = {}
    for oxide, value in composition.items():
        oxide_info(oxide)
        wt[oxide] = float(check_range(f"composition[{oxide!r}]", value, 0.0, 100.0, unit="wt %"))
    total = sum(wt.values())
    if abs(total - 100.0) > tol:
        raise ValueError(f"composition sums to {total:g} wt %; expected 100 +- {tol:g}")
    if abs(total - 100.0) > 1e-6:
        warnings.warn(f"composition sums to {total:g} wt %; rescaled to 100", stacklevel=3)
    return {k: 100.0 * v / total for k, v in wt.items() if v > 0.0}


def mole_fractions(wt: Mapping[str, float]) -> dict[str, float]:
    """Mole fractions [-] of the oxides of a composition given in wt % (any total)."""
    moles = {k: v / molar_mass(k) for k, v in wt.items() if v > 0.0}
    total = sum(moles.values())
    return {k: v / total for k, v in moles.items()}
