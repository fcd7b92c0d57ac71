"""``agglomtool compare CONFIG``: a comparison a designer can act on, from a file."""

import textwrap
from pathlib import Path

import pytest
import xarray as xr

from agglomtool.cli import main

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "configs" / "biomass_compare.toml"


def test_the_example_comparison_prints_a_verdict_per_pair(capsys, tmp_path):
    out = tmp_path / "cmp.nc"
    assert main(["compare", str(EXAMPLE), "-n", "512", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "propensity over 512 plausible inputs" in text
    verdicts = [line for line in text.splitlines()
                if line.startswith(("decided", "not decided", "no difference"))]
    assert len(verdicts) == 3
    assert "assumed but not drawn" not in text  # the melt's composition is drawn too
    ds = xr.open_dataset(out)
    assert "liquid k-silicate-ash-melt composition_wt K2O" in ds.attrs["assumed_drawn"]
    assert list(ds.option.values) == ["silica-sand", "ilmenite", "olivine"]
    # the history line of every file the tool writes: UTC time, version, the command
    assert ": agglomtool compare " in ds.attrs["history"].splitlines()[0]
    ds.close()


SCENE = """
[scene]
liquid = "water"
T = "25 degC"
d_i = "300 um"
h0 = "5 um"
"""


@pytest.mark.parametrize("body, match", [
    (SCENE, r"\[compare\] must hold exactly one field"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite"]\n', "two or more options"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\nh0 = [1e-6, 2e-6]\n',
     "exactly one field"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[uncertain]\n'
     'h0 = { law = "gamma", mean = 1e-6, sd = 1e-7 }\n', "law = 'gamma' is not one of"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[uncertain]\n'
     'h0 = { law = "normal", mean = "5 um" }\n', "missing: sd"),
    # a law with a unit on one number and none on another: 1e-6 would be read in m
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[uncertain]\n'
     'h0 = { law = "normal", mean = "5 um", sd = 1e-6 }\n',
     r"\[uncertain\] h0: mean = \"5 um\" has a unit and sd = 1e-06 has none \(read as "
     r"1e-06 m\)"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[uncertain]\n'
     'T = { law = "uniform", low = 290, high = "40 degC" }\n',
     r"\[uncertain\] T: high = \"40 degC\" has a unit and low = 290 has none"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[uncertain]\nha = 1\n',
     r"\[uncertain\] ha: not a numeric Scene field"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[options]\nn = 0\n',
     r"\[options\] n: must be an integer >= 16 \(.*bins.*\), got 0"),
    # fewer draws than the bins that find the deciding input: said in the file's terms
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[options]\nn = 8\n',
     r"\[options\] n: must be an integer >= 16 \(.*bins.*\), got 8"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "granite"]\n', "option 'granite'"),
    (SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n[extra]\n', "unknown table"),
    # a misspelt field: the file and the table named, with the field it may have meant
    (SCENE + '[compare]\nsolid_jj = ["ilmenite", "olivine"]\n',
     r"c\.toml: \[compare\] solid_jj: not a Scene field \(did you mean 'solid_j'\?\)"),
])
def test_bad_files_get_one_line_naming_the_key(tmp_path, capsys, body, match):
    path = tmp_path / "c.toml"
    path.write_text(textwrap.dedent(body))
    assert main(["compare", str(path), "-n", "16"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("agglomtool: error:") and len(err.strip().splitlines()) == 1
    import re

    assert re.search(match, err), err


def test_a_user_law_with_units_from_the_file(tmp_path, capsys):
    path = tmp_path / "c.toml"
    path.write_text(textwrap.dedent(SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n'
                                    '[uncertain]\nassumed = true\n'
                                    'h0 = { law = "normal", mean = "5 um", sd = "1 um" }\n'))
    assert main(["compare", str(path), "-n", "64"]) == 0
    assert "h0" in capsys.readouterr().out


@pytest.mark.parametrize("n", ["1", "8"])
def test_too_few_draws_on_the_command_line_name_n(tmp_path, capsys, n):
    # it named 'bins = 16', an option the command does not have
    path = tmp_path / "c.toml"
    path.write_text(textwrap.dedent(SCENE + '[compare]\nsolid_j = ["ilmenite", "olivine"]\n'))
    assert main(["compare", str(path), "-n", n]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"agglomtool: error: n = {n} ") and "allowed: n >= 16" in err, err
