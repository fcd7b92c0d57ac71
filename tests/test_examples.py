"""Smoke tests: every example runs on a tiny grid and writes its picture."""

import runpy
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


@pytest.mark.parametrize("name", ["fig6_curves", "silica_ilmenite", "biomass_window",
                                  "granulator_window"])
def test_example_runs(name, tmp_path, monkeypatch):
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_OUT", str(tmp_path))
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_N", "4")
    monkeypatch.syspath_prepend(str(EXAMPLES))
    sys.modules.pop("_output", None)
    path = runpy.run_path(str(EXAMPLES / f"{name}.py"))["main"]()
    assert Path(path).parent == tmp_path and Path(path).stat().st_size > 10_000
