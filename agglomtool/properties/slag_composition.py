"""Oxide compositions of slags and ash melts: names, molar masses, wt % to mole fractions."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from functools import cache
from typing import Any

import numpy as np
from chemicals.elements import molecular_weight, simple_formula_parser

from .._validate import check_range

__all__ = ["OXIDES", "oxide_info", "molar_mass", "mole_fractions", "normalise_wt",
           "is_array_composition"]

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


class NormalisedWt(dict):
    """A composition :func:`normalise_wt` has checked and scaled to 100 wt %: normalising
    it again returns a copy as it is (the models of a melt each normalise what they are
    given; a melt's properties normalise once and pass this on)."""


def normalise_wt(composition: Mapping[str, float], *, tol: float = 2.0) -> dict:
    """Validate a composition in wt % and scale it to sum to exactly 100.

    A sum further than ``tol`` from 100 is an error (a composition in fractions rather
    than percent, or a missing major oxide); a smaller deviation warns and is rescaled.

    Each oxide's value may be an array (one composition per element, as a Monte Carlo over
    an assumed composition draws them): the arrays broadcast against each other, every
    element is checked and rescaled on its own, and the result holds float arrays of the
    broadcast shape. With scalar values the result holds floats, and an oxide at 0 wt %
    is dropped.
    """
    if isinstance(composition, NormalisedWt):
        return NormalisedWt(composition)  # a copy: models may edit theirs (Fe2O3 -> FeO)
    if not isinstance(composition, Mapping) or not composition:
        raise ValueError(f"composition must be a non-empty dict of oxide -> wt %, got "
                         f"{composition!r}")
    wt = {}
    for oxide, value in composition.items():
        oxide_info(oxide)
        wt[oxide] = check_range(f"composition[{oxide!r}]", value, 0.0, 100.0, unit="wt %")
    if all(v.ndim == 0 for v in wt.values()):
        scalar = {k: float(v) for k, v in wt.items()}
        total = sum(scalar.values())
        if abs(total - 100.0) > tol:
            raise ValueError(f"composition sums to {total:g} wt %; expected 100 +- {tol:g}")
        if abs(total - 100.0) > 1e-6:
            warnings.warn(f"composition sums to {total:g} wt %; rescaled to 100", stacklevel=3)
        return NormalisedWt({k: 100.0 * v / total for k, v in scalar.items() if v > 0.0})
    try:
        shape = np.broadcast_shapes(*(v.shape for v in wt.values()))
    except ValueError:
        raise ValueError("composition: the oxides' arrays do not broadcast together "
                         f"(shapes {[v.shape for v in wt.values()]})") from None
    total_a: np.ndarray = sum(wt.values(), np.zeros(()))
    far = np.abs(total_a - 100.0) > tol
    if far.any():
        bad = np.broadcast_to(total_a, shape)[np.broadcast_to(far, shape)]
        raise ValueError(f"composition sums to {bad.flat[0]:g} wt % in {bad.size} of "
                         f"{int(np.prod(shape))} elements; expected 100 +- {tol:g}")
    if (np.abs(total_a - 100.0) > 1e-6).any():
        warnings.warn("composition sums to "
                      f"{float(np.min(total_a)):g}-{float(np.max(total_a)):g} wt %; rescaled "
                      "to 100", stacklevel=3)
    return NormalisedWt({k: np.broadcast_to(100.0 * v / total_a, shape) for k, v in wt.items()})


def is_array_composition(wt: Mapping) -> bool:
    """Whether a composition holds arrays (one composition per element) rather than floats."""
    return any(np.ndim(v) > 0 for v in wt.values())


def mole_fractions(wt: Mapping[str, float]) -> dict:
    """Mole fractions [-] of the oxides of a composition given in wt % (any total).

    Floats give floats (oxides at 0 left out); arrays give arrays, element by element.
    """
    moles: dict[str, Any]
    if is_array_composition(wt):
        moles = {k: np.asarray(v, dtype=float) / molar_mass(k) for k, v in wt.items()}
    else:
        moles = {k: v / molar_mass(k) for k, v in wt.items() if v > 0.0}
    total = sum(moles.values())
    return {k: v / total for k, v in moles.items()}
