"""The summary of a Monte Carlo run in two passes over ``e_w``: exact quantiles, the
histogram of the rebounding part and the agglomeration count, without sorting or copying
the samples.

The first pass gives every sample a *bucket*: 0 for an exact zero (the point mass of
agglomeration); for a positive value, its histogram bin (found by comparisons with the
edges, as numpy does) split into ``SUB`` equal sub-buckets. Buckets are ordered as the
values are, so their cumulative counts tell in which bucket the sample of any rank lies;
the histogram is read off the same counts. The second pass copies the samples of the few
buckets that hold a wanted rank into one small buffer (typically under 1 % of the
samples), where they are sorted. Quantiles are then interpolated exactly as :func:`numpy.quantile`
(``method="linear"``, Hyndman and Fan's type 7) does, so the numbers are numpy's, bitwise.

A run this does not fit (a negative or NaN sample, non-finite edges, or wanted buckets
holding more than max(n / 16, 65536) samples) is summarised with numpy instead
(:func:`summary_numpy`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .._jit import CACHE

__all__ = ["summary_counts", "summary_numpy", "linear_quantiles"]


@njit(cache=CACHE)
def _scan(x, edges, e0, inv_w, nb, uniform, sub, inv_bw, gather, slot, pos, buf):
    """One pass over ``x``. Every sample's bucket: 0 for ``x == 0``; for ``x > 0``,
    ``1 + j sub + s`` with ``j`` the number of edges <= x and ``s`` in ``[0, sub)`` its
    sub-bucket inside bin ``j - 1`` (0 below the first and above the last edge); the
    bucket is non-decreasing in ``x``. Negative and NaN samples are counted apart.

    ``gather=False``: returns the bucket counts, the number of positive samples equal to
    the last edge and the number of negative or NaN ones. ``gather=True``: copies the
    samples of the buckets with ``slot[k] >= 0`` to ``buf[pos[slot[k]]]`` (advancing
    ``pos``). (The bucket is computed inline: a helper function taking the arrays costs
    five times the pass.)
    """
    counts = np.zeros(1 if gather else 1 + (nb + 2) * sub, np.int64)
    n_last = 0
    n_bad = 0
    last = edges[nb]
    for i in range(x.size):
        v = x[i]
        if v == 0.0:
            k = 0
        elif not v > 0.0:
            n_bad += 1
            continue
        else:
            if uniform:  # a guess from the bin width, then made exact against the edges
                g = (v - e0) * inv_w
                if g < 0.0:
                    j = 0
                elif g > nb:
                    j = nb + 1
                else:
                    j = int(g) + 1
                while j > 0 and edges[j - 1] > v:
                    j -= 1
                while j <= nb and edges[j] <= v:
                    j += 1
            else:  # bisection: the number of edges <= v
                j, hi = 0, nb + 1
                while j < hi:
                    mid = (j + hi) // 2
                    if edges[mid] <= v:
                        j = mid + 1
                    else:
                        hi = mid
            s = 0
            if sub > 1 and j >= 1 and j <= nb:  # v in [edges[j - 1], edges[j])
                t = (v - edges[j - 1]) * inv_bw[j - 1]
                s = int(t) if t < sub - 1 else sub - 1
            k = 1 + j * sub + s
        if gather:
            q = slot[k]
            if q >= 0:
                buf[pos[q]] = v
                pos[q] += 1
        else:
            counts[k] += 1
            if k > 0 and v == last:
                n_last += 1
    return counts, n_last, n_bad


#: Sub-buckets per histogram bin (fewer when there are many bins): the samples copied and
#: sorted for the quantiles are those of at most two sub-buckets per quantile.
SUB = 16


def _edge_args(edges: np.ndarray):
    nb = edges.size - 1
    e0, e1 = float(edges[0]), float(edges[-1])
    uniform = bool(np.array_equal(edges, np.linspace(e0, e1, nb + 1)))
    sub = max(1, min(SUB, (1 << 16) // (nb + 2)))
    with np.errstate(over="ignore", divide="ignore"):
        inv_bw = sub / np.diff(edges)
    if not np.all(np.isfinite(inv_bw)):
        sub = 1
    return edges, e0, nb / (e1 - e0), nb, uniform, sub, inv_bw


def linear_ranks(n: int, q: np.ndarray):
    """The ranks (0-based) below and above each quantile level and the weights, as
    :func:`numpy.quantile` computes them (``method="linear"``)."""
    v = (n - 1) * q
    prev = np.floor(v)
    nxt = prev + 1.0
    above = v >= n - 1
    prev[above] = n - 1
    nxt[above] = n - 1
    gamma = v - np.where(above, -1.0, prev)  # numpy's weight there (its index is -1)
    return prev.astype(np.intp), np.minimum(nxt, n - 1).astype(np.intp), gamma


def linear_quantiles(a: np.ndarray, b: np.ndarray, gamma: np.ndarray) -> np.ndarray:
    """numpy's linear interpolation between the order statistics ``a`` and ``b``."""
    diff = b - a
    out = a + diff * gamma
    np.subtract(b, diff * (1.0 - gamma), out=out, where=gamma >= 0.5)
    return out


def summary_counts(e_w: np.ndarray, q: np.ndarray, edges: np.ndarray):
    """``(n_zero, histogram counts of the positive samples, quantiles)`` of ``e_w``, or
    ``None`` where the two-pass method does not apply (module docstring).

    The counts equal ``numpy.histogram(e_w[e_w > 0], edges)[0]`` and the quantiles
    ``numpy.quantile(e_w, q)``.
    """
    n = e_w.size
    if n == 0 or not np.all(np.isfinite(edges)):
        return None
    x = np.ascontiguousarray(e_w, dtype=np.float64)
    args = _edge_args(np.ascontiguousarray(edges, dtype=np.float64))
    if not math.isfinite(args[2]):
        return None
    none = np.empty(0, dtype=np.intp)
    counts, n_last, n_bad = _scan(x, *args, False, none, none, np.empty(0))
    if n_bad:
        return None
    nb, sub = args[3], args[5]
    # bucket 1 + j sub + s with j = b + 1: edges[b] <= x < edges[b + 1]
    hist = counts[1 + sub:1 + (nb + 1) * sub].reshape(nb, sub).sum(axis=1)
    hist[-1] += n_last  # numpy's last bin is closed
    prev, nxt, gamma = linear_ranks(n, q)
    ranks = np.unique(np.concatenate([prev, nxt]))
    cum = np.cumsum(counts)
    keys = np.searchsorted(cum, ranks, side="right")  # the bucket of each rank
    wanted = np.unique(keys[keys > 0])
    sizes = counts[wanted]
    if sizes.sum() > max(n // 16, 1 << 16):
        return None
    slot = np.full(counts.size, -1, dtype=np.intp)
    slot[wanted] = np.arange(wanted.size)
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.intp)
    buf = np.empty(int(sizes.sum()))
    _scan(x, *args, True, slot, start.copy(), buf)
    for s in range(wanted.size):
        buf[start[s]:start[s] + sizes[s]].sort()
    value = {}
    for r, k in zip(ranks.tolist(), keys.tolist(), strict=True):
        if k == 0:
            value[r] = 0.0
        else:
            s = slot[k]
            value[r] = buf[start[s] + r - (cum[k] - counts[k])]
    a = np.array([value[r] for r in prev.tolist()], dtype=np.float64)
    b = np.array([value[r] for r in nxt.tolist()], dtype=np.float64)
    return int(counts[0]), hist, linear_quantiles(a, b, gamma)


def summary_numpy(e_w: np.ndarray, q: np.ndarray, edges: np.ndarray, chunk: int,
                  scratch: bool):
    """The same triple with numpy, temporaries of at most ``chunk`` samples
    (``scratch=True`` lets the quantiles reorder ``e_w`` in place)."""
    n = e_w.size
    parts = [slice(s, min(s + chunk, n)) for s in range(0, n, chunk)]
    n_zero = sum(int(np.count_nonzero(e_w[sl] == 0.0)) for sl in parts)
    counts = np.zeros(edges.size - 1, dtype=np.int64)
    for sl in parts:
        x = e_w[sl]
        counts += np.histogram(x[x > 0.0], bins=edges)[0]
    return n_zero, counts, np.quantile(e_w, q, overwrite_input=scratch)
