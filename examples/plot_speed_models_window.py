"""
How far the window moves with the impact-speed model
====================================================

The README's granulator (glass beads of 400 um wetted by water in air at 50 degC) under
each impact-speed model valid at the scene, side by side: the probability that a
collision sticks (colour) over the water layer's thickness ``h0`` and the fluidization
number ``U/U_mf``, with contours of the critical impact speed ``u0*``.

``u0*`` is a property of the pair and the liquid alone: its contours are the same in every
panel. What moves is the propensity, the share of the bed's impacts slower than ``u0*``:
the default ``excess-gas`` estimate (r.m.s. velocity ``U - U_mf``), the circulation
driven by bubble wakes (bubbles of Darton et al. 1977 or of Mori and Wen 1975 in a 0.3 m
column with 0.3 m of static bed, collisions at mid-height) and the collisional energy
balance of the kinetic theory of granular flow. The bubble models step where Kunii and
Levenspiel's bubble fraction changes regime; the collisional balance grows only as the
cube root of ``U - U_mf``, so its safe region grows slowest with gas velocity.
See :doc:`/speed_models` for the models and why the default is kept.

The same picture from Python::

    from agglomtool.plots import speed_model_windows
    speed_model_windows(scene, h0=[...], U_Umf=[...], path="speed_models_window.png")
"""

# %%
# The scene and the grid
# ----------------------
# ``speed_model_windows`` sweeps the scene over the grid and over the models that
# :func:`agglomtool.impact_speed_methods` finds valid at it, and draws one column per
# model with :func:`agglomtool.plots.operating_window`.
import numpy as np
from _output import points, save

import agglomtool as at
from agglomtool.plots import speed_model_windows

scene = at.Scene(liquid="water", T="50 degC", solid_i="glass-beads", d_i="400 um",
                 bed_height=0.3, column_diameter=0.3)
print("models valid here:", at.impact_speed_methods(scene))
n = points(30)
fig = speed_model_windows(scene, h0=np.geomspace(0.6e-6, 20e-6, n),
                          U_Umf=np.linspace(1.2, 4.0, n))

# %%
# How much of the grid each model calls safe
# -------------------------------------------
# The share of grid points where fewer than one collision in ten sticks.
ds = fig.data
safe = (ds.propensity < 0.1).mean(["h0", "U_Umf"])
for name, share in zip(ds.speed.values, safe.values, strict=True):
    print(f"{name:>20}: {100 * float(share):.0f} % of the grid")
save(fig, "speed_models_window")
