"""
The operating window of a biomass-fired bubbling bed
====================================================

Silica sand (500 um) coated by a potassium-silicate ash melt in biomass flue gas:
temperature against coating thickness at ``U/U_mf`` = 2, 4 and 8, coloured by the
agglomeration propensity, with ``u0*`` contours. The scene and the grid are
``examples/configs/biomass_window.toml``.

The database's melt is so viscous (Giordano-Russell-Dingwell: 4e2-4e7 Pa s at these
temperatures) that any coating thicker than the 0.1 um asperities sticks at every speed up
to the ``u0*`` ceiling (10 m/s): the picture hatches that region; the safe window is only
where no bridge forms.

The gallery draws the full grid (41 x 41 x 3 points). The same picture from the command
line::

    agglomtool map examples/configs/biomass_window.toml -o biomass_window.nc
    agglomtool plot biomass_window.nc -o biomass_window.png
"""

# %%
from _output import map_from_config, save

from agglomtool.plots import operating_window

ds = map_from_config("biomass_window")
fig = operating_window(ds)
save(fig, "biomass_window")
