"""Speed of the answers with their confidence (the Scene Monte Carlo, robust maps, compare).

Run ``python benchmarks/bench_confidence.py [--quick]``. Figures, not assertions; each is
the best and the median of ``REPEATS`` runs after a warm-up call, with the load average.

1. Scene Monte Carlo, 1e6 draws (1e5 with ``--quick``), water and a melt: ``h0`` alone
   against ``h0`` and ``T`` uncertain, timed in alternation (the goal: T and h0 within 3x
   of h0 alone). Every draw answers the map's question (u0*, propensity, e_w). 1b: the
   same with a melt's assumed composition drawn instead of T.
2. A robust map of 35 x 35 points x 3 materials with 256 draws per point (water, the
   README's material comparison; goal under 60 s on an idle 2-core machine).
3. ``compare`` of 3 materials with 4096 paired draws (the biomass combustor's melt; goal
   under 10 s).
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_collision import paired, timings  # noqa: E402

import agglomtool as at  # noqa: E402

REPEATS = 5


def load() -> str:
    return "load average {:.2f} {:.2f} {:.2f}".format(*os.getloadavg())


def scene_mc(n: int) -> None:
    cases = {
        "water, glass 400 um, 50 degC": (
            at.Scene(liquid="water", T=323.15, h0=5e-6, d_i=400e-6, solid_i="glass-beads",
                     U_Umf=2.0), at.Normal(5e-6, 1e-6), at.Normal(323.15, 5.0)),
        "blast-furnace slag, alumina 500 um, 1500 degC": (
            at.Scene(liquid="blast-furnace-slag", T=1773.15, h0=2e-6, d_i=500e-6,
                     solid_i="dense-alumina", U_Umf=3.0),
            at.Normal(2e-6, 0.5e-6), at.Normal(1773.15, 20.0)),
    }
    for label, (scene, h0, T) in cases.items():
        def one(unc, scene=scene):
            return at.monte_carlo(scene, uncertain=unc, n=n, seed=1, keep_samples=False)

        both, alone = {"h0": h0, "T": T}, {"h0": h0}
        (tb, tm), (rb, rm), ratio = paired(lambda u=both: one(u), lambda u=alone: one(u),
                                           repeats=REPEATS)
        print(f"  {label}: n = {n:,} ({load()})")
        print(f"    h0 alone      best {rb:7.3f} s  median {rm:7.3f} s")
        print(f"    h0 and T      best {tb:7.3f} s  median {tm:7.3f} s  "
              f"median ratio {ratio:.2f} (goal <= 3)")


def composition_mc(n: int) -> None:
    """A melt whose composition the database assumes (K2O-CaO-SiO2 ash melt, 900 degC):
    ``h0`` alone against ``h0`` and the composition's three oxide factors drawn (each
    draw's melt properties from the models, vectorised over the compositions)."""
    scene = at.Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T=1173.15,
                     h0=2e-6, d_i=500e-6, solid_i="silica-sand", ha_i=1e-7, theta_deg=10.0,
                     speed="lognormal", u0=0.3)  # only the composition left assumed
    h0 = at.Normal(2e-6, 0.5e-6)

    def one(unc):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return at.monte_carlo(scene, uncertain=unc, n=n, seed=1, keep_samples=False)

    (tb, tm), (rb, rm), ratio = paired(lambda: one({"assumed": True, "h0": h0}),
                                       lambda: one({"h0": h0}), repeats=REPEATS)
    print(f"  k-silicate ash melt, sand 500 um, 900 degC: n = {n:,} ({load()})")
    print(f"    h0 alone           best {rb:7.3f} s  median {rm:7.3f} s")
    print(f"    h0 and composition best {tb:7.3f} s  median {tm:7.3f} s  "
          f"median ratio {ratio:.2f}")


def robust_map(samples: int, n: int) -> None:
    scene = at.Scene(liquid="water", T=298.15, solid_i="silica-sand", d_i=300e-6)
    grid = dict(solid_j=["silica-sand", "ilmenite", "olivine"],
                U_Umf=np.linspace(1.2, 8.0, n), h0=np.geomspace(1e-6, 30e-6, n))
    b, m = timings(lambda: at.sweep(scene, uncertain="assumed", samples=samples, **grid),
                       repeats=3)
    print(f"  robust map {n} x {n} x 3 points x {samples} draws: best {b:.2f} s, median "
          f"{m:.2f} s ({load()}; goal < 60 s)")


def compare(n: int) -> None:
    scene = at.Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T=1173.15,
                     solid_i="silica-sand", d_i=300e-6, h0=0.5e-6, U_Umf=3.0)
    b, m = timings(lambda: at.compare(scene, solid_j=["silica-sand", "ilmenite",
                                                           "olivine"], n=n, seed=0))
    print(f"  compare 3 materials x {n} paired draws: best {b:.2f} s, median {m:.2f} s "
          f"({load()}; goal < 10 s)")


def main() -> None:
    quick = "--quick" in sys.argv
    warnings.simplefilter("ignore", at.PlausibilityWarning)
    print("1. Scene Monte Carlo, h0 alone against h0 and T")
    scene_mc(10**5 if quick else 10**6)
    print("1b. Scene Monte Carlo, h0 alone against h0 and a melt's assumed composition")
    composition_mc(10**5 if quick else 10**6)
    print("2. Robust map")
    robust_map(32 if quick else 256, 12 if quick else 35)
    print("3. compare")
    compare(1024 if quick else 4096)


if __name__ == "__main__":
    main()
