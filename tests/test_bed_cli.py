"""The bed's configuration file and its command: `agglomtool bed CONFIG -o OUT.nc`."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import agglomtool as at
from agglomtool.bed import Component, read_efficiency
from agglomtool.bed.config import parse_bed_config
from agglomtool.cli import main
from agglomtool.maps.config import ConfigError

CONFIG = Path(__file__).resolve().parent.parent / "examples" / "configs" / \
    "bed_sand_ilmenite.toml"

ONE = """
[scene]
liquid = "water"
T = "25 degC"
h0 = "5 um"
U_Umf = 2.0

[[component]]
solid = "silica-sand"
fraction = 0.6
d50 = "800 um"
gsd = 1.4
classes = 3

[[component]]
solid = "ilmenite"
fraction = 0.4
d = ["300 um", 400e-6]
d_fractions = [0.5, 0.5]
h0 = 0.0

[options]
directions = 4
"""


def test_bed_command_one_point_matches_the_api(tmp_path, capsys):
    cfg = tmp_path / "one.toml"
    cfg.write_text(ONE)
    rc = main(["bed", str(cfg), "-o", str(tmp_path / "b.nc"), "--efficiency",
               str(tmp_path / "m.csv")])
    assert rc == 0
    scene = at.Scene(liquid="water", T=298.15, h0=5e-6, U_Umf=2.0)
    ds = at.bed_propensity(scene, [Component("silica-sand", 0.6, d50=800e-6, gsd=1.4,
                                             classes=3),
                                   Component("ilmenite", 0.4, d=[300e-6, 400e-6], h0=0.0)],
                           directions=4)
    with xr.open_dataset(tmp_path / "b.nc") as f:
        assert float(f.propensity) == pytest.approx(float(ds.propensity), rel=1e-12)
        assert f.propensity.attrs["units"] == "1"
    np.testing.assert_array_equal(read_efficiency(tmp_path / "m.csv").efficiency.values,
                                  ds.efficiency.values)
    assert "bed propensity" in capsys.readouterr().out


def test_bed_command_sweeps_the_example_config(tmp_path):
    assert main(["bed", str(CONFIG), "-o", str(tmp_path / "s.nc")]) == 0
    with xr.open_dataset(tmp_path / "s.nc") as f:
        assert f.propensity.dims == ("U_Umf", "fraction")
        p = f.propensity.values
    assert np.all((p >= 0.0) & (p <= 1.0))
    assert np.all(np.diff(p, axis=0) < 0.0)  # faster bed, fewer sticking collisions


@pytest.mark.parametrize("gas", ["steam", "biomass-flue-gas"])
def test_bed_config_scene_is_read_at_its_own_temperature(gas):
    """A bed file's [scene] is a scene at its own T, not a one-point map at 300 K: a gas
    that condenses at room temperature (steam, a humid flue gas) loads at a bed temperature
    (it was refused with an error about a "[grid] T" the file does not have)."""
    import tomllib

    text = ONE.replace('liquid = "water"\nT = "25 degC"',
                       f'liquid = "k-silicate-ash-melt"\nT = "850 degC"\ngas = "{gas}"')
    assert text != ONE
    cfg = parse_bed_config(tomllib.loads(text), "bed.toml")
    assert cfg.scene.gas == gas
    assert cfg.scene.T == pytest.approx(1123.15, rel=1e-12)


@pytest.mark.parametrize("edit, message", [
    (("fraction = 0.4", "fraction = 0.3"), "sum to 0.9"),
    (('solid = "ilmenite"', 'solid = "ilmenit"'), "[[component]] 2: solid = 'ilmenit'"),
    (("gsd = 1.4", "gsd = 0.4"), "[[component]] 1: gsd = 0.4"),
    (("classes = 3", "classes = 3\ncolour = 1"), "[[component]] 1 colour: unknown"),
    (("directions = 4", "directions = 0"), "[options] directions"),
    (("[options]", "[grid]\nd_i = [1e-3]\n[options]"), "[grid] d_i: cannot be swept"),
    (("[options]", "[grid]\nfraction = [0.1]\n[options]"), "needs [options] mix"),
    # the same solid in two components: which one the fraction sets is not said by its name
    (('solid = "ilmenite"', 'solid = "silica-sand"', "[options]",
      '[grid]\nfraction = [0.1]\n[options]\nmix = "silica-sand"'),
     "[options] mix: mix = 'silica-sand' names 2 components (0, 1)"),
    # one component: its fraction is 1 whatever the axis says
    (('[[component]]\nsolid = "ilmenite"\nfraction = 0.4\nd = ["300 um", 400e-6]\n'
      'd_fractions = [0.5, 0.5]\nh0 = 0.0\n', "", "fraction = 0.6", "fraction = 1.0",
      "[options]", '[grid]\nfraction = [0.1]\n[options]\nmix = "silica-sand"'),
     "[grid] fraction: the bed has one component"),
])
def test_bed_config_errors_name_the_key(edit, message, capsys, tmp_path):
    text = ONE
    for old, new in zip(edit[::2], edit[1::2], strict=True):
        text = text.replace(old, new)
    assert text != ONE
    import tomllib

    with pytest.raises(ConfigError) as info:
        parse_bed_config(tomllib.loads(text), "bed.toml")
    assert message in str(info.value)
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text)
    assert main(["bed", str(cfg), "-o", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("agglomtool: error:") and err.count("\n") == 1


BED_U = """
[scene]
liquid = "water"
T = "25 degC"
h0 = "5 um"

[[component]]
solid = "silica-sand"
fraction = 1.0
d50 = "300 um"

[grid]
U_Umf = {}
"""


@pytest.mark.parametrize("axis, said", [
    ("[0.5, 3.0]", r"bed propensity (\S+) over U_Umf 2; no answer at 1 of 2 points"),
    ("[0.5, 0.8]", r"bed propensity: no answer at any of the 2 points"),
])
def test_the_bed_summary_counts_the_points_without_an_answer(tmp_path, capsys, axis, said):
    """'bed propensity 0.64-0.64 over U_Umf 2' hid that one of two points had no answer, and
    a bed with none printed 'nan-nan'."""
    import re

    cfg = tmp_path / "b.toml"
    cfg.write_text(BED_U.format(axis))
    out = tmp_path / "b.nc"
    assert main(["bed", str(cfg), "-o", str(out), "-q"]) == 0
    text = capsys.readouterr().out
    found = re.search(said, text)
    assert found and "nan" not in text, text
    with xr.open_dataset(out) as ds:
        p = ds.propensity.values
        assert int((ds.speed_flag != 0).sum()) == int(np.isnan(p).sum()) >= 1
        if found.groups():
            assert float(found.group(1)) == pytest.approx(float(np.nanmax(p)), rel=1e-3)
