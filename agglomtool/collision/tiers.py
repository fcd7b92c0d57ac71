"""The registry of model tiers reachable through ``mode=``.

Each tier is a function of flat, equal-length float64 arrays
``(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, w, fn_i, fn_j, e, details=bool)``
returning ``(e_w, stage, path, det)`` like :func:`agglomtool.collision.paper.run_paper`.
A new tier registers itself here; the public API dispatches on the name.
"""

from __future__ import annotations

from collections.abc import Callable

from .paper import run_paper

__all__ = ["TIERS", "evaluate", "mode_names"]

#: name -> tier function
TIERS: dict[str, Callable] = {
    "paper": run_paper,
}


def mode_names() -> tuple[str, ...]:
    """The names accepted by ``mode=``."""
    return tuple(TIERS)


def evaluate(mode: str, *arrays, details: bool = False):
    """Run tier ``mode`` on flat arrays; see the module docstring."""
    try:
        tier = TIERS[mode]
    except KeyError:
        raise ValueError(f"mode = {mode!r} is not one of {mode_names()}") from None
    return tier(*arrays, details=details)
