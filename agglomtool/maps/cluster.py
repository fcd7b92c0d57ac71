"""Sweeps on a dask.distributed cluster: one task per block, each writing its own region.

The collision kernel is compiled with Numba and parallel inside one process, and its
threading layer does not allow calls from several threads at once; so a block is computed
with dask's synchronous scheduler inside one worker, and a cluster for sweeps should have
process workers with one thread each, e.g. ``LocalCluster(processes=True,
threads_per_worker=1)`` or ``dask worker SCHEDULER --nthreads 1 --nworkers N``.

The client submits the blocks a few at a time (two to four per worker thread, a batch at
a time), so neither it nor the scheduler ever holds more than those in flight: a
store-backed sweep of any size runs with bounded memory on the client, which keeps only
each block's small completion record (its checksums).
"""

from __future__ import annotations

import itertools
import os
import uuid

import numpy as np
import xarray as xr

__all__ = ["run_blocks", "compute_on_cluster", "NoWorkersError", "WORKER_TIMEOUT"]


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


#: Seconds a cluster run waits with no live worker before it fails (:class:`NoWorkersError`);
#: the environment variable ``AGGLOMTOOL_WORKER_TIMEOUT`` sets another.
WORKER_TIMEOUT = 60.0
TIMEOUT_VAR = "AGGLOMTOOL_WORKER_TIMEOUT"


def _worker_timeout() -> float:
    text = os.environ.get(TIMEOUT_VAR)
    if text is None:
        return WORKER_TIMEOUT
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < 1e6:
        raise ValueError(f"{TIMEOUT_VAR} = {text!r} must be a number of seconds in (0, 1e6)")
    return value


class NoWorkersError(RuntimeError):
    """A cluster run had no live worker for :data:`WORKER_TIMEOUT` seconds."""


def _workers(client) -> int:
    try:
        return len(client.scheduler_info()["workers"])
    except Exception:  # noqa: BLE001 - a scheduler that cannot answer has no usable worker
        return 0


def _same(value):
    """The value itself: a task that holds ``shared`` on the workers (:func:`run_blocks`)."""
    return value


def run_blocks(client, todo, task, func, done, *, in_flight: int | None = None,
               worker_timeout: float | None = None, shared=None) -> None:
    """Run ``func(*task(idx, sl))`` for every block of ``todo`` on the workers of ``client``
    (``func(shared, *task(idx, sl))`` where ``shared`` is given).

    Blocks are submitted in batches (one ``client.map`` each), between ``in_flight`` and
    twice as many at a time, and their results are collected as they finish
    (``distributed.as_completed``): the scheduler takes one message per batch, not one per
    block, and the client makes no round trip of its own per block.

    Parameters
    ----------
    client : distributed.Client
    todo : iterable of (tuple, dict)
        Block index and ``{dim: slice}`` of every block to run.
    task : callable
        ``task(idx, sl)`` -> the arguments of ``func`` for one block (built on the client).
    func : callable
        Runs on a worker; its result is passed to ``done``.
    done : callable
        ``done(idx, result)``, called on the client as each block finishes.
    in_flight : int, optional
        Blocks submitted at once (default: twice the workers' threads, at least 2); up to
        twice as many are in flight.
    worker_timeout : float, optional
        Seconds without a live worker after which the run fails with
        :class:`NoWorkersError` (default: ``AGGLOMTOOL_WORKER_TIMEOUT``, else
        :data:`WORKER_TIMEOUT`).
    shared : object, optional
        The first argument of every block (the sweep's plan): sent to the cluster once, as
        one task's result that every block depends on, instead of once per block; a worker
        then holds one copy, with its caches, for all its blocks.

    Raises
    ------
    NoWorkersError
        When the cluster has had no live worker for ``worker_timeout`` seconds.
    Exception
        An error raised on a worker, as the worker raised it (its type and message).
    """
    import time

    from distributed import as_completed

    timeout = _worker_timeout() if worker_timeout is None else float(worker_timeout)
    limit = in_flight or max(2, 2 * _threads(client))
    pending = iter(todo)
    index: dict = {}  # key -> (future, idx) of every block in flight
    run = uuid.uuid4().hex[:12]
    held = [] if shared is None else [client.submit(_same, shared, pure=False,
                                                     key=f"agglomtool-shared-{run}")]
    finished = as_completed(with_results=True)

    def submit(n: int) -> int:
        batch = list(itertools.islice(pending, n))
        if not batch:
            return 0
        columns = list(zip(*(task(idx, sl) for idx, sl in batch), strict=True))
        keys = [f"agglomtool-block-{run}-{'-'.join(map(str, idx))}" for idx, _ in batch]
        first = [held * len(batch)] if held else []  # the shared task's future, each block
        futures = client.map(func, *first, *columns, key=keys, pure=False)
        for fut, (idx, _) in zip(futures, batch, strict=True):
            index[fut.key] = fut, idx
        finished.update(futures)
        return len(batch)

    live = submit(2 * limit)
    alone_since = None  # when the cluster was last seen without a worker
    try:
        while live:
            ready = []
            while finished.has_ready():  # a worker's error is raised here, as it was raised
                ready.append(next(finished))
            if not ready:
                with finished.thread_condition:
                    if not finished.has_ready():
                        finished.thread_condition.wait(timeout=min(1.0, timeout))
                if finished.has_ready() or _workers(client):
                    alone_since = None
                    continue
                now = time.monotonic()
                alone_since = alone_since or now
                if now - alone_since >= timeout:
                    raise NoWorkersError(
                        f"the dask cluster {_address(client)} has had no live worker for "
                        f"{timeout:g} s, with {len(index)} block(s) waiting; start workers "
                        "(dask worker SCHEDULER_ADDRESS --nthreads 1) and run again "
                        "(finished blocks of a store are reused), or run without a cluster")
                continue
            alone_since = None
            for fut, result in ready:
                done(index.pop(fut.key)[1], result)
            live -= len(ready)
            del ready
            if live <= limit:
                live += submit(2 * limit - live)
    except BaseException:
        for fut, _ in list(index.values()):  # a copy: cancelling changes what is pending
            fut.cancel()
        raise
    finally:
        for fut in held:
            fut.release()


def _address(client) -> str:
    try:
        return str(client.scheduler.address)
    except Exception:  # noqa: BLE001 - only for the message
        return "(its scheduler)"


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
        return sl, plan.owned(idx)

    with SweepBar(plan.points, plan.n_blocks, "sweep", progress) as bar:

        def done(idx, values):
            sl = plan.block_slices(idx)
            for name, a in values.items():
                out[name][tuple(sl[d] for d in plan.variables[name][0])] = a
            bar.update(plan.block_points(sl))

        run_blocks(client, plan.blocks(), task, _compute_block, done, shared=plan)
    return out
