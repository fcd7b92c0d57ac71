"""Draw docs/speed_models.png: the median impact speed of every impact-speed model against
U - U_mf, for silica sand and glass beads of 0.2, 0.5 and 1 mm in air at 20 degC.

Run from the repository root: ``python docs/speed_models_figure.py`` (a few seconds). The
bed: a 0.3 m column, 0.3 m of static bed on a porous plate, collisions at half its height,
wake fraction 0.25, each solid's database restitution. A line is dotted where the model
warns that the scene is outside the data its correlations were fitted to.
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

import agglomtool as at
from agglomtool.scene import Resolved

OUT = Path(__file__).resolve().parent / "speed_models.png"
SOLIDS = {"silica-sand": "silica sand", "glass-beads": "glass beads"}
SIZES = (200e-6, 500e-6, 1000e-6)
EXCESS = np.geomspace(0.02, 0.6, 28)  # U - U_mf [m/s]
STYLE = {"excess-gas": "#444444", "bubble-darton": "#1f77b4", "bubble-mori-wen": "#2ca02c",
         "collisional-balance": "#d62728"}


def medians(solid: str, d: float, model: str):
    """The model's median impact speed at each excess velocity, and whether it warned."""
    base = at.Scene(T=293.15, gas="air", liquid="water", h0=0.5e-6, solid_i=solid, d_i=d,
                    speed=model, bed_height=0.3, column_diameter=0.3).values()
    umf = float(Resolved(base).Umf)
    out, warned = [], []
    for x in EXCESS:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", at.PlausibilityWarning)
            out.append(float(Resolved({**base, "U": umf + x}).speeds.median()))
        warned.append(any(issubclass(w.category, at.PlausibilityWarning) for w in caught))
    return np.array(out), np.array(warned), umf


def main(path: Path = OUT) -> Path:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(11, 6.4), sharex=True, sharey=True,
                             constrained_layout=True)
    for row, (solid, label) in enumerate(SOLIDS.items()):
        for col, d in enumerate(SIZES):
            ax = axes[row, col]
            umf = None
            for model, color in STYLE.items():
                y, warned, umf = medians(solid, d, model)
                ok = np.where(warned, np.nan, y)
                ax.plot(EXCESS, ok, color=color, lw=1.8, label=model)
                ax.plot(EXCESS, y, color=color, lw=1.2, ls=":")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xticks([0.02, 0.05, 0.1, 0.2, 0.5], ["0.02", "0.05", "0.1", "0.2", "0.5"])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.grid(True, which="both", alpha=0.25)
            ax.set_title(f"{label}, {d * 1e3:g} mm (U_mf = {umf * 100:.2g} cm/s)", fontsize=10)
            if row == 1:
                ax.set_xlabel("U - U_mf [m/s]")
            if col == 0:
                ax.set_ylabel("median impact speed u0 [m/s]")
    axes[0, 0].legend(fontsize=8, loc="upper left")
    fig.suptitle("Impact-speed models side by side (air, 20 degC; 0.3 m column, 0.3 m bed, "
                 "porous plate, collisions at 0.15 m); dotted: outside the correlations' "
                 "data", fontsize=10)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    print(main(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT))
