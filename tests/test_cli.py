"""The command line: each command runs and says what it computed; bad input is an error
message and exit code 2, not a traceback."""

import subprocess
import sys

import agglomtool as at
from agglomtool.cli import main


def test_reference_command_prints_both_cases(capsys):
    assert main(["reference", "--beta", "0"]) == 0
    out = capsys.readouterr().out
    assert "Case I, water" in out and "Case II, hypothetical slag" in out
    # The printed u0* is the API's, to the printed digits.
    u_star = float(at.examples.reference_cases()[0].critical_impact_speed(0.0))
    assert f"{u_star:9.5f}" in out


def test_bad_mode_is_a_clear_error(capsys):
    assert main(["reference", "--mode", "nonsense"]) == 2
    err = capsys.readouterr().err
    assert "--mode" in err and "'nonsense'" in err and "paper" in err


def test_module_entry_point_runs():
    done = subprocess.run(
        [sys.executable, "-m", "agglomtool", "reference", "--beta", "90"],
        capture_output=True, text=True, timeout=300, check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "u0* [m/s]" in done.stdout
