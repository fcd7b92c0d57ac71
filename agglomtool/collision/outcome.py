"""Codes that say where and how a collision's outcome was decided.

The kernels write small integers; :class:`Stage` and :class:`Path` name them.
"""

from __future__ import annotations

import enum

import numpy as np

__all__ = ["Stage", "Path", "DETAIL_NAMES", "STAGE_DESCRIPTIONS", "NO_BRIDGE_DESCRIPTION",
           "stage_names", "path_names"]


class Stage(enum.IntEnum):
    """Where the outcome was decided (the flow chart of the paper's Fig. 3, docs/model.md);
    :data:`STAGE_DESCRIPTIONS` says what each means."""

    REBOUND = 0
    APPROACH_VISCOUS = 1
    APPROACH_ENERGY = 2
    APPROACH_ALONE = 3
    APPROACH_ALONE_VISCOUS = 4
    CONTACT = 5
    SEPARATION_VISCOUS = 6
    SEPARATION_ENERGY = 7
    SEPARATION_ALONE = 8
    SEPARATION_ALONE_VISCOUS = 9


#: One sentence per :class:`Stage`.
STAGE_DESCRIPTIONS = {
    Stage.REBOUND: "The bridge ruptured with energy left: the pair rebounds (Eq. 31 gives e_w).",
    Stage.APPROACH_VISCOUS: (
        "Approach: the viscous force alone stops the pair before "
        "contact (Eqs. 73, 80)."
    ),
    Stage.APPROACH_ENERGY: (
        "Approach: both particles' energies are spent before contact "
        "(Eqs. 36a, 37a)."
    ),
    Stage.APPROACH_ALONE: (
        "Approach: one particle stopped; the other, going on alone, "
        "runs out (Eq. 39)."
    ),
    Stage.APPROACH_ALONE_VISCOUS: (
        "Approach: one particle stopped; viscosity alone stops the "
        "other (Eq. 144)."
    ),
    Stage.CONTACT: "Solid contact leaves no separation speed (e = 0).",
    Stage.SEPARATION_VISCOUS: (
        "Separation: the viscous force alone stops the pair before "
        "rupture (Eqs. 75, 82)."
    ),
    Stage.SEPARATION_ENERGY: (
        "Separation: both particles' energies are spent before "
        "rupture (Eqs. 58a, 59a)."
    ),
    Stage.SEPARATION_ALONE: (
        "Separation: one particle stopped; the other, going on "
        "alone, runs out (Eqs. 61-62)."
    ),
    Stage.SEPARATION_ALONE_VISCOUS: (
        "Separation: one particle stopped; viscosity alone stops the "
        "other."
    ),
}


#: What a collision flagged :attr:`Path.NO_BRIDGE` went through, whatever its stage code
#: (``REBOUND`` with ``e_w = e``, or ``CONTACT`` when ``e = 0``): no bridge formed to rupture.
NO_BRIDGE_DESCRIPTION = ("The coatings are no thicker than the asperities (H0 <= Ha): no "
                         "liquid bridge forms.")


class Path(enum.IntFlag):
    """Special-case paths taken (bit flags; 0 = the ordinary path)."""

    APPROACH_I_STOPS = 1
    """Particle i stopped first during the approach; j went on alone (Section 2.3.5)."""
    APPROACH_J_STOPS = 2
    """Particle j stopped first during the approach; i went on alone."""
    SEPARATION_I_STOPS = 4
    """Particle i stopped first during the separation; j went on alone (Suppl. S-11)."""
    SEPARATION_J_STOPS = 8
    """Particle j stopped first during the separation; i went on alone (Suppl. S-12)."""
    NO_BRIDGE = 16
    """Coatings no thicker than the asperities (H0 <= Ha): no bridge, a dry collision."""
    BRIDGE_BROKEN_AT_CONTACT = 32
    """The rupture distance is not above the contact gap: no separation losses."""


#: Names of the per-collision details the kernels can write, in column order.
#: Energies [J] are in the paper's centre-of-mass frames; losses [J] are positive when
#: energy is lost; gaps [m]. NaN marks a quantity of a stage the collision never reached.
DETAIL_NAMES = (
    "K_ini_i", "K_ini_j",          # Eqs. 34-35
    "L_cap_app", "L_vis_app",      # totals over the approach (Eqs. 88, 100)
    "L_bdw_app_i", "L_bdw_app_j",  # Eqs. 126-127
    "K_app_i", "K_app_j",          # Eqs. 36-37
    "D_stop_app",                  # D_app of the particle that stopped first (Eq. 136)
    "w_contact",                   # relative speed at contact [m/s]
    "L_c",                         # contact loss, both particles (Eqs. 132-134)
    "K_sep_i", "K_sep_j",          # Eqs. 54-55
    "Ca", "h_rupt",                # Eqs. 57, 94
    "L_cap_sep", "L_vis_sep",      # totals over the separation (Eqs. 95, 101)
    "L_bdw_sep_i", "L_bdw_sep_j",  # Eqs. 128-129
    "D_stop_sep",                  # D_sep of the particle that stopped first
    "K_fin_i", "K_fin_j",          # Eqs. 58-59
    "St_app",                      # viscous Stokes number of the approach, m v0 / c
    # Modes other than "paper": work bounds of optional terms over the initial relative
    # kinetic energy [-] (agglomtool.collision.stages.term_work_fractions); a term is
    # negligible below relative.NEGLIGIBLE_FRACTION. Taken at the impact speed over the whole
    # gap, a bound can exceed 1 (by ~1/St_app where viscosity stops the pair first): it then
    # says only "not negligible" (CollisionResult.explain prints it so).
    "W_body_frac", "W_volcorr_frac",
)  # fmt: skip


def stage_names(codes) -> np.ndarray:
    """Names (strings) for an array of :class:`Stage` codes."""
    names = np.array([s.name.lower() for s in Stage])
    return names[np.asarray(codes, dtype=np.intp)]


def path_names(flags: int) -> list[str]:
    """Names of the :class:`Path` flags set in one integer."""
    return [str(p.name).lower() for p in Path if int(flags) & p.value]
