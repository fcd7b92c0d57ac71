"""Uncertainty propagation and global sensitivity of the wet restitution coefficient.

- :func:`monte_carlo`: draw uncertain inputs (:class:`Normal`, :class:`LogNormal`,
  :class:`Uniform`, truncated to each input's physical range by resampling), evaluate
  ``e_w`` with any model tier, and return an ``xarray.Dataset`` of samples and summary.
- :func:`sobol_indices`: first-order and total Sobol indices with SALib (optional
  dependency); :func:`spread_by_input`: one-at-a-time spreads.
- :func:`compare`: options of one Scene field under paired draws, with the probability
  that one sticks less than another and the input that decides it.
- :func:`table4_case`: the paper's Table 4 analyses as ready inputs.

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Section 3.4.
"""

from ._inputs import UNCERTAIN_INPUTS
from .compare import compare
from .distributions import Distribution, LogNormal, Normal, Uniform
from .monte_carlo import DEFAULT_QUANTILES, e_w_density, monte_carlo
from .sensitivity import sobol_indices, spread_by_input
from .table4 import TABLE4, TABLE4_GROUPS, TABLE4_U0, table4_case

__all__ = [
    "DEFAULT_QUANTILES",
    "Distribution",
    "LogNormal",
    "Normal",
    "TABLE4",
    "TABLE4_GROUPS",
    "TABLE4_U0",
    "UNCERTAIN_INPUTS",
    "compare",
    "Uniform",
    "e_w_density",
    "monte_carlo",
    "sobol_indices",
    "spread_by_input",
    "table4_case",
]
