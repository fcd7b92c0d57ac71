"""Smoke tests: every example of the gallery runs on a tiny grid and writes its pictures."""

import runpy
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

#: example -> the pictures it writes (the gallery shows the same figures).
PICTURES = {
    "plot_fig6_curves": ["fig6_curves"],
    "plot_material_comparison": ["sand_vs_ilmenite"],
    "plot_biomass_window": ["biomass_window"],
    "plot_biomass_compare": ["biomass_compare"],
    "plot_granulator_window": ["granulator_window"],
    "plot_sobol": ["sobol_granulator"],
    "plot_speed_models_window": ["speed_models_window"],
    "plot_monte_carlo_table4": ["fig10_water_ew052", "fig10_water_ew020", "fig11_slag_ew052",
                                "fig11_slag_ew020", "figS4_convergence_water",
                                "figS4_convergence_slag"],
}


def run_example(name, tmp_path, monkeypatch, n="4"):
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_OUT", str(tmp_path))
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_N", n)
    monkeypatch.setenv("AGGLOMTOOL_EXAMPLE_SAMPLES", "2000")
    monkeypatch.syspath_prepend(str(EXAMPLES))
    sys.modules.pop("_output", None)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    try:
        runpy.run_path(str(EXAMPLES / f"{name}.py"), run_name="__main__")
    finally:
        plt.close("all")


def test_every_example_is_tested():
    # plot_bed_mixtures has its own test (tests/test_bed_example.py): it is slower.
    found = {p.stem for p in EXAMPLES.glob("plot_*.py")}
    assert found == set(PICTURES) | {"plot_bed_mixtures"}


@pytest.mark.parametrize("name", sorted(PICTURES))
def test_example_runs(name, tmp_path, monkeypatch):
    run_example(name, tmp_path, monkeypatch)
    for picture in PICTURES[name]:
        path = tmp_path / f"{picture}.png"
        assert path.stat().st_size > 10_000, path
