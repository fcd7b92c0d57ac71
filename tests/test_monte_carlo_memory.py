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
