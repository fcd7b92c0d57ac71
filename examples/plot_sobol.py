"""
Sobol indices: which uncertain input matters at an operating point?
===================================================================

A designer's granulator runs 400 um glass beads wetted by about 4 um of water, in air at
50 degC, at ``U/U_mf`` = 1.6: near the edge of its operating window (see the granulator
example). None of these numbers is known exactly. Which uncertainty decides whether the
beads stick?

The uncertain inputs are named as the :class:`agglomtool.Scene` names them, with units:

- the water film ``h0``: lognormal with mean 4 um and standard deviation 0.8 um;
- the bead diameter ``d_i``: normal, 400 +- 40 um;
- the temperature ``T``: normal, 323.15 +- 5 K;
- the fluidization number ``U_Umf``: uniform on [1.2, 2.0];
- the asperity height ``ha_i``: lognormal, mean 0.5 um, sd 0.2 um (the database's value is
  an assumption).

Every draw re-derives the properties as a map does (water's viscosity and surface tension
at the drawn ``T``, ``U_mf`` at the drawn size), and ``e_w`` is evaluated at the median of
the scene's impact-speed distribution. :func:`agglomtool.monte_carlo` gives the spread of
``e_w``; :func:`agglomtool.sobol_indices` (SALib) splits its variance among the inputs:
the first-order index ``S1`` is the share an input explains alone, the total index ``ST``
includes its interactions.

The gallery runs 1e5 Monte Carlo samples and a Sobol base sample of 2**13; the full size
(2e5 samples, 2**14)::

    python examples/plot_sobol.py     # writes examples/output/sobol_granulator.png
"""

# %%
# The operating point and its uncertain inputs
# --------------------------------------------
import matplotlib.pyplot as plt
import numpy as np
from _output import samples, save

import agglomtool as at

scene = at.Scene(gas="air", T=323.15, liquid="water", solid_i="glass-beads", d_i="400 um",
                 h0="4 um", U_Umf=1.6)
uncertain = {
    "h0": at.LogNormal(4.0, 0.8, units="um"),
    "d_i": at.Normal(400.0, 40.0, units="um"),
    "T": at.Normal(323.15, 5.0),
    "U_Umf": at.Uniform(1.2, 2.0),
    "ha_i": at.LogNormal(0.5, 0.2, units="um"),
}
N = samples(200_000)
N_BASE = 2 ** max(6, round(np.log2(N / 16)))

# %%
# Monte Carlo: how uncertain is the outcome?
# ------------------------------------------
mc = at.monte_carlo(scene, uncertain=uncertain, n=N, seed=7)
print(f"e_w at the mean inputs {float(mc.e_w_nominal):.3f}; P(sticks) = "
      f"{float(mc.p_agglomeration):.3f} +- {float(mc.p_agglomeration_se):.3f}; "
      f"mean e_w {float(mc.e_w_mean):.3f}, sd {float(mc.e_w_std):.3f}")

# %%
# Sobol: which input is responsible?
# -----------------------------------
sob = at.sobol_indices(scene, uncertain=uncertain, n_base=N_BASE, seed=7)
for i, name in enumerate(sob.factor.values):
    print(f"{name:6s} S1 = {float(sob.S1[i]):6.3f} +- {float(sob.S1_conf[i]):.3f}   "
          f"ST = {float(sob.ST[i]):6.3f} +- {float(sob.ST_conf[i]):.3f}")
print(f"{sob.attrs['n_model_runs']:,} model runs")

# %%
# The picture
# -----------
# Left: the distribution of ``e_w`` (the bar at 0 is the probability of sticking). Right:
# the indices with their 95 % bootstrap confidence half-widths.
fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
rebound = mc.e_w.values[mc.e_w.values > 0]
ax0.hist(rebound, bins=60, range=(0, 1), weights=np.full(rebound.size, 1 / mc.e_w.size),
         color="0.5", label="rebounds")
ax0.bar(0.0, float(mc.p_agglomeration), width=0.03, color="C3",
        label=f"sticks: P = {float(mc.p_agglomeration):.2f}")
ax0.set(xlabel="wet restitution coefficient e_w [-]", ylabel="fraction of samples [-]",
        title=f"Monte Carlo, {N:,} samples")
ax0.legend(fontsize=8)
x = np.arange(sob.factor.size)
ax1.bar(x - 0.2, sob.S1, 0.4, yerr=sob.S1_conf, capsize=3, label="first order S1")
ax1.bar(x + 0.2, sob.ST, 0.4, yerr=sob.ST_conf, capsize=3, label="total ST")
ax1.set_xticks(x, [f"{n}" for n in sob.factor.values])
ax1.axhline(0, color="k", lw=0.6)
ax1.set(ylabel="Sobol index of e_w [-]",
        title=f"Sobol indices, base sample {N_BASE} ({sob.attrs['n_model_runs']:,} runs)")
ax1.legend(fontsize=8)
fig.suptitle("Glass beads 400 um, water 4 um, 50 degC, U/U_mf 1.6: what decides sticking?")
save(fig, "sobol_granulator")

# %%
# The fluidization number and the bead size carry most of the variance: they set the
# impact speed and the inertia that must break the liquid bridge. The film thickness comes
# next; temperature (over +- 5 K) and the asperity height hardly matter here.
