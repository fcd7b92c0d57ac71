"""Sweeps on a dask.distributed cluster: one task per block, each writing its own region.

The collision kernel is compiled with Numba and parallel inside one process, and its
threading layer does not allow calls from several threads at once; so a block is computed
with dask's synchronous scheduler inside one worker, and a cluster for sweeps should have
process workers with one thread each, e.g. ``LocalCluster(processes=True,
threads_per_worker=1)`` or ``dask worker SCHEDULER --nthreads 1 --nworkers N``.

The client submits the blocks a few at a time (about two per worker thread), so neither
it nor the scheduler ever holds more than those in flight: a store-backed sweep of any size
runs with bounded memory on the client, which keeps only each block's small completion
record (its checksums).
"""

from __future__ import annotations

import itertools
import uuid

import numpy as np
import xarray as xr

__all__ = ["run_blocks", "compute_on_cluster"]


def _blocks(chunks: dict):
    """(index tuple, {dim: slice}) of every block, in C order."""
    dims = list(chunks)
    starts = {d: np.concatenate([[0], np.cumsum(chunks[d])]) for d in dims}
    for idx in itertools.product(*[range(len(chunks[d])) for d in dims]):
        sl = {d: slice(int(starts[d][i]), int(starts[d][i + 1]))
              for d, i in zip(dims, idx, strict=True)}
        yield idx, sl


def _owned(var_dims: dict, dims: list, idx: tuple) -> list:
    """Variables block ``idx`` writes: those over whose missing dimensions it is first."""
    at = dict(zip(dims, idx, strict=True))
    return [v for v, vd in var_dims.items() if all(at[d] == 0 for d in dims if d not in vd)]


def _threads(client) -> int:
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # noqa: BLE001 - a client that cannot say: assume one
        return 1


def run_blocks(client, todo, task, func, done, *, in_flight: int | None = None) -> None:
    """Run ``func(*task(idx, sl))`` for every block of ``todo`` on the workers of ``client``.

    Parameters
    ----------
    client : distributed.Client
    todo : list of (tuple, dict)
        Block index and ``{dim: slice}`` of every block to run.
    task : callable
        ``task(idx, sl)`` -> the arguments of ``func`` for one block (built on the client).
    func : callable
        Runs on a worker; its result is passed to ``done``.
    done : callable
        ``done(idx, result)``, called on the client as each block finishes.
    in_flight : int, optional
        Blocks submitted at once (default: twice the workers' threads, at least 2).
    """
    from distributed import as_completed

    limit = in_flight or max(2, 2 * _threads(client))
    pending = iter(todo)
    index = {}
    run = uuid.uuid4().hex[:12]

    def submit():
        for idx, sl in pending:
            fut = client.submit(func, *task(idx, sl), pure=False,
                                key=f"agglomtool-block-{run}-{'-'.join(map(str, idx))}")
            index[fut.key] = idx
            return fut
        return None

    first = [f for f in (submit() for _ in range(limit)) if f is not None]
    queue = as_completed(first)
    try:
        for fut in queue:
            result = fut.result()  # a worker's error is raised here, as the worker raised it
            done(index.pop(fut.key), result)
            fut.release()
            nxt = submit()
            if nxt is not None:
                queue.add(nxt)
    except BaseException:
        for fut in queue.futures:
            fut.cancel()
        raise


def _compute_block(plan, sl: dict, owned: list) -> dict:
    """One block's values (numpy), computed on a worker."""
    return plan.evaluate(sl, owned)


def compute_on_cluster(ds: xr.Dataset, client) -> xr.Dataset:
    """Compute the lazy sweep ``ds`` block by block on the workers; return it in memory.

    Every value is computed once, on a worker; the client gathers the blocks into one
    in-memory Dataset (use ``store=`` for maps larger than the client's memory).
    """
    from .plan import SweepPlan, _dataset

    plan = SweepPlan.from_dataset(ds)
    return _dataset(plan, _compute_plan(plan, client, False))


def _compute_plan(plan, client, progress: bool) -> dict:
    """``{name: numpy array}`` of the sweep ``plan``, its blocks computed on the workers."""
    from .progress import SweepBar

    out = {k: np.empty(plan.var_shape(k), dtype=plan.variables[k][1])
           for k in plan.lazy_names}

    def task(idx, sl):
        return plan, sl, plan.owned(idx)

    with SweepBar(plan.points, plan.n_blocks, "sweep", progress) as bar:

        def done(idx, values):
            sl = plan.block_slices(idx)
            for name, a in values.items():
                out[name][tuple(sl[d] for d in plan.variables[name][0])] = a
            bar.update(plan.block_points(sl))

        run_blocks(client, plan.blocks(), task, _compute_block, done)
    return out
