"""Physical constants used across the package, in SI units.

The bottom of the import graph: this module imports nothing, so the collision core and the
property layer can both take their constants from it without importing each other.
"""

from __future__ import annotations

__all__ = ["GRAVITY", "R_GAS"]

#: Standard gravity [m/s2] (CGPM 1901, exact).
GRAVITY = 9.80665

#: Molar gas constant [J/(mol K)], as used by CoolProp 8 (the gas tables' compressibility
#: is defined with it, so it must stay the value CoolProp uses).
R_GAS = 8.314462618
