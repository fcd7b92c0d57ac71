"""Example 2: silica sand against ilmenite in the same bed and melt.

u0* and agglomeration propensity maps (temperature against coating thickness) for the
silica-silica, silica-ilmenite and ilmenite-ilmenite pairs of a bed of both materials,
fluidized by air at U/U_mf = 4, coated by a wood-ash melt.

    python examples/silica_ilmenite.py    # writes examples/output/silica_ilmenite.png
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from _output import output_dir, points  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

from agglomtool.maps import sweep  # noqa: E402
from agglomtool.scene import Scene  # noqa: E402

SIZES = {"silica-sand": 400e-6, "ilmenite": 200e-6}  # typical bed sizes [m]
PAIRS = [("silica-sand", "silica-sand"), ("silica-sand", "ilmenite"), ("ilmenite", "ilmenite")]


def main() -> str:
    n = points(40)
    T = np.linspace(1073.15, 1473.15, n)
    h0 = np.geomspace(1.05e-6, 10e-6, n)  # above ilmenite's 1 um asperities
    maps = []
    for a, b in PAIRS:
        scene = Scene(gas="air", liquid="wood-ash-melt", solid_i=a, d_i=SIZES[a], solid_j=b,
                      d_j=SIZES[b], U_Umf=4.0)
        ds = sweep(scene, T=T, h0=h0)
        maps.append(ds[["u_star", "propensity"]].expand_dims(pair=[f"{a} / {b}"]))
    ds = xr.concat(maps, dim="pair")
    ds.to_netcdf(output_dir() / "silica_ilmenite.nc")
    fig, axes = plt.subplots(2, 3, figsize=(14, 7.5), sharex=True, sharey=True,
                             layout="constrained")
    us = ds.u_star.values
    finite = us[np.isfinite(us) & (us > 0)]
    norm = LogNorm(finite.min(), finite.max()) if finite.size else None
    for k, pair in enumerate(ds.pair.values):
        part = ds.sel(pair=pair)
        x, y = part.h0.values * 1e6, part.T.values - 273.15
        m1 = axes[0, k].pcolormesh(x, y, part.u_star.transpose("T", "h0").values,
                                   shading="nearest", norm=norm, cmap="viridis")
        m2 = axes[1, k].pcolormesh(x, y, part.propensity.transpose("T", "h0").values,
                                   shading="nearest", vmin=0, vmax=1, cmap="magma_r")
        axes[0, k].set_title(pair, fontsize=9)
        for ax in axes[:, k]:
            ax.set_xscale("log")
            ax.set_xlabel("coating thickness h0 [um]")
    for ax in axes[:, 0]:
        ax.set_ylabel("temperature [degC]")
    fig.colorbar(m1, ax=axes[0], label="critical impact speed u0* [m/s]")
    fig.colorbar(m2, ax=axes[1], label="agglomeration propensity [-]")
    fig.suptitle("wood-ash melt, air, U/U_mf = 4: silica sand (400 um) and ilmenite (200 um)")
    path = output_dir() / "silica_ilmenite.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return str(path)


if __name__ == "__main__":
    print(main())
