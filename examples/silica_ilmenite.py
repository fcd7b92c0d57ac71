"""Example 2: which bed material is safer? Silica sand against ilmenite (and olivine).

A 300 um silica-sand grain meets a grain of silica sand, ilmenite or olivine of the same
size, all wetted by water at 25 degC in air. One sweep with the partner's material as the
first dimension gives the comparison; the picture has one panel per material. The scene and
grid are ``configs/sand_vs_ilmenite.toml``; the same from the command line::

    agglomtool map examples/configs/sand_vs_ilmenite.toml -o sand_vs_ilmenite.nc
    agglomtool plot sand_vs_ilmenite.nc -o sand_vs_ilmenite.png

Assumed (database entries say so): ilmenite's and olivine's 1 um asperity height and
restitution 0.85; the impact speeds are the default excess-gas estimate.
"""

from _output import map_from_config, output_dir

from agglomtool.plots import operating_window


def main() -> str:
    ds = map_from_config("sand_vs_ilmenite")
    for name in ds.solid_j.values:  # the numbers behind the picture, per material
        us = ds.u_star.sel(solid_j=name)
        print(f"{name:12s} u0* = {float(us.min()):.3f}-{float(us.max()):.3f} m/s, mean "
              f"propensity {float(ds.propensity.sel(solid_j=name).mean()):.3f}")
    path = output_dir() / "sand_vs_ilmenite.png"
    operating_window(ds, col="solid_j", path=path)
    return str(path)


if __name__ == "__main__":
    print(main())
