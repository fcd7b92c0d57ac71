"""The registry of model tiers reachable through ``mode=``.

Each tier is a function of one :class:`~.records.TierInputs` (the flat, equal-length
float64 arrays ``m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e``) and the
keyword flag ``details=bool`` (and ``tol=`` for the tiers in :data:`TAKES_TOL`), returning
``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
A new tier registers itself here; the public API dispatches on the name.
"""

from __future__ import annotations

from collections.abc import Callable

from .auto import run_auto
from .ode import run_ode, run_ode_self_consistent
from .paper import run_paper
from .records import tier_inputs
from .relative import run_relative
from .stokes import run_stokes

__all__ = ["TIERS", "TAKES_TOL", "evaluate", "mode_names"]

#: name -> tier function
TIERS: dict[str, Callable] = {
    "stokes": run_stokes,
    "paper": run_paper,
    "relative": run_relative,
    "ode": run_ode,
    "ode_selfconsistent": run_ode_self_consistent,
    "auto": run_auto,
}

#: Tiers that take a tolerance ``tol`` in ``e_w`` (passed through ``collide(..., tol=)``).
TAKES_TOL = frozenset({"auto"})


def mode_names() -> tuple[str, ...]:
    """The names accepted by ``mode=``."""
    return tuple(TIERS)


def evaluate(mode: str, *arrays, details: bool = False, tol: float | None = None):
    """Run tier ``mode`` on flat arrays; see the module docstring.

    ``tol``: the tolerance in ``e_w`` of the tiers in :data:`TAKES_TOL` (None: their
    default); other tiers refuse it.
    """
    try:
        tier = TIERS[mode]
    except KeyError:
        raise ValueError(f"mode = {mode!r} is not one of {mode_names()}") from None
    ins = tier_inputs(arrays)
    if tol is None:
        return tier(ins, details=details)
    if mode not in TAKES_TOL:
        raise ValueError(
            f"tol = {tol!r} was given but mode = {mode!r} takes no tolerance; "
            f"only {sorted(TAKES_TOL)} do"
        )
    return tier(ins, details=details, tol=tol)
