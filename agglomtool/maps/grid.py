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

import json
import logging

import numpy as np
import xarray as xr

from .._version import __version__
from ..plausibility import scene_findings, warn_findings
from ..scene import (
    CATEGORICAL_FIELDS,
    NUMERIC_FIELDS,
    Resolved,
    Scene,
    assumed_inputs,
    collision_outputs,
    critical_outputs,
    provenance,
    validate,
)
from ..units import to_si_array
from .meta import FIELD_META, field_attrs, variable_attrs

__all__ = ["sweep", "build", "GROUPS", "DEFAULT_BLOCK"]

logger = logging.getLogger("agglomtool.maps")

#: Default number of grid points per dask block (bounded memory: about 30 MB of
#: temporaries per collision batch).
DEFAULT_BLOCK = 2**18

SPEED_FIELDS = ("u0", "speed", "sigma_ln", "granular_temperature", "fluctuation_ratio",
                "U", "U_Umf")
_ALL = tuple(CATEGORICAL_FIELDS) + tuple(NUMERIC_FIELDS)

#: group name -> (fields it depends on, output names, output dtypes)
GROUPS = {
    "gas": (("T", "P", "gas"), ("mu_g", "rho_g"), (float, float)),
    "liquid": (("T", "P", "liquid", "theta_deg"), ("mu_l", "gamma_l", "rho_l"),
               (float, float, float)),
    "fluid": (("T", "P", "gas", "liquid", "solid_i", "solid_j", "d_i", "d_j", "h0", "h0_j",
               "U_e_Umf", "umf_method"), ("Umf", "U_e"), (float, float)),
    "critical": (tuple(f for f in _ALL if f not in SPEED_FIELDS),
                 ("u_star", "u_star_flag", "Ca_star", "regime"),
                 (float, np.int8, float, np.int8)),
    "collision": (_ALL, ("u_typical", "U", "e_w", "agglomerated", "stage", "St",
                         "propensity", "margin"),
                  (float, float, float, bool, np.int8, float, float, float)),
}


def _grid_values(scene: Scene, grid: dict) -> dict:
    """Validate the grid: 1-D, known fields, values the scene accepts."""
    out = {}
    base = scene.values()
    for name, values in grid.items():
        if name == "body_forces":
            raise ValueError("body_forces cannot be swept; run two sweeps")
        if name not in base:
            raise ValueError(f"{name!r} is not a Scene field; fields: {sorted(base)}")
        if name in CATEGORICAL_FIELDS:
            vals = [values] if isinstance(values, str) else list(values)
            if not vals or not all(isinstance(v, str) for v in vals):
                raise ValueError(f"grid {name} must be a non-empty list of names, got {values!r}")
            for v in vals:
                validate({**base, name: v})
            arr = np.array(vals)
        else:
            unit, long_name = FIELD_META[name]
            values = to_si_array(name, values, unit, long_name)
            try:
                arr = np.atleast_1d(np.asarray(values, dtype=float))
            except (TypeError, ValueError):
                raise ValueError(f"grid {name} must be numbers (SI) or quantities with units, "
                                 f"got {values!r}") from None
            if arr.ndim != 1 or arr.size == 0:
                raise ValueError(f"grid {name} must be a non-empty 1-D list of numbers, "
                                 f"got shape {arr.shape}")
            validate({**base, name: arr})
        if len(np.unique(arr)) != arr.size:
            raise ValueError(f"grid {name} repeats a value; coordinates must be unique")
        out[name] = arr
    _check_properties(base, out)
    numeric = {k: v for k, v in out.items() if k not in CATEGORICAL_FIELDS}
    before = set(scene_findings(base))  # the Scene warned of these already
    found = scene_findings({**base, **numeric})
    for name in (k for k in out if k in CATEGORICAL_FIELDS):  # names: check each value
        for v in out[name]:
            found += scene_findings({**base, **numeric, name: str(v)})
    warn_findings([f for f in dict.fromkeys(found) if f not in before], stacklevel=4)
    speed = base["speed"]
    needs = {"u0": ("fixed", "lognormal"), "sigma_ln": ("lognormal",),
             "granular_temperature": ("maxwellian",), "fluctuation_ratio": ("excess-gas",)}
    if "speed" not in grid:
        for name, families in needs.items():
            if name in grid and speed not in families:
                raise ValueError(f"grid {name} has no effect with speed = {speed!r}; set the "
                                 f"scene's speed to one of {list(families)}")
    return out


def _check_properties(base: dict, grid: dict) -> None:
    """Evaluate the gas and liquid properties on the swept (T, P) values of every swept gas
    and liquid, so that a value outside a correlation's range fails now, naming the gas or
    liquid, and not inside a dask task (nor at a default the sweep never uses)."""
    T = np.asarray(grid.get("T", base["T"]), dtype=float)
    P = np.asarray(grid.get("P", base["P"]), dtype=float)
    T, P = T.reshape(-1, 1), P.reshape(1, -1)
    for gas in np.atleast_1d(grid.get("gas", base["gas"])):
        for liquid in np.atleast_1d(grid.get("liquid", base["liquid"])):
            r = Resolved({**base, "T": T, "P": P, "gas": str(gas), "liquid": str(liquid)})
            _ = r.mu_g, r.liquid


def _first_point(base: dict, grid: dict) -> dict:
    """The scene's values at the grid's first point (every swept field at its first value)."""
    return {**base, **{k: (str(v[0]) if k in CATEGORICAL_FIELDS else float(v[0]))
                       for k, v in grid.items()}}


def _chunks(grid: dict, chunks) -> dict:
    """Chunk size per dim: 1 for names, else ``chunks`` (dict, int total, "auto", None)."""
    from .checks import check_chunks

    check_chunks(chunks)  # 0, negative, fractional or boolean sizes: a ValueError, no clamp
    sizes = {k: len(v) for k, v in grid.items()}
    out = {k: 1 for k in grid if k in CATEGORICAL_FIELDS}
    numeric = [k for k in grid if k not in CATEGORICAL_FIELDS]
    if isinstance(chunks, dict):
        unknown = sorted(set(chunks) - set(grid))
        if unknown:
            raise ValueError(f"chunks names {unknown[0]!r}, which is not a grid dimension")
        for k in numeric:
            out[k] = int(min(sizes[k], chunks.get(k, sizes[k])))
        return out
    if chunks is None:
        return {**out, **{k: sizes[k] for k in numeric}}
    target = DEFAULT_BLOCK if chunks == "auto" else int(chunks)
    if target < 1:
        raise ValueError(f"chunks = {chunks!r} must be >= 1 points per block")
    prod = 1
    for k in reversed(numeric):  # the last dims whole first, the outer ones split
        c = int(min(sizes[k], max(1, target // prod)))
        out[k] = c
        prod *= c
    return out


def _block_function(scene_values: dict, names: tuple, group: str, nodes: int):
    """The numpy function of one output group over one block."""

    def func(*arrays):
        values = dict(scene_values)
        values.update(zip(names, arrays[: len(names)], strict=True))
        r = Resolved(values)
        if group == "gas":
            out = (r.mu_g, r.rho_g)
        elif group == "liquid":
            out = (r.liquid.mu, r.liquid.gamma, r.liquid.rho)
        elif group == "fluid":
            out = (r.Umf, r.U_e)
        elif group == "critical":
            c = critical_outputs(r)
            out = tuple(c[k] for k in GROUPS["critical"][1])
        else:
            c = collision_outputs(r, arrays[-1], nodes)
            out = tuple(c[k] for k in GROUPS["collision"][1])
        shape = np.broadcast_shapes(*[np.shape(a) for a in arrays]) if arrays else ()
        return tuple(np.broadcast_to(o, shape).copy() for o in out)

    return func


def _split(n: int, c: int) -> tuple:
    """Block sizes of an axis of ``n`` values in blocks of ``c``."""
    return (c,) * (n // c) + ((n % c,) if n % c else ())


def _plan(scene: Scene, chunks, nodes, grid: dict):
    """The validated :class:`~agglomtool.maps.plan.SweepPlan` of a sweep's arguments."""
    from .plan import SweepPlan

    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be an agglomtool Scene, got {type(scene).__name__}")
    if not isinstance(nodes, int | np.integer) or nodes < 1:
        raise ValueError(f"nodes = {nodes!r} must be an integer >= 1")
    values = _grid_values(scene, grid)
    sizes = _chunks(values, chunks)
    return SweepPlan(scene.values(), values,
                     {k: _split(len(v), sizes[k]) for k, v in values.items()}, int(nodes))


def _dataset(plan, data: dict) -> xr.Dataset:
    """The sweep's Dataset: ``data`` (``{name: array}``, numpy or dask) for the variables
    over grid dimensions, the plan's 0-d values for the others; coordinates and attributes."""
    coords = {k: xr.DataArray(v, dims=[k], attrs=field_attrs(k)) for k, v in plan.grid.items()}
    variables = {name: xr.Variable(dims, data[name] if dims else plan.eager[name],
                                   attrs=variable_attrs(name))
                 for name, (dims, _, _) in plan.variables.items()}
    ds = xr.Dataset(variables, coords=coords)
    ds.attrs.update(_dataset_attrs(plan.base, plan.grid, plan.nodes))
    return ds


def _block_task(plan, idx):
    """One block of the lazy Dataset: ``{name: array}`` of the variables it owns."""
    idx = tuple(idx)
    return plan.evaluate(plan.block_slices(idx), plan.owned(idx))


def _lazy_arrays(plan) -> dict:
    """``{name: dask array}``: one task per block (:func:`_block_task`), and each variable's
    chunk taken from the block that owns it. The graph is written block by block, so no
    small input is broadcast into the block structure (which dask warns about)."""
    import itertools
    import operator

    import dask.array as da
    from dask.base import tokenize
    from dask.highlevelgraph import HighLevelGraph

    token = tokenize(json.dumps(plan.base, sort_keys=True), list(plan.grid),
                     [plan.grid[k] for k in plan.grid], plan.chunks, plan.nodes, __version__)
    bname, pkey = f"agglomtool-sweep-{token}", f"agglomtool-sweep-plan-{token}"
    blocks = {pkey: plan}
    for idx, _ in plan.blocks():
        blocks[(bname, *idx)] = (_block_task, pkey, list(idx))
    out = {}
    for name in plan.lazy_names:
        dims, dtype, _ = plan.variables[name]
        vname = f"{name}-{token}"
        layer = {}
        for j in itertools.product(*[range(len(plan.chunks[d])) for d in dims]):
            at = dict(zip(dims, j, strict=True))
            owner = tuple(at.get(d, 0) for d in plan.dims)
            layer[(vname, *j)] = (operator.getitem, (bname, *owner), name)
        graph = HighLevelGraph({bname: blocks, vname: layer}, {bname: set(), vname: {bname}})
        out[name] = da.Array(graph, vname, chunks=tuple(plan.chunks[d] for d in dims),
                             dtype=dtype, meta=np.empty((0,) * len(dims), dtype=dtype))
    return out


def _template(plan) -> xr.Dataset:
    """The sweep's Dataset with unwritten (never computed) arrays: a store's layout."""
    import dask.array as da

    empty = {name: da.empty(plan.var_shape(name), dtype=plan.variables[name][1], chunks=-1)
             for name in plan.lazy_names}
    return _dataset(plan, empty)


def build(scene: Scene, *, chunks="auto", nodes: int = 16, **grid) -> xr.Dataset:
    """The lazy (dask-backed) Dataset of a sweep: nothing is computed yet.

    Parameters are those of :func:`sweep`. Each block is one task (evaluating the block's
    variables, :meth:`~agglomtool.maps.plan.SweepPlan.evaluate`); compute it with the
    synchronous scheduler (the collision kernel is itself parallel, and its threading layer
    does not allow concurrent calls from several threads). :func:`sweep` runs the same
    blocks without building this graph.
    """
    plan = _plan(scene, chunks, nodes, grid)
    return _dataset(plan, _lazy_arrays(plan))


def _dataset_attrs(base: dict, grid: dict, nodes: int) -> dict:
    first = _first_point(base, grid)  # properties are described where the grid has them
    tiers = list(grid["mode"]) if "mode" in grid else [base["mode"]]
    sources = {}
    for name in ("solid_i", "solid_j", "liquid", "gas"):
        for value in (list(grid[name]) if name in grid else [base[name]]):
            if value is None:
                continue
            for key, text in Resolved({**first, name: str(value)}).sources.items():
                sources["source: " + key] = " ".join(text.split())
    prov = {f"provenance: {name}": f"{val} {units}; {origin}; {conf}"
            for name, (val, units, origin, conf) in provenance(first).items()
            if name not in grid}
    assumed = []
    combos = [first] + [{**first, k: str(v)} for k in grid if k in CATEGORICAL_FIELDS
                        for v in grid[k]]
    for values in combos:
        for text in assumed_inputs(values):
            if text not in assumed:
                assumed.append(text)
    return {
        "title": "agglomtool operating map",
        "assumed_inputs": "; ".join(assumed) if assumed else "none",
        **prov,
        "agglomtool_version": __version__,
        "model_tier": ", ".join(tiers),
        "scene": json.dumps(base),
        "grid": json.dumps(list(grid)),
        "propensity_method": (
            f"F(u0*) plus the sticking indicator integrated over {nodes} equal-probability "
            "nodes above u0* (agglomtool.maps.speeds)"),
        "quadrature_nodes": int(nodes),
        "reference": ("Shabanian, Duchesne, Syamlal and Runstedtler (2024), Heliyon "
                      "10:e29397, doi:10.1016/j.heliyon.2024.e29397"),
        **sources,
    }


def sweep(scene: Scene, *, chunks="auto", nodes: int = 16, store=None, progress=False,
          compute: bool = True, overwrite: bool = False, client=None, **grid) -> xr.Dataset:
    """Evaluate ``scene`` over a grid of its fields.

    Parameters
    ----------
    scene : Scene
        The operating point; fields not in ``grid`` keep its values.
    chunks : "auto", int, dict or None
        Block size: ``"auto"`` (about 2.6e5 points per block), a number of points per
        block, a ``{dim: size}`` dict, or ``None`` (one block per category combination).
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
        memory for grids larger than memory); ``.to_netcdf(path)`` writes one file.
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
    **grid
        ``field=values``: one dimension per field, in the order given, with the values
        as coordinates (numbers in the units of :class:`Scene`, or names).

    Returns
    -------
    xarray.Dataset
        Data variables (see :data:`agglomtool.maps.meta.VARIABLE_META`), each with
        ``units`` and ``long_name``: gas and liquid properties, ``Umf``, ``U``, ``U_e``,
        ``u_star``, ``Ca_star``, ``regime``, ``u_typical``, ``St``, ``e_w``,
        ``agglomerated``, ``stage``, ``propensity`` and ``margin``, each over the grid
        dimensions it depends on. Attributes record the agglomtool version, model tier,
        base scene and material sources.

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

    Every worker needs the same agglomtool version and the same user materials files
    (``AGGLOMTOOL_MATERIALS``, at the same paths); a worker whose materials files differ
    refuses its blocks. With several workers on one machine, set ``NUMBA_NUM_THREADS`` in
    their environment to that machine's cores divided by its workers.

    Examples
    --------
    >>> import numpy as np, agglomtool as at                         # doctest: +SKIP
    >>> ds = at.sweep(at.Scene(), T=np.linspace(1000, 1300, 31), h0=[0.2e-6, 1e-6])
    """
    from . import estimate as _est
    from .checks import check_chunks
    from .progress import compile_notice, say_on_stderr

    check_chunks(chunks)
    if store is not None:
        from .store import _check_path

        _check_path(store)  # before any work: a file is not a store
    plan = _plan(scene, chunks, nodes, grid)
    if store is None and not compute:
        return _dataset(plan, _lazy_arrays(plan))
    if client is None:
        from .store import _active_client

        client = _active_client()
    on_cluster = client is not None and client is not False
    if store is None:  # before any work: nothing is computed, nothing grows
        _est.check_memory(_est.estimate_plan(plan))
    announce = _est.announcer(plan, store)
    if on_cluster:
        announce(None, "not measured for a cluster")
    say = say_on_stderr if progress else logger.info
    with compile_notice(say, _est.compile_seconds(plan)):
        if store is not None:
            from .store import _run_store

            return _run_store(plan, store, progress=progress, overwrite=overwrite,
                              client=client, announce=None if on_cluster else announce)
        if on_cluster:
            from .cluster import _compute_plan

            return _dataset(plan, _compute_plan(plan, client, progress))
        return _dataset(plan, _compute_here(plan, progress, announce))


def _compute_here(plan, progress: bool, announce) -> dict:
    """``{name: numpy array}`` of the sweep, block by block in this process; the estimate is
    announced after a few timed blocks (:func:`agglomtool.maps.estimate.run_blocks_here`),
    the progress bar follows."""
    from .estimate import run_blocks_here
    from .progress import SweepBar

    out = {k: np.empty(plan.var_shape(k), dtype=plan.variables[k][1])
           for k in plan.lazy_names}
    bar = None

    def start(seconds, method):
        nonlocal bar
        announce(seconds, method)
        bar = SweepBar(plan.points, plan.n_blocks, "sweep", progress)

    def done(idx, sl, values):
        for name, a in values.items():
            out[name][tuple(sl[d] for d in plan.variables[name][0])] = a
        bar.update(plan.block_points(sl))

    try:
        run_blocks_here(plan, lambda idx, sl: plan.evaluate(sl, plan.owned(idx)), done,
                        start)
    finally:
        if bar is not None:
            bar.close()
    return out
