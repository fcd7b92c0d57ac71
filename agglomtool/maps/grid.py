"""Sweeps: a scene evaluated over a grid of its fields, as an ``xarray.Dataset``.

The grid is cut into blocks and every block is evaluated on its own slice of the
coordinates (:class:`agglomtool.maps.plan.SweepPlan`): in memory, into a store, on a
cluster's workers, or as the tasks of the lazy Dataset of :func:`build`. Outputs are
computed in groups, each over the dimensions it depends on only: gas properties over (T, P),
``u0*`` over every field except the impact-speed ones, the collisions over the whole grid.
``u0*`` is the expensive part (about 1e5 solves/s), so a grid whose speed axes are long is
cheap. Before it starts, a sweep says what it will take (:mod:`agglomtool.maps.estimate`)
and refuses an in-memory result larger than the memory available.
"""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr
from numba import njit, prange

from .._jit import CACHE, parallel_launch
from ..scene import (
    Scene,
)
from .layout import (  # noqa: F401  (re-exported: the sweep's layout, as before)
    _ALL,
    DEFAULT_BLOCK,
    GROUPS,
    SPEED_FIELDS,
    GridError,
    _block_function,
    _chunks,
    _dataset_attrs,
    _first_point,
    _grid_values,
    grid_findings,
    sweep_chunks,
)
from .plan import _dataset, _lazy_arrays, _plan, build  # noqa: F401  (re-exported)

__all__ = ["sweep", "build", "GROUPS", "DEFAULT_BLOCK", "GridError", "grid_findings"]

logger = logging.getLogger("agglomtool.maps")


def sweep(scene: Scene, *, chunks="auto", nodes: int = 16, store=None, progress=False,
          compute: bool = True, overwrite: bool = False, client=None, uncertain=None,
          samples: int = 256, threshold: float = 0.5, seed: int | None = 0,
          **grid) -> xr.Dataset:
    """Evaluate ``scene`` over a grid of its fields.

    Parameters
    ----------
    scene : Scene
        The operating point; fields not in ``grid`` keep its values.
    chunks : "auto", int, dict or None
        Block size: ``"auto"`` (about 2.6e5 points per block of a store, a cluster or a
        lazy map; a map computed in memory here takes blocks of about 1e6 points, larger
        on 8 or more threads: ``auto_block`` of ``agglomtool.maps.layout``), a number of
        points per block, a ``{dim: size}`` dict,
        or ``None`` (one block per category combination).
        Dimensions holding names (solids, liquid, gas, mode, ...) are always chunked by 1.
    nodes : int
        Quadrature nodes of the impact-speed distribution for the propensity.
    store : path, optional
        A directory holding a resumable zarr store of the sweep
        (:mod:`agglomtool.maps.store`): every finished block is written to it with a
        checksum and a completion record, and a sweep run again with the same store checks
        and reuses them, recomputing any block that is missing or damaged. The store records
        a fingerprint of the sweep (scene, grid, chunks, nodes, materials files, version); a
        different sweep is refused with a ValueError saying what differs. Only one process
        writes a store at a time. The result is opened lazily from the store (bounded
        memory for grids larger than memory); :func:`agglomtool.write_map` writes one file.
    progress : bool
        Show a progress bar on stderr (tqdm): points and blocks done, rate, time left;
        and, on a first run, a line saying that the kernels are being compiled.
    compute : bool
        ``False`` returns the lazy dask-backed Dataset (ignored with ``store``).
    overwrite : bool
        With ``store``: discard a store that holds a different sweep and start again.
    client : distributed.Client or False, optional
        Run the blocks as tasks on the workers of this dask.distributed cluster. ``None``
        (the default) uses the active client if one has been created in this process, else
        computes here; ``False`` always computes here. With ``store`` each worker writes
        its blocks' regions of the store, which must then be on a file system that the
        workers and this process share; the client holds only completion records. Without
        ``store`` the blocks are gathered into one in-memory Dataset.
    uncertain : mapping or ``"assumed"``, optional
        A robust map (:mod:`agglomtool.maps.robust`): the uncertain inputs, as for
        :func:`agglomtool.monte_carlo` with a Scene (Scene field -> distribution,
        ``"assumed"`` for every value the materials database assumes, or both). The map
        then also holds, per point, ``propensity_mean``, ``propensity_quantile`` (5, 50,
        95 %), ``p_unsafe`` (the probability that the propensity exceeds ``threshold``)
        and ``undecided`` (``p_unsafe`` between 0.1 and 0.9), over ``samples`` draws that
        are the same at every point (common random numbers). Computed in memory.
    samples : int
        Draws per point of a robust map (>= 2).
    threshold : float
        The propensity above which a point of a robust map is unsafe, in [0, 1).
    seed : int or None
        Seed of a robust map's draws (the same seed gives the same draws as
        :func:`agglomtool.monte_carlo` and :func:`agglomtool.compare`).
    **grid
        ``field=values``: one dimension per field, in the order given, with the values
        as coordinates (numbers in the units of :class:`Scene`, or names).

    Returns
    -------
    xarray.Dataset
        Data variables (see :data:`agglomtool.maps.meta.VARIABLE_META`), each with
        ``units`` and ``long_name``: gas and liquid properties, ``Umf``, ``U``, ``U_e``,
        ``u_star``, ``Ca_star``, ``regime``, ``u_typical``, ``St``, ``e_w``,
        ``agglomerated``, ``stage``, ``propensity``, ``margin`` and ``speed_flag``, each
        over the grid dimensions it depends on; coded outputs (``stage``, ``regime``,
        ``u_star_flag``, ``speed_flag``, ``agglomerated``) carry CF ``flag_values`` and
        ``flag_meanings``. Where the impact-speed model has no answer (a bubble model
        beyond a bubbling bed, a bed below U_mf) ``speed_flag`` says why, the outputs made
        of the speed are NaN and the sweep warns how many points
        (:mod:`agglomtool.maps.speed_flag`); a single point raises instead. ``ds["U"]`` is
        always the superficial gas velocity: the output ``U_Umf * Umf`` where ``U`` is not
        swept, and the coordinate ``U`` where it is (the output would repeat it). Attributes
        (CF-1.8, see :mod:`agglomtool.maps.meta`) record the call (``source``), the agglomtool
        version, model tier, base scene, the provenance of every input (JSON), the database
        values that are assumptions and the materials' sources (JSON).
        :func:`agglomtool.write_map` writes it as a CF-1.8 netCDF file.

    Raises
    ------
    agglomtool.maps.estimate.SweepTooLargeError
        A :class:`ValueError`, before any work, where the result would be held in memory
        (no ``store``) and is larger than the memory available; its message gives both
        sizes. Pass ``store=`` to write the sweep block by block to disk.

    Notes
    -----
    **Before it starts** a sweep counts its points, blocks and bytes (in memory and, with
    ``store``, in the store) and, from 1e5 points on, times a sample of its own points to
    estimate its compute time (:func:`agglomtool.maps.estimate_sweep` gives the same
    without running). It logs this in one line to the ``agglomtool.maps`` logger: at
    WARNING (shown on stderr by default) for big sweeps (more than 1e6 points or 10 s),
    else at INFO. The kernels are compiled on their first use (tens of seconds, once: they
    are cached on disk); a note says so, on stderr with ``progress``, else at INFO.

    **Running on a cluster.** The collision kernel is compiled (Numba) and already uses
    every core of the process running it, and its threading layer does not allow calls
    from several threads; so give a cluster process workers with one thread each. A block
    is one task, computed inside one worker, so blocks should be large (the default
    ``chunks="auto"``, about 2.6e5 points, takes seconds), and a map needs several blocks
    per worker to keep them all busy. On one machine a cluster gains little or nothing
    (the default already runs the kernel on every core); it pays off when the workers
    are on several machines, with the store on a file system they all share::

        from dask.distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=2, processes=True, threads_per_worker=1)
        with Client(cluster) as client:
            ds = at.sweep(scene, store="map-store", client=client, T=..., h0=...)

        # or a remote scheduler, its workers started on each machine with
        #   dask worker tcp://scheduler-host:8786 --nworkers 1 --nthreads 1
        client = Client("tcp://scheduler-host:8786")
        ds = at.sweep(scene, store="/shared/map-store", client=client, T=..., h0=...)

    Every worker needs the same agglomtool version. The materials files are read once, at
    the start of the sweep, and their content travels with the tasks: a worker computes
    from them, not from its own files. A cluster with no live worker for 60 s
    (``AGGLOMTOOL_WORKER_TIMEOUT``) fails the sweep with ``NoWorkersError`` (of
    ``agglomtool.maps.cluster``); an error raised on a worker is raised
    here as itself. With several workers on one machine, set ``NUMBA_NUM_THREADS`` in
    their environment to that machine's cores divided by its workers.

    Examples
    --------
    >>> import numpy as np, agglomtool as at                         # doctest: +SKIP
    >>> ds = at.sweep(at.Scene(), T=np.linspace(1000, 1300, 31), h0=[0.2e-6, 1e-6])
    """
    from .. import materials
    from .checks import check_chunks
    from .layout import check_sweep_options

    check_chunks(chunks)
    check_sweep_options(nodes=nodes, compute=compute, client=client, progress=progress,
                        overwrite=overwrite, uncertain=uncertain, samples=samples,
                        threshold=threshold, seed=seed)
    # inputs read once per run: the materials files are read and hashed here, and every
    # block (here or on a cluster's workers) computes from those bytes
    owner = materials.current() is None
    with materials.pinned() as snap:
        ds = _sweep(scene, chunks=chunks, nodes=nodes, store=store, progress=progress,
                    compute=compute, overwrite=overwrite, client=client, uncertain=uncertain,
                    samples=samples, threshold=threshold, seed=seed, **grid)
    if owner:
        materials.warn_if_changed(snap, "the sweep")
    return ds


def _sweep(scene: Scene, *, chunks, nodes, store, progress, compute, overwrite, client,
           uncertain, samples, threshold, seed, _drawn=(), **grid) -> xr.Dataset:
    """:func:`sweep` inside its materials snapshot (``_drawn``: the speed models that the
    robust map whose nominal map this is may draw)."""
    from . import estimate as _est
    from .progress import compile_notice, say_on_stderr

    if uncertain is not None:
        if store is not None or not compute or client not in (None, False):
            raise ValueError("a robust map (uncertain=...) is computed in memory, here: "
                             "store=, compute=False and client= are not for it")
        from ..uncertainty.scene_mc import (
            drawn_speeds,
            split_uncertain,
            uncertain_without_effect,
        )
        from .robust import robust_sweep

        split_uncertain(uncertain)  # a bad request fails before the nominal map is made
        if "speed" not in grid:  # (a speed axis: robust_sweep asks with its checked names)
            found = uncertain_without_effect(scene, uncertain)
            if found:  # a law nothing reads: said before the nominal map, not after it
                raise ValueError(found[1])
        nominal = _sweep(scene, chunks=chunks, nodes=nodes, store=None, progress=progress,
                         compute=True, overwrite=False, client=False, uncertain=None,
                         samples=samples, threshold=threshold, seed=seed,
                         _drawn=drawn_speeds(scene, uncertain), **grid)
        return robust_sweep(scene, nominal, tuple(grid), uncertain=uncertain,
                            samples=samples, seed=seed, threshold=threshold, nodes=nodes)
    if store is not None:
        from .store import _check_path

        _check_path(store)  # before any work: a file is not a store
    if client is None and (compute or store is not None):  # (a lazy map needs none)
        from .store import _active_client

        client = _active_client()
    on_cluster = client is not None and client is not False
    # in memory, here: larger blocks on many threads (auto_block says why)
    chunks = sweep_chunks(chunks, store is None and compute and not on_cluster)
    plan = _plan(scene, chunks, nodes, grid, _drawn)
    if store is None and not compute:
        return _dataset(plan, _lazy_arrays(plan))
    if store is None:  # before any work: nothing is computed, nothing grows
        _est.check_memory(_est.estimate_plan(plan))
    announce = _est.announcer(plan, store)
    if on_cluster:
        announce(None, "not measured for a cluster")
    say = say_on_stderr if progress else logger.info
    summary: dict = {}  # a store's flag counts and mu_l range, from its blocks
    with compile_notice(say, _est.compile_seconds(plan)):
        if store is not None:
            from .store import _run_store

            ds = _run_store(plan, store, progress=progress, overwrite=overwrite,
                            client=client, announce=None if on_cluster else announce,
                            summary=summary)
        elif on_cluster:
            from .cluster import _compute_plan

            ds = _dataset(plan, _compute_plan(plan, client, progress))
        else:
            ds = _dataset(plan, _compute_here(plan, progress, announce))
    from .speed_flag import warn_flagged

    # the points the speed model has no answer at, if any
    warn_flagged(ds, stacklevel=4, counts=summary.get("speed_flag"))
    return _with_regime(ds, summary)


def _with_regime(ds: xr.Dataset, summary: dict | None = None) -> xr.Dataset:
    """``ds`` with the attribute ``deciding_regime`` where the map has no finite ``u0*``
    (:func:`agglomtool.maps.regime.deciding_regime`: what then decides it)."""
    from .regime import deciding_regime

    text = deciding_regime(ds, summary)
    if text:
        ds.attrs["deciding_regime"] = text
    return ds


#: Bytes between the writes of :func:`prefault` (a page of memory).
PAGE = 4096


@njit(parallel=True, cache=CACHE)
def _touch(buf, step):  # pragma: no cover - compiled
    for p in prange((buf.shape[0] + step - 1) // step):
        buf[p * step] = 0


def prefault(arrays) -> None:
    """Write one byte of every page of ``arrays`` (new, not yet written: ``np.empty``) on
    every thread. The system maps a new array's memory at its first write, page by page;
    a map's result (0.2 GB for 4e6 points) was first written block by block on the
    calling thread, 20-30 ms of every such map in page faults (measured: 0.2 GB written
    first 0.024-0.030 s, written again 0.0075 s). The values are left undefined, as
    ``np.empty``'s: every element is written by the sweep's blocks."""
    for a in arrays:
        if a.nbytes >= 1 << 20 and a.flags.c_contiguous:
            parallel_launch(_touch, a.reshape(-1).view(np.uint8), PAGE)


def _compute_here(plan, progress: bool, announce) -> dict:
    """``{name: numpy array}`` of the sweep, block by block in this process; the estimate is
    announced after a few timed blocks (:func:`agglomtool.maps.estimate.run_blocks_here`),
    the progress bar follows."""
    from .estimate import run_blocks_here
    from .progress import SweepBar

    out = {k: np.empty(plan.var_shape(k), dtype=plan.variables[k][1])
           for k in plan.lazy_names}
    prefault(out.values())
    bar = None

    def start(seconds, method):
        nonlocal bar
        announce(seconds, method)
        bar = SweepBar(plan.points, plan.n_blocks, "sweep", progress)

    def done(idx, sl, values):  # the values are already in ``out`` (plan.evaluate's out)
        bar.update(plan.block_points(sl))

    try:
        run_blocks_here(plan, lambda idx, sl: plan.evaluate(sl, plan.owned(idx), out), done,
                        start)
    finally:
        if bar is not None:
            bar.close()
    return out
