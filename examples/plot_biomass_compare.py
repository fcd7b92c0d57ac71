"""
Is ilmenite safer than silica sand in a biomass combustor? Decided, or not?
===========================================================================

A biomass-fired bubbling bed at 875 degC: bed grains of 300 um coated by 0.5 um of a
potassium-silicate ash melt, in flue gas at ``U/U_mf`` = 3. The bed could be silica sand,
ilmenite or olivine. At the database's values the answer looks clear: sand sticks far more.
But those values are not all measured: the database marks the asperity heights of the three
solids, the restitution of the two ores and the melt's contact angle as *assumptions*, and
states for each a plausible law and why (``materials/*.toml``, the ``uncertainty`` tables).

:func:`agglomtool.compare` draws every assumed value from its law, the same draws for every
option that shares it (paired), evaluates each option's propensity on every draw as a map
does, and says, for each pair, in how many of the plausible worlds one sticks less than the
other, and which uncertain input decides the difference.
"""

# %%
# The comparison
# --------------
import warnings

import matplotlib.pyplot as plt
import numpy as np
from _output import samples, save

import agglomtool as at

warnings.simplefilter("ignore", at.PlausibilityWarning)
scene = at.Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T="875 degC",
                 solid_i="silica-sand", d_i="300 um", h0="0.5 um", U_Umf=3.0)
options = ["silica-sand", "ilmenite", "olivine"]
n = samples(4096)
ds = at.compare(scene, solid_j=options, n=n, seed=0)

nominal = at.sweep(scene, solid_j=options)
for name in options:
    print(f"{name:12s} propensity at the database's values "
          f"{float(nominal.propensity.sel(solid_j=name)):.3f}; over the plausible inputs: "
          f"mean {float(ds.propensity_mean.sel(option=name)):.3f}, 5-95 % "
          f"{float(ds.propensity_quantile.sel(option=name, quantile=0.05)):.3f}-"
          f"{float(ds.propensity_quantile.sel(option=name, quantile=0.95)):.3f}")
print()
print(ds.attrs["verdicts"])

# %%
# What decides it
# ---------------
# The melt is so viscous that on each draw a collision either sticks at every bed speed or
# no bridge forms at all: the left panel says how often each happens. The right one bins
# the same draws by the asperity height drawn for the sand grain that every option meets:
# a sand grain much rougher than the 0.5 um coating forms no bridge, whatever its partner,
# and a smooth one sticks to a smooth partner; in between, the partner's own (assumed)
# roughness decides.
runs = {name: at.monte_carlo(scene.replace(solid_j=name), uncertain="assumed", n=n, seed=0)
        for name in options}
fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
# the melt is so viscous that a collision either sticks at every bed speed or no bridge
# forms: the propensity of a draw is (nearly) 0 or 1, so say how often each happens
shares = {}
for name in options:
    p = runs[name].propensity.values
    shares[name] = (np.mean(p < 0.01), np.mean((p >= 0.01) & (p <= 0.99)), np.mean(p > 0.99))
labels = ("never sticks (< 0.01)", "sometimes", "always sticks (> 0.99)")
colours = ("#4c9f70", "#e0c341", "#c8553d")
left = np.zeros(len(options))
for k, (label, colour) in enumerate(zip(labels, colours, strict=True)):
    width = np.array([shares[name][k] for name in options])
    if not width.any():
        continue  # no legend entry for what the draws never gave
    ax0.barh(range(len(options)), width, left=left, color=colour, label=label)
    left += width
for k, name in enumerate(options):
    ax0.text(1.01, k, f"database values: {float(nominal.propensity.sel(solid_j=name)):.2f}",
             va="center", fontsize=8)
ax0.set_yticks(range(len(options)), [f"sand + {name}" for name in options])
ax0.set_xlim(0, 1)
ax0.set_xlabel("share of the plausible inputs [-]")
ax0.set_title("propensity over the plausible inputs", fontsize=10)
ax0.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=3)
ha_sand = runs["silica-sand"]["solid_silica-sand_asperity_height"].values * 1e6
edges = np.geomspace(np.percentile(ha_sand, 1), np.percentile(ha_sand, 99), 13)
centres = np.sqrt(edges[:-1] * edges[1:])
which = np.digitize(ha_sand, edges) - 1
for k, name in enumerate(options):
    p = runs[name].propensity.values
    inside = (which >= 0) & (which < centres.size)
    share = np.bincount(which[inside], weights=(p[inside] > 0.99), minlength=centres.size)
    count = np.bincount(which[inside], minlength=centres.size)
    ax1.plot(centres, share / np.maximum(count, 1), "o-", color=f"C{k}", ms=4,
             label=f"sand + {name}")
ax1.set_xscale("log")
ax1.set_ylim(-0.02, 1.02)
ax1.axvline(0.5, color="0.4", ls=":", lw=1)
ax1.annotate("coating 0.5 um", (0.5, 0.5), xytext=(4, 0), textcoords="offset points",
             fontsize=8, color="0.3")
ax1.set_xlabel("drawn asperity height of the silica-sand grain [um] (1-99 % of draws)")
ax1.set_ylabel("share of draws that always stick [-]")
ax1.set_title(f"{n} paired draws of the assumed values, binned", fontsize=10)
ax1.legend(fontsize=8)
fig.suptitle("K-silicate ash melt 0.5 um on 300 um grains, 875 degC, biomass flue gas, "
             "U/U_mf = 3, 1 atm", fontsize=10)
save(fig, "biomass_compare")
print("sand's asperity height: drawn "
      f"{np.percentile(ha_sand, 5):.2f}-{np.percentile(ha_sand, 95):.2f} um (5-95 %)")
