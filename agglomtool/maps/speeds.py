"""Compatibility name: the impact-speed distributions live in :mod:`agglomtool.bed.speeds`."""

from ..bed.speeds import SPEED_FAMILIES, SpeedModel, sticking_probability

__all__ = ["SPEED_FAMILIES", "SpeedModel", "sticking_probability"]
