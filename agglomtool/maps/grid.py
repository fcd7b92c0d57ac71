"""Sweeps: a scene evaluated over a grid of its fields, as an ``xarray.Dataset``.

The grid is chunked with dask and every block is evaluated by
``xarray.apply_ufunc(..., dask="parallelized")``. Outputs are computed in groups, each
over the dimensions it depends on only: gas properties over (T, P), ``u0*`` over every
field except the impact-speed ones, the collisions over the whole grid. ``u0*`` is the
expensive part (about 1e5 solves/s), so a grid whose speed axes are long is cheap.
"""

from __future__ import annotations

import itertools
import json
import re

import dask
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
from .meta import (
    FIELD_META,
    call_text,
    field_attrs,
    global_attrs,
    provenance_attr,
    variable_attrs,
)

__all__ = ["sweep", "build", "GROUPS", "DEFAULT_BLOCK", "GridError", "grid_findings"]

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


class GridError(ValueError):
    """A grid that cannot be swept; ``field`` is the swept field the message blames (None
    where it blames none of them)."""

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field


def _blamed(message: str, names) -> str | None:
    """The swept field (of ``names``) whose value ``message`` states first, if any."""
    found = [(m.start(), k) for k in names
             for m in [re.search(rf"(?<![\w.]){re.escape(k)} = ", message)] if m]
    return min(found)[1] if found else None


def _axes(base: dict, grid: dict) -> dict:
    """Each axis alone: a known field, 1-D, non-empty, unique, in SI; names as strings."""
    out = {}
    for name, values in grid.items():
        if name == "body_forces":
            raise GridError("body_forces cannot be swept; run two sweeps", name)
        if name not in base:
            raise GridError(f"{name!r} is not a Scene field; fields: {sorted(base)}", name)
        if name in CATEGORICAL_FIELDS:
            vals = [values] if isinstance(values, str) else list(values)
            if not vals or not all(isinstance(v, str) for v in vals):
                raise GridError(f"grid {name} must be a non-empty list of names, got "
                                f"{values!r}", name)
            arr = np.array(vals)
        else:
            unit, long_name = FIELD_META[name]
            try:
                values = to_si_array(name, values, unit, long_name)
            except ValueError as exc:
                raise GridError(str(exc), name) from None
            try:
                arr = np.atleast_1d(np.asarray(values, dtype=float))
            except (TypeError, ValueError):
                raise GridError(f"grid {name} must be numbers (SI) or quantities with units, "
                                f"got {values!r}", name) from None
            if arr.ndim != 1 or arr.size == 0:
                raise GridError(f"grid {name} must be a non-empty 1-D list of numbers, "
                                f"got shape {arr.shape}", name)
        if len(np.unique(arr)) != arr.size:
            raise GridError(f"grid {name} repeats a value; coordinates must be unique", name)
        out[name] = arr
    return out


def _combinations(base: dict, axes: dict):
    """The scene's values as the grid sweeps them, one dict per combination of its names:
    every swept number as its whole axis (checks see its extremes), every swept name at
    each of its values together with each value of the other swept names."""
    numeric = {k: v for k, v in axes.items() if k not in CATEGORICAL_FIELDS}
    names = [k for k in axes if k in CATEGORICAL_FIELDS]
    for combo in itertools.product(*[[str(v) for v in axes[k]] for k in names]):
        yield {**base, **numeric, **dict(zip(names, combo, strict=True))}


def grid_findings(base: dict, axes: dict) -> list:
    """The plausibility findings of the scene ``base`` swept over ``axes`` (validated
    axes), at the values swept (not at the scene's values of the swept fields)."""
    found = []
    for values in _combinations(base, axes):
        found += scene_findings(values)
    return list(dict.fromkeys(found))


def _grid_values(scene: Scene, grid: dict, *, plausibility: bool = True) -> dict:
    """Validate the grid, once, at the values swept: each axis alone (1-D, known field,
    units, unique), then every field the model reads together, with each swept field at its
    swept values and never at the scene's value for it (numbers as whole axes, names in
    every combination), properties included. Raises :class:`GridError` naming the swept
    field it blames; warns the plausibility findings the scene has not said already."""
    base = scene.values()
    out = _axes(base, grid)
    try:
        for values in _combinations(base, out):
            validate(values)
        _check_properties(base, out)
    except ValueError as exc:
        raise GridError(str(exc), _blamed(str(exc), out)) from None
    if plausibility:
        before = set(scene_findings(base))  # the Scene warned of these already
        warn_findings([f for f in grid_findings(base, out) if f not in before], stacklevel=4)
    speed = base["speed"]
    needs = {"u0": ("fixed", "lognormal"), "sigma_ln": ("lognormal",),
             "granular_temperature": ("maxwellian",), "fluctuation_ratio": ("excess-gas",)}
    if "speed" not in grid:
        for name, families in needs.items():
            if name in grid and speed not in families:
                raise GridError(f"grid {name} has no effect with speed = {speed!r}; set the "
                                f"scene's speed to one of {list(families)}", name)
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


def build(scene: Scene, *, chunks="auto", nodes: int = 16, **grid) -> xr.Dataset:
    """The lazy (dask-backed) Dataset of a sweep: nothing is computed yet.

    Parameters are those of :func:`sweep`; compute it with the synchronous scheduler
    (the collision kernel is itself parallel, and its threading layer does not allow
    concurrent calls from several threads).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be an agglomtool Scene, got {type(scene).__name__}")
    if not isinstance(nodes, int | np.integer) or nodes < 1:
        raise ValueError(f"nodes = {nodes!r} must be an integer >= 1")
    grid = _grid_values(scene, grid)
    sizes = _chunks(grid, chunks)
    coords = {k: xr.DataArray(v, dims=[k], attrs=field_attrs(k)) for k, v in grid.items()}
    inputs = {k: c.chunk({k: sizes[k]}) for k, c in coords.items()}
    base = scene.values()
    data: dict[str, xr.DataArray] = {}
    for group, (deps, outs, dtypes) in GROUPS.items():
        names = tuple(k for k in grid if k in deps)
        args = [inputs[k] for k in names]
        func = _block_function(base, names, group, int(nodes))
        if group == "collision":
            args.append(data["u_star"])
        if names:
            res = xr.apply_ufunc(
                func, *args, dask="parallelized", output_dtypes=list(dtypes),
                output_core_dims=[[] for _ in outs],
            )
        else:
            vals = func(*[a.values for a in args])
            res = tuple(xr.DataArray(v) for v in vals)
        for name, da in zip(outs, res, strict=True):
            if name in coords:  # U swept: the output would be its coordinate, once again
                continue
            data[name] = da.assign_attrs(variable_attrs(name)).drop_vars(
                [c for c in da.coords if c not in coords], errors="ignore")
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(_dataset_attrs(scene, grid, nodes))
    return ds


def _dataset_attrs(scene: Scene, grid: dict, nodes: int) -> dict:
    """Global attributes of a map: CF's (:func:`~agglomtool.maps.meta.global_attrs`), the
    provenance of every input the grid does not set (JSON), the database values that are
    assumptions, the materials' sources (JSON) and the sweep's settings."""
    base = scene.values()
    first = _first_point(base, grid)  # properties are described where the grid has them
    tiers = list(grid["mode"]) if "mode" in grid else [base["mode"]]
    sources = {}
    for name in ("solid_i", "solid_j", "liquid", "gas"):
        for value in (list(grid[name]) if name in grid else [base[name]]):
            if value is None:
                continue
            for key, text in Resolved({**first, name: str(value)}).sources.items():
                sources[key] = " ".join(text.split())
    prov = {name: item for name, item in provenance(first).items() if name not in grid}
    assumed = []
    combos = [first] + [{**first, k: str(v)} for k in grid if k in CATEGORICAL_FIELDS
                        for v in grid[k]]
    for values in combos:
        for text in assumed_inputs(values):
            if text not in assumed:
                assumed.append(text)
    return {
        **global_attrs("agglomtool operating map",
                       call_text("agglomtool.sweep", grid, nodes=int(nodes))),
        "assumed_inputs": "; ".join(assumed) if assumed else "none",
        "provenance": provenance_attr(prov),
        "agglomtool_version": __version__,
        "model_tier": ", ".join(tiers),
        "scene": json.dumps(base),
        "grid": json.dumps(list(grid)),
        "propensity_method": (
            f"F(u0*) plus the sticking indicator integrated over {nodes} equal-probability "
            "nodes above u0* (agglomtool.maps.speeds)"),
        "quadrature_nodes": int(nodes),
        "material_sources": json.dumps(sources),
    }


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
        Dask block size: ``"auto"`` (about 2.6e5 points per block), a number of points per
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
        memory for grids larger than memory); :func:`agglomtool.write_map` writes one file.
    progress : bool
        Show progress on stderr (``tqdm`` if installed, else a text bar).
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
        ``agglomerated``, ``stage``, ``propensity`` and ``margin``, each over the grid
        dimensions it depends on; coded outputs (``stage``, ``regime``, ``u_star_flag``,
        ``agglomerated``) carry CF ``flag_values`` and ``flag_meanings``. ``ds["U"]`` is
        always the superficial gas velocity: the output ``U_Umf * Umf`` where ``U`` is not
        swept, and the coordinate ``U`` where it is (the output would repeat it). Attributes
        (CF-1.8, see :mod:`agglomtool.maps.meta`) record the call (``source``), the agglomtool
        version, model tier, base scene, the provenance of every input (JSON), the database
        values that are assumptions and the materials' sources (JSON).
        :func:`agglomtool.write_map` writes it as a CF-1.8 netCDF file.

    Notes
    -----
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
    from .checks import check_chunks

    check_chunks(chunks)
    if uncertain is not None:
        if store is not None or not compute or client not in (None, False):
            raise ValueError("a robust map (uncertain=...) is computed in memory, here: "
                             "store=, compute=False and client= are not for it")
        from ..uncertainty.scene_mc import split_uncertain
        from .robust import robust_sweep

        split_uncertain(uncertain)  # a bad request fails before the nominal map is made
        nominal = sweep(scene, chunks=chunks, nodes=nodes, progress=progress, client=False,
                        **grid)
        return robust_sweep(scene, nominal, tuple(grid), uncertain=uncertain,
                            samples=samples, seed=seed, threshold=threshold, nodes=nodes)
    if store is not None:
        from .store import _check_path

        _check_path(store)  # before any work: a file is not a store
    ds = build(scene, chunks=chunks, nodes=nodes, **grid)
    if client is None and (store is not None or compute):
        from .store import _active_client

        client = _active_client()
    if store is not None:
        from .store import run_with_store

        return run_with_store(ds, store, progress=progress, overwrite=overwrite,
                              client=client)
    if not compute:
        return ds
    if client is not None and client is not False:
        from .cluster import compute_on_cluster

        return compute_on_cluster(ds, client)
    with dask.config.set(scheduler="synchronous"):
        if progress:
            from .store import progress_callback

            with progress_callback():
                return ds.compute()
        return ds.compute()
