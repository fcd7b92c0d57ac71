"""Example 4: the operating window of a fluidized-bed granulator or dryer.

Glass beads wetted by water in air at 50 degC: the probability that a collision sticks over
the water layer's thickness and the fluidization number, for three bead sizes. Small beads
carrying a few microns of water stick unless the bed is fluidized hard; large beads are safe
almost everywhere. The scene and grid are ``configs/granulator_window.toml``; the same
picture from the command line (it is the README's)::

    agglomtool map examples/configs/granulator_window.toml -o granulator_window.nc
    agglomtool plot granulator_window.nc -o granulator_window.png

Assumed: the impact speeds are the default excess-gas estimate (Maxwellian, r.m.s. per
component U - U_mf), an order of magnitude; glass's 0.5 um asperity height.
"""

from _output import map_from_config, output_dir

from agglomtool.plots import operating_window


def main() -> str:
    ds = map_from_config("granulator_window")
    path = output_dir() / "granulator_window.png"
    operating_window(ds, path=path)
    return str(path)


if __name__ == "__main__":
    print(main())
