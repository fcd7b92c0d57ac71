"""
Which bed material is safer? Silica sand, ilmenite, olivine
===========================================================

A 300 um silica-sand grain meets a grain of silica sand, ilmenite or olivine of the same
size, all wetted by water at 25 degC in air. One sweep with the partner's material as a
dimension of the map gives the comparison; the picture has one panel per material. The
scene and the grid are ``examples/configs/sand_vs_ilmenite.toml``.

Assumed (the materials database marks them so): ilmenite's and olivine's 1 um asperity
height and restitution 0.85; the impact speeds are the default excess-gas estimate.

The gallery draws the full grid (3 x 35 x 35 points). The same from the command line::

    agglomtool map examples/configs/sand_vs_ilmenite.toml -o sand_vs_ilmenite.nc
    agglomtool plot sand_vs_ilmenite.nc -o sand_vs_ilmenite.png
"""

# %%
# The map and the numbers behind the picture
# ------------------------------------------
# The partner's material ``solid_j`` is a dimension of the map like any number.
from _output import map_from_config, save

from agglomtool.plots import operating_window

ds = map_from_config("sand_vs_ilmenite")
for name in ds.solid_j.values:
    us = ds.u_star.sel(solid_j=name)
    print(f"{name:12s} u0* = {float(us.min()):.3f}-{float(us.max()):.3f} m/s, mean "
          f"propensity {float(ds.propensity.sel(solid_j=name).mean()):.3f}")

# %%
# One panel per material
# ----------------------
# An ilmenite partner sticks least: a denser partner has more inertia to break the liquid
# bridge, so ``u0*`` is lower (the paper's Table 3 finds the same trend).
fig = operating_window(ds, col="solid_j")
save(fig, "sand_vs_ilmenite")
