"""Monte Carlo in chunks: the same draws as drawing everything at once, memory set by
``chunk_size``."""

import tracemalloc

import numpy as np
import pytest

from agglomtool.uncertainty import Uniform, monte_carlo, table4_case
from agglomtool.uncertainty.monte_carlo import draw_inputs


@pytest.mark.parametrize("chunk", [7, 333, 5_000])
def test_chunked_draws_equal_the_draws_made_at_once(chunk):
    kw = table4_case("water", 0.52)
    kw["uncertain"] = {**kw["uncertain"], "h0_i": Uniform(-0.2, 0.8, units="um")}
    n = 5_000
    ds = monte_carlo(**kw, n=n, seed=4, chunk_size=chunk)
    values, resampled, _ = draw_inputs(kw["uncertain"], n, 4)
    assert resampled["h0_i"] > 0  # the truncation path is exercised
    for name, x in values.items():
        assert ds[name].values.tobytes() == x.tobytes(), name
        assert ds[name].attrs["n_resampled"] == resampled[name]
    whole = monte_carlo(**kw, n=n, seed=4, chunk_size=n, keep_samples=False)
    for name in ("p_agglomeration", "e_w_mean", "e_w_quantile", "e_w_density"):
        np.testing.assert_array_equal(ds[name].values, whole[name].values, err_msg=name)
    np.testing.assert_allclose(float(ds.e_w_std), np.std(ds.e_w.values, ddof=1), rtol=1e-12)


def _peak(n, chunk):
    kw = table4_case("water", 0.52)
    tracemalloc.start()
    try:
        monte_carlo(**kw, n=n, seed=1, chunk_size=chunk, keep_samples=False)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_memory_is_e_w_plus_one_chunk():
    """Peak of the arrays a run allocates (numpy reports them to tracemalloc): 8 bytes a
    sample for e_w plus a bounded amount per sample of a chunk, not the ~90 bytes a sample
    of drawing every input at once."""
    n, chunk = 1_000_000, 20_000
    one, two = _peak(n, chunk), _peak(2 * n, chunk)
    assert one < 8 * n + 1_000 * chunk, f"{one / n:.0f} bytes per sample"
    assert two - one < 12 * n, f"{(two - one) / n:.0f} bytes per extra sample"


#: More draws than any machine holds (8 bytes each at least: 80 TB).
HUGE = 10**13


def test_more_draws_than_memory_are_refused_naming_the_count():
    """n or samples beyond the memory available is refused before any work, naming the
    field, the value and the largest that fits (it was numpy's MemoryError, a traceback on
    the command line)."""
    import warnings

    import agglomtool as at

    warnings.simplefilter("ignore", at.PlausibilityWarning)
    scene = at.Scene(liquid="water", T=298.15, d_i=300e-6, h0=5e-6, U_Umf=3.0,
                     solid_i="silica-sand", solid_j="ilmenite")
    match = rf"n = {HUGE} would hold .* in memory .* is available; allowed: n <= \d+"
    with pytest.raises(ValueError, match=match):
        monte_carlo(**table4_case("water", 0.52), n=HUGE, seed=1)
    with pytest.raises(ValueError, match=match):
        at.monte_carlo(scene, uncertain="assumed", n=HUGE, seed=1)
    with pytest.raises(ValueError, match=match):
        at.compare(scene, uncertain="assumed", n=HUGE, seed=1,
                   solid_j=["silica-sand", "ilmenite"])
    with pytest.raises(ValueError, match=rf"samples = {HUGE} would hold .*allowed: samples"):
        at.sweep(scene, uncertain="assumed", samples=HUGE, h0=[2e-6, 8e-6])


def test_the_largest_count_said_fits(monkeypatch):
    import agglomtool._validate as validate
    from agglomtool._validate import check_memory_for

    monkeypatch.setattr(validate, "available_memory", lambda: 1000)
    with pytest.raises(ValueError, match=r"n = 126 would hold 1.01 kB .*allowed: n <= 125"):
        check_memory_for("n", 126, 8)
    check_memory_for("n", 125, 8)  # what it says fits, fits
    monkeypatch.setattr(validate, "available_memory", lambda: None)
    check_memory_for("n", HUGE, 8)  # memory not known: nothing refused


def test_the_compare_command_refuses_too_many_draws(tmp_path, capsys):
    from agglomtool.cli import main

    cfg = tmp_path / "c.toml"
    cfg.write_text(f"""
[scene]
liquid = "water"
T = "25 degC"
solid_i = "silica-sand"
d_i = "300 um"
h0 = "5 um"
U_Umf = 3.0
[compare]
solid_j = ["silica-sand", "ilmenite"]
[options]
n = {HUGE}
""")
    assert main(["compare", str(cfg)]) == 2
    err = capsys.readouterr().err
    assert f"error: n = {HUGE} would hold" in err and "Traceback" not in err
