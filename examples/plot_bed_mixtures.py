"""
Beds, not pairs: mixtures and size spread
=========================================

Shabanian et al. (2024, Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397) conclude that
"a fluidized bed of mixed silica sand and ilmenite particles ... can show a lower
agglomeration tendency than a bed merely comprised of silica sand" and that "a fluidized bed
made of particles with a narrow size distribution can exhibit a lower agglomeration tendency
than a bed having a wide particle size distribution". Here the bed-level propensity (the
fraction of all collisions that stick, weighted by collision rates and averaged over
isotropic collision directions: :func:`agglomtool.bed_propensity`) answers both:

(a) 1000 um silica sand alone against sand + 30 % (mass) 1000 um ilmenite;
(b) a narrow (geometric standard deviation 1.15) against a wide (1.6) lognormal of sand, mass
    median 1000 um;

at the paper's Table 2 conditions: case I, water at 25 C, h0 = 5 um; case II, the
hypothetical slag at 800 C in air, h0 = 0.15 um; both coated, asperities 0.1 um (the
paper's; the database's ilmenite value is an assumed 1 um). Impact speeds: the default
excess-gas estimate (Maxwellian, r.m.s. velocity per component = U - U_mf) at U/U_mf = 2.

Mixing and size spread also change the bed's U_mf (Wen-Yu with the Sauter mean diameter and
mean density), and with it the speeds at a given U/U_mf. So every comparison is made three
ways: at fixed U/U_mf = 2; at the fixed superficial velocity U of the reference bed (sand
alone, or narrow sand); at the reference bed's fixed granular temperature (the same speed
distribution: pair physics and collision weighting only).

The ilmenite is 1 mm as in the paper's Figs. 8b and 9b (1 mm particles with ilmenite's
density), larger than ilmenite bed material usually is (100-400 um in the materials
database): the tool warns about that size, and this example silences that one warning on
purpose, since it follows the paper.

The gallery runs the full size (11 ilmenite fractions, 6 size spreads, 12 size classes per
lognormal), about 10 s on two cores::

    python examples/plot_bed_mixtures.py     # writes examples/output/bed_mixtures.png
"""

# %%
# Set-up
# ------
# A :class:`agglomtool.Component` is a solid with its mass fraction, its sizes and its own
# coating; :func:`agglomtool.bed_propensity` evaluates a bed of components at one
# operating point, :func:`agglomtool.bed_sweep` over a grid (here the ilmenite fraction).
import warnings

import matplotlib.pyplot as plt
import numpy as np
from _output import points, save

import agglomtool as at
from agglomtool.bed import Component, bed_propensity, bed_sweep

# the paper's 1 mm ilmenite (see above): the one warning this example expects
warnings.filterwarnings("ignore", message=r"d50 = 0\.001 m is above the typical size range "
                        "of ilmenite", category=at.PlausibilityWarning)

CASES = {
    "case I: water, 25 C, h0 = 5 um": dict(T=298.15, liquid="water", h0=5e-6),
    "case II: slag, 800 C, h0 = 0.15 um": dict(T=1073.15, liquid="hypothetical-slag",
                                               h0=0.15e-6),
}
U_UMF = 2.0
D50 = 1000e-6
HA = 0.1e-6
NARROW, WIDE = 1.15, 1.6


def sand(fraction=1.0, gsd=1.0, classes=1):
    return Component("silica-sand", fraction, d50=D50, gsd=gsd, classes=classes, ha=HA)


def ilmenite(fraction):
    return Component("ilmenite", fraction, d50=D50, ha=HA)


def conventions(cond, ref_bed):
    """The three scenes of a comparison: fixed U/U_mf, the reference bed's U, its speeds."""
    scene = at.Scene(**cond, U_Umf=U_UMF)
    ref = bed_propensity(scene, ref_bed, directions=2)
    U, Umf = float(ref.U), float(ref.Umf)
    return {"fixed U/Umf = 2": scene,
            f"fixed U = {U:.2f} m/s": at.Scene(**cond, U=U),
            f"fixed speeds (Theta = {(U - Umf) ** 2:.3f} m2/s2)":
                at.Scene(**cond, speed="maxwellian", granular_temperature=(U - Umf) ** 2)}


# %%
# Both statements, both cases, three conventions
# ----------------------------------------------
# Left column (a): propensity against the ilmenite mass fraction; right column (b): against
# the geometric standard deviation of the sand sizes. The printed lines are the numbers of
# the README's table.
fractions = np.linspace(0.0, 1.0, points(11))
spreads = np.linspace(1.0, 2.0, points(6))
classes = points(12)
fig, axes = plt.subplots(2, 2, figsize=(10, 7.5), constrained_layout=True)
styles = ["-", "--", ":"]
for row, (title, cond) in enumerate(CASES.items()):
    print(title)
    # (a) mixture fraction of ilmenite
    ax = axes[row, 0]
    for style, (label, scene) in zip(styles, conventions(cond, [sand()]).items(),
                                     strict=True):
        ds = bed_sweep(scene, [sand(1.0), ilmenite(0.0)], mix="ilmenite",
                       fraction=np.unique(np.r_[fractions, 0.3]))
        p = ds.propensity
        ax.plot(p.fraction, p, style, color="k", label=label)
        print(f"  (a) {label:36s} sand alone {float(p.sel(fraction=0.0)):.4f}, "
              f"+30 % ilmenite {float(p.sel(fraction=0.3)):.4f}")
    ax.axvline(0.3, color="0.6", lw=0.8)
    ax.set(xlabel="ilmenite mass fraction in the bed [-]",
           ylabel="bed agglomeration propensity [-]", title=f"(a) {title}")
    ax.legend(fontsize=8)
    # (b) size spread of sand
    ax = axes[row, 1]
    for style, (label, scene) in zip(styles, conventions(
            cond, [sand(gsd=NARROW, classes=classes)]).items(), strict=True):
        props = {}
        for g in np.unique(np.r_[spreads, NARROW, WIDE]):
            ds = bed_propensity(scene, [sand(gsd=g, classes=1 if g == 1.0 else classes)])
            props[g] = float(ds.propensity)
        ax.plot(list(props), list(props.values()), style, color="k", label=label)
        print(f"  (b) {label:36s} narrow {props[NARROW]:.4f}, wide {props[WIDE]:.4f}")
    for g, text in ((NARROW, "narrow"), (WIDE, "wide")):
        ax.axvline(g, color="0.6", lw=0.8)
        ax.annotate(text, (g, 0.02), xycoords=("data", "axes fraction"), fontsize=8,
                    color="0.4", rotation=90, ha="right")
    ax.set(xlabel="geometric standard deviation of the sand sizes [-]",
           ylabel="bed agglomeration propensity [-]", title=f"(b) {title}")
    if row == 0:
        ax.legend(fontsize=8, loc="upper left")
    else:  # lower right, lifted above the "wide" label of its line
        ax.legend(fontsize=8, loc="lower right", bbox_to_anchor=(1.0, 0.14))
fig.suptitle("Beds, not pairs: 1000 um sand with ilmenite (a) and with a size spread (b)")
save(fig, "bed_mixtures")

# %%
# A wide size distribution agglomerates more in every comparison: its small grains are
# many and light, so they dominate the collisions and have the higher ``u0*``. The ilmenite
# bed agglomerates less at the same speeds and at the same ``U/U_mf``, but not at the same
# superficial velocity: the denser mixture has a higher ``U_mf``, so the same gas gives
# slower particles, and in this model slower collisions stick more.
