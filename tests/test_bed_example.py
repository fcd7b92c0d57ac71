"""Smoke test of examples/bed_mixtures.py (its own: it takes ~15 s even on a tiny grid, too
long for the shared list of tests/test_examples.py)."""

import runpy
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_bed_mixtures_example_runs(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_OUT", str(tmp_path))
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_N", "3")
    monkeypatch.syspath_prepend(str(EXAMPLES))
    sys.modules.pop("_output", None)
    path = runpy.run_path(str(EXAMPLES / "bed_mixtures.py"))["main"]()
    assert Path(path).parent == tmp_path and Path(path).stat().st_size > 10_000
    out = capsys.readouterr().out
    assert out.count("sand alone") == 6 and out.count("narrow") == 6
