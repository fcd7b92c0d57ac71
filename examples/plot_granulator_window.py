"""
The operating window of a fluidized-bed granulator
==================================================

Glass beads wetted by water in air at 50 degC: the probability that a collision sticks
(colour) over the water layer's thickness ``h0`` and the fluidization number ``U/U_mf``,
for beads of 200, 400 and 800 um, with contours of the critical impact speed ``u0*``.
This is the README's main example; the scene and the grid are
``examples/configs/granulator_window.toml``.

Small beads carrying a few microns of water stick unless the bed is fluidized hard; large
beads are safe almost everywhere. Assumed: the impact speeds are the default excess-gas
estimate (Maxwellian, r.m.s. velocity per component ``U - U_mf``), an order of magnitude;
glass's 0.5 um asperity height; head-on collisions.

The gallery draws the full grid (3 x 35 x 35 points). The same picture from the command
line::

    agglomtool map examples/configs/granulator_window.toml -o granulator_window.nc
    agglomtool plot granulator_window.nc -o granulator_window.png
"""

# %%
# The map
# -------
# ``map_from_config`` (in ``examples/_output.py``) reads the TOML file, runs
# :func:`agglomtool.sweep` over its grid and writes the map as netCDF. The result is an
# :class:`xarray.Dataset` with units on every variable.
from _output import map_from_config, save

from agglomtool.plots import operating_window

ds = map_from_config("granulator_window")
print(ds.propensity.attrs["long_name"], f"[{ds.propensity.attrs['units']}]")

# %%
# The picture
# -----------
# :func:`agglomtool.plots.operating_window` puts every dimension of the map somewhere: here
# ``h0`` on x, ``U_Umf`` on y, the bead size in facet columns.
fig = operating_window(ds)
save(fig, "granulator_window")
