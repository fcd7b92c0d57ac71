"""The command line takes an option typed with the field's own name (``--d_i``, as in
Python and in the TOML files) as its dashed spelling (``--d-i``), and says each warning
once."""

from agglomtool.cli import main

ARGS = ["collide", "--liquid", "water", "--T", "25 degC", "--u0", "0.05"]


def test_field_names_with_underscores_are_the_dashed_options(capsys):
    assert main([*ARGS, "--d-i", "3 mm", "--U-Umf=2"]) == 0
    dashed = capsys.readouterr()
    assert main([*ARGS, "--d_i", "3 mm", "--U_Umf=2"]) == 0  # refused before
    underscored = capsys.readouterr()
    assert underscored.out == dashed.out
    assert "3000 um" in dashed.out
    assert main([*ARGS, "--d-i", "3 mm", "--h0", "d_i_not_an_option"]) == 2  # values alone


def test_a_warning_is_said_once(capsys):
    """d_i above the solid's size range was said twice by collide (the scene and its
    evaluation each found it)."""
    assert main(["collide", "--liquid", "water", "--T", "25 degC", "--d-i", "3 mm"]) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("agglomtool: warning:")]
    assert len(lines) == len(set(lines)) >= 1
    assert sum("d_i = 0.003 m" in line for line in lines) == 1
