"""The sampling and the summary shared by both Monte Carlo paths: the core's inputs
(:mod:`.monte_carlo`) and a Scene's fields (:mod:`.scene_mc`).

Both paths draw their uncertain inputs with :class:`_ChunkedDraws` (one set of random
streams per input, derived from the seed and the input's name), and summarise ``e_w`` with
:func:`_summary`. They live here, below both, so that neither Monte Carlo module imports
the other's internals.
"""

from __future__ import annotations

import zlib
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from typing import cast

import numba
import numpy as np
import xarray as xr

from ._inputs import UNCERTAIN_INPUTS, check_names
from ._select import summary_counts, summary_numpy
from .distributions import Distribution, _replace_outside, to_si

_DIMLESS = "dimensionless"

#: How the draws are made (recorded in every result; see :class:`_ChunkedDraws`).
_SAMPLING = ("numpy PCG64, one stream per input: SeedSequence(seed, spawn_key=(crc32(name),)) "
             "for the first draws; draws outside the input's range replaced through the "
             "truncated inverse CDF of uniforms from the stream of name + '/truncated'")


def resolve_seed(seed) -> tuple[int, bool]:
    """The integer entropy behind ``seed`` and whether the caller chose it.

    ``None`` draws fresh entropy (63 bits) from the operating system; it is recorded in the
    result so that the run can be repeated.
    """
    if seed is None:
        return int(cast(int, np.random.SeedSequence().entropy)) % 2**63, False
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or not (
        0 <= seed < 2**63
    ):
        raise ValueError(f"seed = {seed!r} must be an integer in [0, 2**63) or None")
    return int(seed), True


def _stream(entropy: int, name: str) -> np.random.Generator:
    """An independent generator per input name: adding, removing or reordering other
    uncertain inputs leaves this input's draws unchanged (common random numbers)."""
    key = zlib.crc32(name.encode("utf-8"))
    return np.random.default_rng(np.random.SeedSequence(entropy, spawn_key=(key,)))


def _core_law(name: str, dist: Distribution):
    """The SI law and range of the core input ``name`` (see :class:`_ChunkedDraws`)."""
    spec = UNCERTAIN_INPUTS[name]
    return (to_si(name, dist, spec.units), spec.lo, spec.hi, spec.lo_open, spec.hi_open,
            spec.range_text())


#: Below this many values per chunk and input the draws are made in the calling thread
#: (a thread hand-off costs more than it saves on small arrays).
_THREADED_MIN = 1 << 15


def _draw_threads() -> int:
    """Threads drawing the inputs of a chunk: as many as the compiled kernels use."""
    return max(1, numba.get_num_threads())


class _ChunkedDraws:
    """The draws of the uncertain inputs, made one chunk at a time (bounded memory).

    Every input has three streams of its own, derived from the seed and the input's stream
    name (:func:`_stream`): ``name`` gives the first draws (one per sample, in sample
    order); ``name + "/truncated"`` the uniforms that replace, through the inverse CDF of
    the law truncated to the input's range, the first draws that fell outside it (in sample
    order); ``name + "/open-bound"`` those that replace a replacement landing exactly on an
    open bound (an event of probability zero). Each stream is read once, front to back, so
    the values do not depend on the chunk size, and the chunks hold exactly the values
    :func:`draw_inputs` returns.

    The inputs of a chunk are drawn concurrently, one thread per input up to
    ``numba.get_num_threads()`` (numpy's generators release the GIL); each thread reads only
    its own input's streams, so the values do not depend on the threads either.

    Changed after agglomtool 0.1.0: there, the replacements were read from the first-draw
    stream after its ``n`` first draws, which took a counting pass: every input was drawn
    twice. Inputs with no draw outside their range (e.g. the
    paper's Table 4 analyses) give bitwise the same values as before; the replaced draws of
    the others differ (same law, other random numbers).
    """

    def __init__(self, uncertain: Mapping[str, Distribution], n: int, entropy: int,
                 chunk: int, law=None, stream_name=None):
        """``law(name, dist)`` gives ``(dist in SI, lo, hi, lo_open, hi_open, range text)``
        (default: the core's inputs, :data:`UNCERTAIN_INPUTS`); ``stream_name(name)`` the
        name of its random stream (default: ``name``)."""
        if law is None:
            check_names(uncertain)
            law = _core_law
        self.stream_name = stream_name or (lambda name: name)
        self.n, self.chunk, self.entropy = n, chunk, entropy
        self.dists, self._spec = {}, {}
        #: name -> how many first draws fell outside the range (complete once every chunk
        #: has been drawn)
        self.resampled: dict[str, int] = {}
        for name, dist in uncertain.items():
            d_si, lo0, hi0, lo_open, hi_open, text = law(name, dist)
            try:
                lo, hi = d_si._effective_bounds(lo0, hi0)
            except ValueError as exc:
                raise ValueError(f"uncertain[{name!r}] ({text}): {exc}") from None
            self.dists[name], self.resampled[name] = d_si, 0
            self._spec[name] = (lo, hi, lo_open, hi_open)

    def __iter__(self):
        return self.chunks()

    def chunks(self, out: Mapping[str, np.ndarray] | None = None):
        """``(slice, {name: SI values})`` of every chunk, in order.

        With ``out`` (name -> float64 array of ``n`` values) the values are drawn into
        ``out[name][slice]`` and the chunk's arrays are those views; without, into buffers
        of one chunk that the next chunk overwrites.
        """
        key = self.stream_name
        names = list(self.dists)
        streams = {name: tuple(_stream(self.entropy, key(name) + tail)
                               for tail in ("", "/truncated", "/open-bound"))
                   for name in names}
        for name in names:
            self.resampled[name] = 0
        buffers = {} if out is not None else {name: np.empty(self.chunk) for name in names}

        def draw(name, x):
            d = self.dists[name]
            first, trunc, again = streams[name]
            d._draw_into(first, x)
            lo, hi, lo_open, hi_open = self._spec[name]
            return _replace_outside(d, x, lo, hi, lo_open, hi_open, trunc, again)

        workers = min(len(names), _draw_threads())
        pool = (ThreadPoolExecutor(max_workers=workers)
                if workers > 1 and self.chunk >= _THREADED_MIN else None)
        try:
            for start in range(0, self.n, self.chunk):
                sl = slice(start, min(start + self.chunk, self.n))
                m = sl.stop - sl.start
                if out is not None:
                    vals = {name: out[name][sl] for name in names}
                else:
                    vals = {name: buffers[name][:m] for name in names}
                if pool is None or m < _THREADED_MIN:
                    bad = [draw(name, vals[name]) for name in names]
                else:
                    bad = list(pool.map(draw, names, [vals[name] for name in names]))
                for name, k in zip(names, bad, strict=True):
                    self.resampled[name] += k
                yield sl, vals
        finally:
            if pool is not None:
                pool.shutdown()


def _attrs(units: str, long_name: str, **extra) -> dict:
    return {"units": units, "long_name": long_name, **extra}


def _summary(e_w: np.ndarray, q: np.ndarray, edges: np.ndarray, e_w_nominal: float,
             chunk: int, scratch: bool = False):
    """The summary of ``e_w``, with temporaries of at most ``chunk`` samples.

    Quantiles, histogram and agglomeration count in two passes without a sort
    (:func:`._select.summary_counts`; numpy's numbers, bitwise), else with numpy, where
    ``scratch=True`` lets the quantiles reorder ``e_w`` in place (no copy of it).
    """
    n = e_w.size
    fast = summary_counts(e_w, q, edges)
    n_zero, counts, quantiles = (fast if fast is not None
                                 else summary_numpy(e_w, q, edges, chunk, scratch))
    p_agg = float(n_zero) / n
    dens = counts / (n * np.diff(edges))
    mean = float(e_w.mean())
    ssd = sum(float(np.sum(np.square(e_w[s:s + chunk] - mean))) for s in range(0, n, chunk))
    std = float(np.sqrt(ssd / (n - 1))) if n > 1 else 0.0
    centres = 0.5 * (edges[:-1] + edges[1:])
    ds = xr.Dataset(
        coords={
            "quantile": ("quantile", q, _attrs(_DIMLESS, "probability level")),
            "e_w_bin": ("e_w_bin", centres, _attrs(
                _DIMLESS, "e_w histogram bin centre", bounds="e_w_bin_bounds")),
        }
    )
    ds["e_w_bin_bounds"] = (("e_w_bin", "bound"), np.stack([edges[:-1], edges[1:]], axis=1),
                            _attrs(_DIMLESS, "e_w histogram bin edges"))
    ds["p_agglomeration"] = ((), p_agg, _attrs(_DIMLESS, "probability of agglomeration "
                                               "P(e_w = 0)"))
    ds["p_agglomeration_se"] = ((), float(np.sqrt(p_agg * (1.0 - p_agg) / n)),
                                _attrs(_DIMLESS, "binomial standard error of "
                                       "p_agglomeration"))
    ds["e_w_mean"] = ((), mean, _attrs(_DIMLESS, "mean of e_w"))
    ds["e_w_std"] = ((), std, _attrs(_DIMLESS, "standard deviation of e_w"))
    ds["e_w_nominal"] = ((), e_w_nominal, _attrs(
        _DIMLESS, "e_w at the nominal inputs (point estimate)"))
    ds["e_w_quantile"] = ("quantile", quantiles, _attrs(_DIMLESS, "quantile of e_w"))
    ds["e_w_density"] = ("e_w_bin", dens, _attrs(
        _DIMLESS, "probability density of rebounding e_w (histogram); integrates to "
        "1 - p_agglomeration"))
    return ds
