"""Command line: map, plot, collide, materials; bad configs name the key."""

import numpy as np
import pytest
import xarray as xr

from agglomtool.cli import main
from agglomtool.maps.config import ConfigError, parse_config

GOOD = """
[scene]
liquid = "hypothetical-slag"
h0 = 0.15e-6
d_i = 1000e-6
[grid]
T = { start = 900.0, stop = 1200.0, num = 3 }
h0 = { start = 0.12e-6, stop = 1e-6, num = 3, log = true }
"""


def test_map_and_plot(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    cfg.write_text(GOOD)
    out = tmp_path / "m.nc"
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 0
    with xr.open_dataset(out) as ds:
        np.testing.assert_allclose(ds.h0.values, np.geomspace(0.12e-6, 1e-6, 3))
        assert ds.propensity.dims == ("T", "h0")
    assert not (tmp_path / "m.nc.parts").exists()
    png = tmp_path / "w.png"
    assert main(["plot", str(out), "-o", str(png)]) == 0
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize("text,key", [
    ('[scene]\nliquidd = "water"\n[grid]\nT = [300.0]', "liquidd"),
    ('[grid]\nT = { start = 900.0, stop = 1200.0 }', "num"),
    ('[grid]\nh0 = [-1e-6, 1e-6]', "h0"),
    ('[grid]\nsolid_j = [1.0, 2.0]', "solid_j"),
    ('[scene]\neps = 2.0\n[grid]\nT = [1000.0]', "eps"),
    ('[options]\nnodes = 0\n[grid]\nT = [1000.0]', "nodes"),
    ('[grids]\nT = [1000.0]', "grids"),
])
def test_bad_config_names_the_key(text, key):
    import tomllib

    with pytest.raises(ConfigError, match=key):
        parse_config(tomllib.loads(text), "c.toml")


def test_bad_config_from_command_line(tmp_path, capsys):
    cfg = tmp_path / "bad.toml"
    cfg.write_text('[grid]\nh0 = [-1e-6]\n')
    assert main(["map", str(cfg), "-o", str(tmp_path / "x.nc")]) == 2
    assert "h0" in capsys.readouterr().err


def test_collide_report(capsys):
    args = ["collide", "--liquid", "hypothetical-slag", "--h0", "0.15e-6", "--d-i", "1e-3"]
    assert main([*args, "--u0", "0.3"]) == 0
    low = capsys.readouterr().out
    assert "agglomerate" in low and "u0* = 0.63" in low and "viscous-limited" in low
    assert main([*args, "--u0", "1.5"]) == 0
    assert "rebound" in capsys.readouterr().out


def test_materials_lists_sources(capsys):
    assert main(["materials"]) == 0
    out = capsys.readouterr().out
    assert "silica-sand" in out and "k-silicate-ash-melt" in out and "source:" in out


def test_materials_headings_name_each_kind_in_english(capsys):
    assert main(["materials"]) == 0
    headings = [line for line in capsys.readouterr().out.splitlines()
                if line and not line.startswith(" ")]
    assert headings == ["solids:", "liquids:", "gases:"]
