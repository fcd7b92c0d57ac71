"""The Monte Carlo draws and summary: one pass over each stream, concurrent inputs, the
summary without a sort. Same laws, reproducible from the seed, independent of chunk size
and threads; the summary equal to numpy's, bitwise."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import scipy.stats as st
from conftest import dkw_eps, ks_sup
from hypothesis import given, settings
from hypothesis import strategies as hs

from agglomtool.uncertainty import LogNormal, Normal, Uniform, monte_carlo, table4_case
from agglomtool.uncertainty._select import summary_counts, summary_numpy
from agglomtool.uncertainty.distributions import Distribution
from agglomtool.uncertainty.monte_carlo import _stream, draw_inputs

#: where the draws and the summary are made (both Monte Carlo paths use it)
sampling = importlib.import_module("agglomtool.uncertainty._sampling")



# --- the draws -----------------------------------------------------------------------------


@pytest.mark.parametrize("dist", [Normal(3.3, 0.7), Normal(-2.0, 1e-6), LogNormal(3.0, 1.5),
                                  Uniform(-0.2e-6, 0.8e-6), Uniform(1.1, 7.3)])
def test_draw_into_gives_the_values_of_draw(dist):
    a = dist._draw(np.random.default_rng(3), 10_007)
    b = np.full(10_007, np.nan)
    dist._draw_into(np.random.default_rng(3), b)
    assert a.tobytes() == b.tobytes()


def test_a_distribution_without_draw_into_still_samples():
    class Shifted(Distribution):  # a user's law implementing only the required methods
        nominal = 1.0

        def _draw(self, rng, n):
            return 1.0 + rng.random(n)

        def _mass(self, lo, hi):
            return max(0.0, min(hi, 2.0) - max(lo, 1.0))

        def _ppf_trunc(self, u, lo, hi):
            a, b = max(lo, 1.0), min(hi, 2.0)
            return a + u * (b - a)

    x, k = Shifted().sample(np.random.default_rng(0), 1000, 1.5, 3.0)
    assert x.min() >= 1.5 and x.max() <= 2.0 and 400 < k < 600



def test_a_users_law_without_a_units_field_takes_quantities():
    """A user's law with no ``units`` field (the base class does not require one) may still
    be given parameters with units: they are converted to SI like a Normal's (this raised
    AttributeError: 'Centred' object has no attribute 'units')."""
    from dataclasses import dataclass

    from agglomtool.uncertainty.distributions import to_si

    @dataclass(frozen=True)
    class Centred(Distribution):
        mean: object = 0.0
        sd: object = 1.0

        @property
        def nominal(self):
            return self.mean

    law = to_si("h0", Centred("5 um", "1 um"), "m")
    assert type(law) is Centred
    assert law.mean == pytest.approx(5e-6, rel=1e-12) and law.sd == pytest.approx(1e-6,
                                                                                 rel=1e-12)
    assert to_si("h0", Centred(5e-6, 1e-6), "m") == Centred(5e-6, 1e-6)  # SI, as typed

def test_first_draws_are_the_input_stream_itself():
    """An input never outside its range (all of the paper's Table 4) is exactly the first
    draws of its own stream: these numbers did not change with the one-pass sampling."""
    kw = table4_case("water", 0.52)
    values, resampled, dists = draw_inputs(kw["uncertain"], 20_000, 5)
    for name, x in values.items():
        assert resampled[name] == 0
        ref = dists[name]._draw(_stream(5, name), 20_000)
        assert x.tobytes() == ref.tobytes(), name


def test_replacements_come_from_their_own_stream():
    """A draw outside the range is replaced through the truncated inverse CDF of a uniform
    from the stream ``name + '/truncated'``, in sample order; the others are untouched."""
    d = Normal(1.0, 1.0)
    values, resampled, _ = draw_inputs({"d_i": d}, 5_000, 11)
    first = d._draw(_stream(11, "d_i"), 5_000)
    bad = first <= 0.0
    assert resampled["d_i"] == int(bad.sum()) > 500
    np.testing.assert_array_equal(values["d_i"][~bad], first[~bad])
    u = _stream(11, "d_i/truncated").random(int(bad.sum()))
    np.testing.assert_array_equal(values["d_i"][bad], d._ppf_trunc(u, 0.0, np.inf))


def test_chunk_size_and_threads_do_not_change_the_draws(monkeypatch):
    kw = table4_case("slag", 0.52)
    kw["uncertain"] = {**kw["uncertain"], "h0_i": Uniform(-0.2, 0.8, units="um"),
                       "theta_deg": Normal(10.0, 30.0), "mu_l": LogNormal(10.0, 20.0, hi=40.0)}
    n = 70_001
    ref, ref_k, _ = draw_inputs(kw["uncertain"], n, 8)
    assert min(ref_k[k] for k in ("h0_i", "theta_deg", "mu_l")) > 0
    monkeypatch.setattr(sampling, "_draw_threads", lambda: 4)
    runs = [monte_carlo(**kw, n=n, seed=8, chunk_size=c) for c in (n, 40_000, 4_567)]
    monkeypatch.setattr(sampling, "_THREADED_MIN", 10**9)  # every chunk in one thread
    runs.append(monte_carlo(**kw, n=n, seed=8))
    for ds in runs:
        for name, x in ref.items():
            assert ds[name].values.tobytes() == x.tobytes(), name
            assert ds[name].attrs["n_resampled"] == ref_k[name]
        np.testing.assert_array_equal(ds.e_w.values, runs[0].e_w.values)


@pytest.mark.parametrize("chunk", [999, 200_000])
def test_truncated_laws_hold_on_every_path(chunk):
    """KS (DKW bound), bounds and moments against scipy's truncated laws, for draws mostly
    replaced (a normal diameter with sd = mean: 15.9 % replaced; a contact angle N(10, 30)
    on [0, 90): 37.5 %) and a truncated lognormal, chunked and threaded."""
    n = 200_000
    kw = table4_case("water", 0.52)
    kw["uncertain"] = {"d_i": Normal(1e-3, 1e-3), "theta_deg": Normal(10.0, 30.0),
                       "mu_l": LogNormal(1e-3, 1e-3, lo=5e-4, hi=3e-3)}
    ds = monte_carlo(**kw, n=n, seed=31, chunk_size=chunk)
    laws = {
        "d_i": st.truncnorm(-1.0, np.inf, loc=1e-3, scale=1e-3),
        "theta_deg": st.truncnorm(-10.0 / 30.0, 80.0 / 30.0, loc=10.0, scale=30.0),
    }
    m, s = LogNormal(1e-3, 1e-3).log_params
    laws["mu_l"] = st.truncnorm((math.log(5e-4) - m) / s, (math.log(3e-3) - m) / s,
                                loc=m, scale=s)
    for name, law in laws.items():
        x = ds[name].values
        if name == "mu_l":
            assert x.min() >= 5e-4 and x.max() <= 3e-3
            x = np.log(x)
        elif name == "d_i":
            assert x.min() > 0.0
        else:
            assert x.min() >= 0.0 and x.max() < 90.0
        assert ks_sup(x, law.cdf) < dkw_eps(n), name
        # 6 standard errors: of the mean, and of the variance (relative standard error
        # sqrt((excess kurtosis + 2) / n))
        assert abs(x.mean() - law.mean()) < 6.0 * law.std() / math.sqrt(n), name
        kurt = float(law.stats(moments="k"))
        assert abs(x.var() / law.var() - 1.0) < 6.0 * math.sqrt((kurt + 2.0) / n), name
    p = st.norm.cdf(-1.0)
    k = ds["d_i"].attrs["n_resampled"]
    assert abs(k - n * p) < 6.0 * math.sqrt(n * p * (1.0 - p))


# --- the summary ---------------------------------------------------------------------------

Q = np.array([0.0, 0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9, 0.95, 0.99, 1.0])


def assert_summary_is_numpys(x, q, edges):
    fast = summary_counts(x, q, edges)
    assert fast is not None
    n_zero, counts, quant = fast
    assert n_zero == np.count_nonzero(x == 0.0)
    np.testing.assert_array_equal(counts, np.histogram(x[x > 0.0], bins=edges)[0])
    assert quant.tobytes() == np.quantile(x, q).tobytes()


def test_summary_equals_numpy_on_a_run_with_a_point_mass():
    ds = monte_carlo(**table4_case("water", 0.20), n=100_000, seed=4)
    x = ds.e_w.values
    assert 0.1 < float(ds.p_agglomeration) < 0.9
    edges = ds.e_w_bin_bounds.values
    edges = np.append(edges[:, 0], edges[-1, 1])
    assert_summary_is_numpys(x, Q, edges)
    # a bin too narrow for sub-buckets (its inverse width overflows), values on its edges
    y = np.concatenate([x, [1e-320, 5e-321, 0.5, 1.0]])
    assert_summary_is_numpys(y, Q, np.array([0.0, 1e-320, 0.5, 1.0]))


@settings(max_examples=60, deadline=None)
@given(
    n=hs.integers(1, 3000),
    p_zero=hs.floats(0.0, 1.0),
    bins=hs.one_of(hs.integers(1, 300), hs.integers(3000, 40_000)),  # 16 to 1 sub-buckets
    ties=hs.booleans(),
    on_edges=hs.booleans(),
    log_edges=hs.booleans(),
    seed=hs.integers(0, 2**32 - 1),
    q=hs.lists(hs.floats(0.0, 1.0), min_size=1, max_size=12),
)
def test_summary_equals_numpy(n, p_zero, bins, ties, on_edges, log_edges, seed, q):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0.0, 0.9, n)
    if ties:
        x = np.round(x, 2)
    edges = (np.geomspace(1e-3, 1.0, bins + 1) if log_edges
             else np.linspace(0.0, 0.9, bins + 1))
    if on_edges:  # values exactly on edges, the last edge included
        x[: n // 3] = rng.choice(edges, n // 3)
    x[rng.random(n) < p_zero] = 0.0
    q = np.array(q)
    fast = summary_counts(x, q, edges)
    if fast is None:  # the wanted buckets were too full: numpy's path
        return
    n_zero, counts, quant = fast
    assert n_zero == np.count_nonzero(x == 0.0)
    np.testing.assert_array_equal(counts, np.histogram(x[x > 0.0], bins=edges)[0])
    assert quant.tobytes() == np.quantile(x, q).tobytes()


def test_summary_falls_back_to_numpy_where_it_does_not_apply(monkeypatch):
    rng = np.random.default_rng(0)
    edges = np.linspace(0.0, 1.0, 11)
    x = rng.uniform(0.0, 1.0, 10_000)
    assert summary_counts(np.append(x, -1e-3), Q, edges) is None  # a negative sample
    assert summary_counts(np.append(x, np.nan), Q, edges) is None  # NaN
    assert summary_counts(np.full(200_000, 0.5), Q, edges) is None  # one bucket holds all
    assert summary_counts(x, Q, np.array([0.0, 1.0, np.inf])) is None
    for y in (np.append(x, -1e-3), np.full(200_000, 0.5)):
        n_zero, counts, quant = summary_numpy(y.copy(), Q, edges, 3_000, scratch=True)
        np.testing.assert_array_equal(counts, np.histogram(y[y > 0.0], bins=edges)[0])
        assert quant.tobytes() == np.quantile(y, Q).tobytes()
    # a run summarised by numpy reports the same numbers
    kw = table4_case("water", 0.20)
    fast = monte_carlo(**kw, n=20_000, seed=2, keep_samples=False)
    monkeypatch.setattr(sampling, "summary_counts", lambda *args: None)
    slow = monte_carlo(**kw, n=20_000, seed=2, keep_samples=False)
    for name in ("p_agglomeration", "e_w_mean", "e_w_std", "e_w_quantile", "e_w_density"):
        assert fast[name].values.tobytes() == slow[name].values.tobytes(), name
