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

from _output import map_from_config, output_dir

from agglomtool.plots import operating_window


def main() -> str:
    ds = map_from_config("biomass_window")
    path = output_dir() / "biomass_window.png"
    operating_window(ds, path=path)
    return str(path)


if __name__ == "__main__":
    print(main())
