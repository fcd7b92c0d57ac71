"""Compatibility name: how kernels are compiled and launched lives in :mod:`agglomtool._jit`
(below the collision core, so that the properties and the Monte Carlo summary use it
without importing the core)."""

from .._jit import CACHE, cache_status, parallel_launch

__all__ = ["CACHE", "parallel_launch", "cache_status"]
