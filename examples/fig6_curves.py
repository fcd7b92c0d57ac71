"""Example 1: the paper's Fig. 6, e_w against u0 for cases I and II at beta = 0, 45, 90.

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Fig. 6 and
Table 2. The paper's model (mode "paper") and, when the installed agglomtool has it, the
frame-consistent variant (mode "relative") side by side.

    python examples/fig6_curves.py        # writes examples/output/fig6_curves.png
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from _output import output_dir, points  # noqa: E402

import agglomtool  # noqa: E402
from agglomtool.examples import reference_cases  # noqa: E402


def main() -> str:
    modes = ["paper"] + (["relative"] if "relative" in agglomtool.MODES else [])
    cases = reference_cases()
    n = points(400)
    fig, axes = plt.subplots(len(cases), len(modes), figsize=(5.2 * len(modes), 7.5),
                             squeeze=False, layout="constrained")
    for row, case in enumerate(cases):
        u_ref = case.published_u_star
        u0 = np.linspace(0.5 * u_ref, 4.0 * u_ref, n)
        for col, mode in enumerate(modes):
            ax = axes[row, col]
            for beta in (0.0, 45.0, 90.0):
                res = case.collide(u0, beta_deg=beta, mode=mode, details=False)
                us = float(case.critical_impact_speed(beta, mode))
                ax.plot(u0, res.e_w, label=f"beta = {beta:g} deg (u0* = {us:.4g} m/s)")
            ax.axvline(u_ref, color="0.6", ls=":", lw=1)
            ax.set_title(f"{case.name}, mode {mode}", fontsize=9)
            ax.set_xlabel("impact speed u0 [m/s]")
            ax.set_ylabel("wet restitution coefficient e_w [-]")
            ax.legend(fontsize=7)
    path = output_dir() / "fig6_curves.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return str(path)


if __name__ == "__main__":
    print(main())
