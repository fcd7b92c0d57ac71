"""The map and bed commands' stderr: the sweep's estimate line, the tqdm bar when asked."""

from pathlib import Path

import pytest

from agglomtool.cli import main

CONFIG = """
[scene]
liquid = "hypothetical-slag"
h0 = 0.15e-6
d_i = 300e-6
[grid]
T = { start = 900.0, stop = 1200.0, num = 3 }
h0 = { start = 0.12e-6, stop = 1e-6, num = 3, log = true }
"""
BED = Path(__file__).resolve().parent.parent / "examples" / "configs" / "bed_sand_ilmenite.toml"


@pytest.fixture()
def cfg(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(CONFIG)
    return path


def _estimate_lines(err):
    return [line for line in err.splitlines() if line.startswith("agglomtool: sweep of ")]


@pytest.mark.parametrize("flag", [[], ["-q"]])
def test_map_says_its_estimate_in_one_line_without_a_bar(cfg, tmp_path, capsys, flag):
    """stderr is not a terminal here: no bar unless asked, the estimate line always."""
    assert main(["map", str(cfg), "-o", str(tmp_path / "m.nc"), *flag]) == 0
    err = capsys.readouterr().err
    (line,) = _estimate_lines(err)
    assert line.startswith("agglomtool: sweep of 9 points in 1 block: ")
    assert "in memory" in line and "store up to" in line
    assert "pt/s" not in err and "%|" not in err


def test_map_shows_a_tqdm_bar_when_asked(cfg, tmp_path, capsys):
    assert main(["map", str(cfg), "-o", str(tmp_path / "m.nc"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert len(_estimate_lines(err)) == 1
    assert "9/9" in err and "pt/s" in err and "100%|" in err and "block 1/1" in err
    assert err.index("agglomtool: sweep of") < err.index("100%|")  # the line, then the bar


def test_progress_and_quiet_exclude_each_other(cfg, tmp_path, capsys):
    assert main(["map", str(cfg), "-o", str(tmp_path / "m.nc"), "--progress", "-q"]) == 2
    assert "not allowed with" in capsys.readouterr().err


def test_bed_shows_a_tqdm_bar_when_asked(tmp_path, capsys):
    assert main(["bed", str(BED), "-o", str(tmp_path / "b.nc"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "12/12" in err and "pt/s" in err and "100%|" in err
    assert main(["bed", str(BED), "-o", str(tmp_path / "b.nc")]) == 0
    assert "pt/s" not in capsys.readouterr().err
