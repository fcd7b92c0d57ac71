"""The collision core: pure functions of SI numbers and arrays, no I/O, no property lookups.

- :mod:`.physics`: the pair physics written once (wet mass, Wen-Yu ``U_mf``, Gidaspow's
  drag), compiled scalar functions that the kernels and the numpy side both call;
- :mod:`.bridge`: liquid-bridge geometry (Eqs. 3, 28-30, 76, 94);
- :mod:`.paper`: the paper's flow chart (mode "paper");
- :mod:`.critical`: the critical-impact-speed search;
- :mod:`.outcome`: stage and path codes.
"""

from .outcome import DETAIL_NAMES, Path, Stage

__all__ = ["DETAIL_NAMES", "Path", "Stage"]
