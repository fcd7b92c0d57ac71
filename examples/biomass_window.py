"""Example 3: the operating window of a biomass-fired bubbling bed.

Silica sand coated by a potassium-silicate ash melt in biomass flue gas: temperature
against coating thickness at U/U_mf = 2, 4 and 8, coloured by the agglomeration
propensity, with u0* contours. The database's melt is so viscous (GRD: 1e2-1e7 Pa s here)
that any coating thicker than the 0.1 um asperities sticks at every speed up to the u0*
ceiling: the picture hatches that region; the window is only where no bridge forms.
The scene and grid are ``configs/biomass_window.toml``;
the same picture from the command line::

    agglomtool map examples/configs/biomass_window.toml -o biomass_window.nc
    agglomtool plot biomass_window.nc -o biomass_window.png
"""

from pathlib import Path

import numpy as np
from _output import output_dir, points

from agglomtool.maps import sweep, write_map
from agglomtool.maps.config import load_config
from agglomtool.plots import operating_window


def main() -> str:
    cfg = load_config(Path(__file__).parent / "configs" / "biomass_window.toml")
    grid = dict(cfg.grid)
    n = points(len(grid["T"]))
    grid["T"] = np.linspace(grid["T"][0], grid["T"][-1], n)
    grid["h0"] = np.geomspace(grid["h0"][0], grid["h0"][-1], n)
    ds = sweep(cfg.scene, nodes=cfg.options["nodes"], **grid)
    write_map(ds, output_dir() / "biomass_window.nc")
    path = output_dir() / "biomass_window.png"
    operating_window(ds, path=path)
    return str(path)


if __name__ == "__main__":
    print(main())
