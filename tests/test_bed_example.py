"""Smoke test of examples/plot_bed_mixtures.py (its own: it takes ~15 s even on a tiny grid,
too long for the shared list of tests/test_examples.py)."""

from test_examples import run_example


def test_bed_mixtures_example_runs(tmp_path, monkeypatch, capsys):
    run_example("plot_bed_mixtures", tmp_path, monkeypatch, n="3")
    assert (tmp_path / "bed_mixtures.png").stat().st_size > 10_000
    out = capsys.readouterr().out
    assert out.count("sand alone") == 6 and out.count("narrow") == 6
