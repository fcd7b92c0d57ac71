"""The plan of a sweep: its grid, its blocks, its variables, and the evaluation of one block.

Every way of running a sweep evaluates the same blocks with :meth:`SweepPlan.evaluate`: in
memory, into a store, on a cluster's workers, and the tasks of the lazy Dataset of
:func:`agglomtool.maps.build`. A block is evaluated from its slice of the coordinates alone,
so running a sweep needs no task graph over the whole grid: memory and start-up time do not
grow with the number of blocks, and there is no broadcasting of small inputs into a large
block structure for dask to warn about.

Outputs come in groups (``agglomtool.maps.layout.GROUPS``), each over the grid dimensions
it depends on. A block computes the variables it *owns*: those over whose missing dimensions
its index is 0, so every value is computed once. ``u0*`` (the critical group, the expensive
one) is needed by every block's collisions; blocks are visited with the critical group's
dimensions outermost and the last one is kept, so a ``u0*`` block is computed once however
the speed axes are split.
"""

from __future__ import annotations

import itertools
import json
import math
import threading
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from .._version import __version__
from ..scene import COMPOSITION_KEY, Resolved, Scene
from .layout import (
    GROUPS,
    _block_function,
    _chunks,
    _dataset_attrs,
    _finish,
    _grid_values,
    _group_outputs,
    _split,
)
from .meta import field_attrs, variable_attrs

if TYPE_CHECKING:  # for the annotation only: materials is imported where it is used
    from ..materials import Snapshot

__all__ = ["SweepPlan", "build"]


def _compat(a: np.ndarray, have: tuple, to: tuple) -> np.ndarray:
    """``a`` (over the dims ``have``, a subset of ``to`` in the same order) shaped to
    broadcast over ``to``: a new axis for each missing dimension after the first present one
    (the shapes ``xarray.apply_ufunc`` passes to a block function)."""
    shape, started = [], False
    for d in to:
        if d in have:
            shape.append(a.shape[have.index(d)])
            started = True
        elif started:
            shape.append(1)
    return a.reshape(shape)


@dataclass(frozen=True, eq=False)
class SweepPlan:
    """A validated sweep: base scene values, grid, block sizes, quadrature nodes.

    Parameters
    ----------
    base : dict
        The scene's values (:meth:`agglomtool.Scene.values`).
    grid : dict
        ``{dim: 1-D numpy array}``, validated, in the order given.
    chunks : dict
        ``{dim: tuple of block sizes}``.
    nodes : int
        Quadrature nodes of the propensity.
    materials : agglomtool.materials.Snapshot, optional
        The materials files as read at the start of the run: every block is evaluated
        from them (:func:`agglomtool.materials.pinned`), wherever it runs; ``None``: the
        files as they are when a block runs.
    """

    base: dict
    grid: dict
    chunks: dict
    nodes: int
    materials: Snapshot | None = None

    # -- layout ---------------------------------------------------------------------------

    @cached_property
    def group_dims(self) -> dict:
        """``{group: its grid dimensions, in grid order}``."""
        return {g: tuple(k for k in self.grid if k in deps) for g, (deps, _, _) in
                GROUPS.items()}

    @cached_property
    def variables(self) -> dict:
        """``{name: (dims, numpy dtype, group)}`` of every output, in the Dataset's order.
        An output named as a grid coordinate (``U``, where U is swept) is left out: it would
        be that coordinate once again."""
        return {name: (self.group_dims[g], np.dtype(dtype), g)
                for g, (_, outs, dtypes) in GROUPS.items()
                for name, dtype in zip(outs, dtypes, strict=True) if name not in self.grid}

    @cached_property
    def dims(self) -> tuple:
        """The Dataset's dimensions in its own order (first appearance over the variables),
        the order of block indices and of a store's fingerprint."""
        out = []
        for dims, _, _ in self.variables.values():
            out += [d for d in dims if d not in out]
        return tuple(out + [d for d in self.grid if d not in out])

    @cached_property
    def shape(self) -> dict:
        return {d: len(v) for d, v in self.grid.items()}

    @property
    def points(self) -> int:
        """Grid points (the size of the collision outputs)."""
        return math.prod(self.shape.values())

    @property
    def n_blocks(self) -> int:
        return math.prod(len(self.chunks[d]) for d in self.dims)

    def var_shape(self, name: str) -> tuple:
        return tuple(self.shape[d] for d in self.variables[name][0])

    def var_nbytes(self, name: str) -> int:
        dims, dtype, _ = self.variables[name]
        return math.prod(self.shape[d] for d in dims) * dtype.itemsize

    @property
    def nbytes(self) -> int:
        """Bytes of the whole result in memory: every variable and coordinate."""
        return (sum(self.var_nbytes(v) for v in self.variables)
                + sum(int(a.nbytes) for a in self.grid.values()))

    def group_work(self, group: str) -> tuple[int, int]:
        """``(points, calls)``: how many points of ``group`` a run evaluates, in how many
        calls (one per block of its own dimensions)."""
        dims = self.group_dims[group]
        return (math.prod(self.shape[d] for d in dims),
                math.prod(len(self.chunks[d]) for d in dims))

    @cached_property
    def lazy_names(self) -> tuple:
        """Variables over at least one grid dimension (computed block by block)."""
        return tuple(v for v, (dims, _, _) in self.variables.items() if dims)

    # -- blocks ---------------------------------------------------------------------------

    @cached_property
    def _starts(self) -> dict:
        return {d: np.concatenate([[0], np.cumsum(self.chunks[d])]).astype(int)
                for d in self.dims}

    def block_slices(self, idx: tuple) -> dict:
        """``{dim: slice}`` of the block ``idx`` (an index per dimension of :attr:`dims`)."""
        st = self._starts
        return {d: slice(int(st[d][i]), int(st[d][i + 1]))
                for d, i in zip(self.dims, idx, strict=True)}

    @cached_property
    def _order(self) -> tuple:
        """The dimensions in the order blocks are visited (critical ones outermost) and the
        position of each of :attr:`dims` in it."""
        crit = self.group_dims["critical"]
        order = [d for d in self.dims if d in crit] + [d for d in self.dims if d not in crit]
        return order, [order.index(d) for d in self.dims]

    def blocks(self):
        """``(idx, {dim: slice})`` of every block, the critical group's dimensions
        outermost (consecutive blocks then share their ``u0*`` block)."""
        order, pos = self._order
        for combo in itertools.product(*[range(len(self.chunks[d])) for d in order]):
            idx = tuple(combo[p] for p in pos)
            yield idx, self.block_slices(idx)

    def block_at(self, n: int):
        """The ``n``-th block of :meth:`blocks`: ``(idx, {dim: slice})``."""
        order, pos = self._order
        combo = np.unravel_index(n, [len(self.chunks[d]) for d in order]) if order else ()
        idx = tuple(int(combo[p]) for p in pos)
        return idx, self.block_slices(idx)

    def block_points(self, sl: dict) -> int:
        return math.prod(s.stop - s.start for s in sl.values())

    def owned(self, idx: tuple) -> list:
        """Variables the block ``idx`` computes: those over whose missing dimensions its
        index is 0 (0-d variables are computed once, up front: :attr:`eager`)."""
        at = dict(zip(self.dims, idx, strict=True))
        return [v for v in self.lazy_names
                if all(at[d] == 0 for d in self.dims if d not in self.variables[v][0])]

    # -- evaluation -----------------------------------------------------------------------

    @cached_property
    def eager(self) -> dict:
        """``{name: 0-d array}`` of the outputs of groups over no grid dimension."""
        out: dict[str, np.ndarray] = {}
        for group, (_, outs, _) in GROUPS.items():
            if self.group_dims[group]:
                continue
            args = [out["u_star"]] if group == "collision" else []  # (no grid at all)
            vals = _block_function(self.base, (), group, int(self.nodes))(*args)
            out.update(zip(outs, vals, strict=True))
        return out

    @cached_property
    def _memo(self):
        return threading.local()

    def _critical(self, sl: dict, shared=None) -> dict:
        """The critical group's outputs over the block's slice of its dimensions; the last
        one is kept (per thread) for the next block."""
        dims = self.group_dims["critical"]
        if not dims:
            return {k: self.eager[k] for k in GROUPS["critical"][1]}
        key = tuple((sl[d].start, sl[d].stop) for d in dims)
        memo = getattr(self._memo, "last", None)
        if memo is not None and memo[0] == key:
            return memo[1]
        vals = self._group("critical", sl, shared=shared)
        self._memo.last = (key, vals)
        return vals

    def _shared(self, sl: dict) -> Resolved:
        """The block's scene resolved once for all its groups: every swept field at its
        slice, over all the grid's dimensions (the collision group's shapes). Each group
        reads what it depends on (the gas and liquid properties, ``U_mf``, ...) from it,
        computed once per block instead of once per group; its values are the same
        element by element, each group's output only lacks the other groups' axes."""
        dims = self.group_dims["collision"]
        values = dict(self.base)
        values.update({d: _compat(self.grid[d][sl[d]], (d,), dims) for d in dims})
        r = Resolved(values)
        whole = self._whole_properties
        if whole is not None:
            def cut(a):  # the block's elements of an array over the whole T and P axes
                a = np.asarray(a)
                at = dims[len(dims) - a.ndim:]
                return a[tuple(sl[d] if n > 1 else slice(None)
                               for d, n in zip(at, a.shape, strict=True))]

            r.take_properties(whole, cut)
        return r

    @cached_property
    def _whole_properties(self) -> Resolved | None:
        """The scene over the grid's whole T and P axes, shaped as the blocks' (its gas
        and liquid properties computed there once, each block takes its own elements:
        :meth:`agglomtool.scene.Resolved.take_properties`); None where a block's
        properties depend on more than its T and P (a swept gas or liquid)."""
        if any(d in self.grid for d in ("gas", "liquid")) or COMPOSITION_KEY in self.base:
            return None
        dims = self.group_dims["collision"]
        values = dict(self.base)
        values.update({d: _compat(self.grid[d], (d,), dims) for d in ("T", "P")
                       if d in self.grid})
        return Resolved(values)

    def _group(self, group: str, sl: dict, u_star=None, out=None, shared=None) -> dict:
        dims = self.group_dims[group]
        args = [_compat(self.grid[d][sl[d]], (d,), dims) for d in dims]
        if group == "collision":
            args.append(_compat(np.asarray(u_star), self.group_dims["critical"], dims))
        into = None
        if out is not None:
            into = tuple(None if k not in out else out[k][tuple(sl[d] for d in dims)]
                         for k in GROUPS[group][1])
        if shared is None or self.group_dims["collision"] != tuple(self.grid):
            vals = _block_function(self.base, dims, group, int(self.nodes), into)(*args)
            return dict(zip(GROUPS[group][1], vals, strict=True))
        r = shared()
        shape = np.broadcast_shapes(*[np.shape(a) for a in args])
        raw = _group_outputs(r, group, int(self.nodes), into, args[-1])
        if group != "collision":  # over every dimension: the group's own axes kept
            ones = tuple(sl[d].stop - sl[d].start if d in dims else 1 for d in self.grid)
            raw = tuple((o if np.shape(o) == ones else np.broadcast_to(o, ones)).reshape(shape)
                        for o in raw)  # (most have those axes already: no view to make)
        return dict(zip(GROUPS[group][1], _finish(raw, shape, into), strict=True))

    def evaluate(self, sl: dict, wanted, out=None) -> dict:
        """``{name: array}`` of the variables ``wanted`` over the block ``sl``
        (``{dim: slice}``), each over its own dimensions' slices; from the plan's
        materials snapshot, where it has one. With ``out`` (``{name: array of the
        variable's whole shape}``, e.g. the result of a sweep in memory) each wanted
        variable is written straight into its block of ``out`` (no copy of the block in
        between), and the arrays returned are those blocks."""
        if self.materials is None:
            return self._evaluate(sl, wanted, out)
        from .. import materials

        with materials.pinned(self.materials):
            return self._evaluate(sl, wanted, out)

    def _evaluate(self, sl: dict, wanted, out=None) -> dict:
        wanted = list(wanted)
        groups = {self.variables[v][2] for v in wanted}
        into = None if out is None else {k: out[k] for k in wanted}
        found: dict = {}
        held: list = []

        def shared():  # the block's one Resolved, made where a group first needs it
            if not held:
                held.append(self._shared(sl))
            return held[0]

        for group in GROUPS:
            if group not in groups:
                continue
            if not self.group_dims[group]:
                vals = {k: self.eager[k] for k in GROUPS[group][1]}
            elif group == "critical":
                vals = self._critical(sl, shared)
            elif group == "collision":
                vals = self._group(group, sl, self._critical(sl, shared)["u_star"], into,
                                   shared)
            else:
                vals = self._group(group, sl, out=into, shared=shared)
            found.update({k: v for k, v in vals.items() if k in wanted})
        if out is not None:  # the critical group's (kept for the next block): copied once
            for k, v in found.items():
                block = out[k][tuple(sl[d] for d in self.variables[k][0])]
                if v is not block:
                    block[...] = v
                    found[k] = block
        return found

    def sample(self, points: dict, group: str, u_star=None) -> dict:
        """The group's outputs at the 1-D sample ``points`` (``{dim: array}``, names as
        one-element arrays), for timing (:mod:`agglomtool.maps.estimate`)."""
        dims = self.group_dims[group]
        args = [points[d] for d in dims]
        if group == "collision":
            args.append(u_star)
        vals = _block_function(self.base, dims, group, int(self.nodes))(*args)
        return dict(zip(GROUPS[group][1], vals, strict=True))

    def __getstate__(self):  # the fields only: caches are rebuilt where it is unpickled
        return {k: getattr(self, k) for k in ("base", "grid", "chunks", "nodes", "materials")}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)

    # -- construction ---------------------------------------------------------------------

    @classmethod
    def from_dataset(cls, ds) -> SweepPlan:
        """The plan of a sweep Dataset made by :func:`agglomtool.maps.build` (its scene,
        grid, chunks and nodes are in its attributes, coordinates and chunks)."""
        try:
            base = json.loads(ds.attrs["scene"])
            order = json.loads(ds.attrs["grid"])
            nodes = int(ds.attrs["quadrature_nodes"])
        except (KeyError, TypeError, ValueError):
            raise ValueError("the Dataset is not a sweep made by agglomtool.maps.build (its "
                             "attributes scene, grid and quadrature_nodes are missing)") from None
        grid = {d: np.asarray(ds[d].values) for d in order}
        chunks = {d: tuple(int(c) for c in ds.chunks[d]) if ds.chunks and d in ds.chunks
                  else (len(grid[d]),) for d in order}
        return cls(base, grid, chunks, nodes, _snapshot())


def _snapshot():
    """The materials snapshot of the run in progress (:func:`agglomtool.materials.pinned`),
    else the files read now: a plan computes from the files as they were when it was made."""
    from .. import materials

    return materials.current() or materials.snapshot()


def _plan(scene: Scene, chunks, nodes, grid: dict, drawn: tuple = ()):
    """The validated :class:`~agglomtool.maps.plan.SweepPlan` of a sweep's arguments
    (``drawn``: the speed models a robust map may draw, which read fields too)."""
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be an agglomtool Scene, got {type(scene).__name__}")
    if not isinstance(nodes, int | np.integer) or nodes < 1:
        raise ValueError(f"nodes = {nodes!r} must be an integer >= 1")
    values = _grid_values(scene, grid, drawn=drawn)
    sizes = _chunks(values, chunks)
    return SweepPlan(scene.values(), values,
                     {k: _split(len(v), sizes[k]) for k, v in values.items()}, int(nodes),
                     _snapshot())


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
                     [plan.grid[k] for k in plan.grid], plan.chunks, plan.nodes, __version__,
                     plan.materials.key if plan.materials is not None else None)
    bname, pkey = f"agglomtool-sweep-{token}", f"agglomtool-sweep-plan-{token}"
    blocks: dict[Any, Any] = {pkey: plan}
    for idx, _ in plan.blocks():
        blocks[(bname, *idx)] = (_block_task, pkey, list(idx))
    out = {}
    for name in plan.lazy_names:
        dims, dtype, _ = plan.variables[name]
        vname = f"{name}-{token}"
        layer: dict[Any, Any] = {}
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
