"""A command that evaluated CoolProp states itself (a gas state outside the property tables,
or a refused one) exits without CoolProp's binding layer reporting "leaked instances": the
states the package keeps are released before the interpreter ends (they were printed after
the answer, or after the error, as if something had gone wrong)."""

import subprocess
import sys

import pytest


@pytest.mark.parametrize("args, code", [
    # a pressure beyond the gas tables: CoolProp evaluates the state; an answer
    (["collide", "--P", "9e8"], 0),
    # steam below its saturation line: refused by name, exit 2
    (["collide", "--gas", "steam", "--T", "300"], 2),
])
def test_no_leak_report_on_exit(args, code):
    run = subprocess.run([sys.executable, "-m", "agglomtool", *args], capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == code, run.stderr
    assert "leaked" not in run.stderr, run.stderr
    assert "leaked" not in run.stdout
