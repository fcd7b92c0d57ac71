"""The layout of a sweep: the output groups, the validation of a grid at the values it
sweeps, block sizes, the block function of each group and the map's global attributes.

The lowest module of :mod:`agglomtool.maps`: the plan of a sweep
(:mod:`agglomtool.maps.plan`), its estimate, its store and its cluster path build on it, and
:func:`agglomtool.maps.sweep` (:mod:`agglomtool.maps.grid`) on all of them.
"""

from __future__ import annotations

import itertools
import json
import logging
import re

import numpy as np

from .._fields import CHOICES
from .._validate import check_typed, material_key
from .._version import __version__
from ..plausibility import scene_findings, warn_findings
from ..scene import (
    CATEGORICAL_FIELDS,
    NUMERIC_FIELDS,
    Resolved,
    Scene,
    assumed_inputs,
    critical_outputs,
    provenance,
    swept_without_effect,
    validate,
)
from ..units import to_si_array
from .meta import (
    FIELD_META,
    call_text,
    global_attrs,
    provenance_attr,
)
from .speed_flag import flagged_collision_outputs

__all__ = ["GROUPS", "DEFAULT_BLOCK", "IN_MEMORY_BLOCK", "auto_block", "sweep_chunks",
           "SPEED_FIELDS", "GridError", "grid_findings"]

logger = logging.getLogger("agglomtool.maps")

#: Default number of grid points per block of a map that is not computed in memory here
#: (a store's chunks, a cluster's tasks, a lazy map's dask blocks).
DEFAULT_BLOCK = 2**18

#: Points per block of a map computed in memory in this process with ``chunks="auto"``
#: on up to 7 threads (:func:`auto_block`). A block's temporaries beside the result it
#: writes into are about 16 bytes per point (the 4e6-point maps of
#: ``benchmarks/bench_scaling.py``, peak memory over the result's: 3-4 MB with blocks of
#: 2**18 points, 16 MB with 2**20, 65 MB with 2**22).
IN_MEMORY_BLOCK = 2**20

#: The most times :data:`IN_MEMORY_BLOCK` that :func:`auto_block` gives (about 130 MB of
#: temporaries).
MAX_BLOCK_FACTOR = 8


def auto_block(threads: int) -> int:
    """Points per block of a map computed in memory in this process with ``chunks="auto"``
    on ``threads`` threads: :data:`IN_MEMORY_BLOCK` up to 7 threads, ``threads // 4``
    times it above (at most :data:`MAX_BLOCK_FACTOR` times).

    Each block is a few compiled parallel launches, and between them the calling thread
    works alone (Python, the block's numpy steps, a launch's start and end): about 1.7 ms
    per block on the 2-core development machine, whatever its size. A 1e6-point map in
    one block instead of four took 4 % less time there (water, excess-gas speeds; 3 %
    slag), and a 4e6-point map on 16 threads in one block instead of four 6 % less
    (water; 4 % slag); the block size within a launch (the fused loop's pieces) made no
    difference. Only the in-memory path: a store's or a cluster's blocks are its chunks
    and tasks (:data:`DEFAULT_BLOCK`), whose size must not depend on the machine that
    starts the sweep. The values do not depend on the block (each point is computed
    alone)."""
    return IN_MEMORY_BLOCK * min(MAX_BLOCK_FACTOR, max(1, int(threads) // 4))


def sweep_chunks(chunks, in_memory: bool):
    """The ``chunks`` a sweep plans with: :func:`auto_block` on Numba's thread count for
    ``"auto"`` where the map is computed in memory in this process (``in_memory``), else
    ``chunks`` as given. Written once for :func:`agglomtool.maps.sweep` and
    :func:`agglomtool.maps.estimate.estimate_sweep`, which must plan the same blocks."""
    if isinstance(chunks, str) and chunks == "auto" and in_memory:
        import numba

        return auto_block(numba.get_num_threads())
    return chunks

SPEED_FIELDS = ("u0", "speed", "sigma_ln", "granular_temperature", "fluctuation_ratio",
                "U", "U_Umf", "bed_height", "column_diameter", "orifice_area", "height",
                "wake_fraction")
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
                         "propensity", "margin", "speed_flag"),
                  (float, float, float, bool, np.int8, float, float, float, np.int8)),
}


class GridError(ValueError):
    """A grid that cannot be swept; ``field`` is the swept field the message blames (None
    where it blames none of them)."""

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field


def check_sweep_options(*, nodes, compute, client, progress, overwrite, uncertain=None,
                        samples=None, threshold=None, seed=None) -> None:
    """The options of :func:`agglomtool.sweep`, before any work: a ``ValueError`` naming the
    option, its value and what is allowed (``nodes=1.5``, ``compute="x"``, ``client="abc"``
    were taken as they came, or failed deep inside)."""
    from .._fields import MAX_NODES
    from .._validate import check_bool, check_int
    from ..uncertainty._sampling import resolve_seed

    check_int("nodes", nodes, 1, MAX_NODES)
    for name, value in (("compute", compute), ("progress", progress),
                        ("overwrite", overwrite)):
        check_bool(name, value)
    if client is not None and client is not False and not (
            hasattr(client, "submit") and hasattr(client, "gather")):
        raise ValueError(f"client = {client!r} is not allowed: a dask.distributed Client, "
                         "None (the active client, if any) or False (compute here)")
    if uncertain is not None:  # a robust map's, before its nominal map is computed
        from .robust import check_robust_options

        check_robust_options(samples, threshold)
        resolve_seed(seed)


def _blamed(message: str, names) -> str | None:
    """The swept field (of ``names``) whose value ``message`` states first, if any."""
    found = [(m.start(), k) for k in names
             for m in [re.search(rf"(?<![\w.]){re.escape(k)} = ", message)] if m]
    return min(found)[1] if found else None


#: The fields that name a materials database entry (any spelling that normalises to it).
_MATERIAL_FIELDS = tuple(f for f in CATEGORICAL_FIELDS if f not in CHOICES)


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
            if name in _MATERIAL_FIELDS:  # as the database spells them: one name, one value
                vals = [material_key(v) for v in vals]
            arr = np.array(vals)
        else:
            unit, long_name = FIELD_META[name]
            typed = values
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
                raise GridError(f"grid {name} = {typed!r} is not allowed: a non-empty 1-D list "
                                f"of numbers (got shape {arr.shape})", name)
            try:  # the field's physical range, with what was typed
                check_typed(name, typed, arr)
            except ValueError as exc:
                raise GridError(str(exc), name) from None
        uniq, counts = np.unique(arr, return_counts=True)
        if uniq.size != arr.size:
            twice = uniq[counts > 1][0]
            shown = repr(str(twice)) if name in CATEGORICAL_FIELDS else f"{float(twice)!r}"
            raise GridError(f"grid {name} = {values!r} repeats the value {shown}; allowed: "
                            "unique coordinates", name)
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


def _grid_values(scene: Scene, grid: dict, *, plausibility: bool = True,
                 drawn: tuple = ()) -> dict:
    """Validate the grid, once, at the values swept: each axis alone (1-D, known field,
    units, unique), then every field the model reads together, with each swept field at its
    swept values and never at the scene's value for it (numbers as whole axes, names in
    every combination), properties included. Raises :class:`GridError` naming the swept
    field it blames, also a field that no speed law or model computing on the map reads
    (``drawn``: the models a robust map may draw; see
    :func:`agglomtool.uncertainty.scene_mc.drawn_speeds`); warns the
    plausibility findings the scene has not said already."""
    base = scene.values()
    if not grid:
        raise GridError("grid: none given; a sweep needs at least one field with its values, "
                        "e.g. at.sweep(scene, T=[1000.0, 1100.0]) (for one point: "
                        "scene.evaluate())")
    out = _axes(base, grid)
    try:
        for values in _combinations(base, out):
            validate(values)
        _check_properties(base, out)
    except ValueError as exc:
        raise GridError(str(exc), _blamed(str(exc), out)) from None
    if plausibility:
        # the Scene warned of these already, but for those about its defaults, which it
        # leaves to where they are used: said here where the map uses them
        before = set(scene_findings(base)) - set(getattr(scene, "_deferred_findings", ()))
        warn_findings([f for f in grid_findings(base, out) if f not in before], stacklevel=4)
    found = swept_without_effect(base, out, drawn)
    if found:
        raise GridError(found[1], found[0])
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


def _block_function(scene_values: dict, names: tuple, group: str, nodes: int, out=None):
    """The numpy function of one output group over one block: a tuple of new arrays, one
    per output. With ``out`` (a tuple, one item per output: an array of the block's shape,
    or None) each output is written into its array instead, once, with no block-sized copy
    in between; an output whose item is None is returned as a read-only view."""

    def func(*arrays):
        values = dict(scene_values)
        values.update(zip(names, arrays[: len(names)], strict=True))
        r = Resolved(values)
        shape = np.broadcast_shapes(*[np.shape(a) for a in arrays]) if arrays else ()
        return _finish(_group_outputs(r, group, nodes, out, arrays[-1] if arrays else None),
                       shape, out)

    return func


def _group_outputs(r: Resolved, group: str, nodes: int, out=None, u_star=None) -> tuple:
    """The outputs of ``group`` (``GROUPS``) from the resolved block ``r``, as computed
    (their own shapes); ``u_star``: the collision group's ``u0*``; ``out``: as for
    :func:`_block_function` (the collision group writes its margin into it)."""
    if group == "gas":
        return (r.mu_g, r.rho_g)
    if group == "liquid":
        return (r.liquid.mu, r.liquid.gamma, r.liquid.rho)
    if group == "fluid":
        return (r.Umf, r.U_e)
    if group == "critical":
        c = critical_outputs(r)
        return tuple(c[k] for k in GROUPS["critical"][1])
    into = None if out is None else {
        k: t for k, t in zip(GROUPS["collision"][1], out, strict=True) if t is not None}
    if into and "U" in into:
        r.U_into(into["U"])  # U_Umf * Umf written into its block, not copied there
    c = flagged_collision_outputs(r, u_star, nodes, into)
    return tuple(c[k] for k in GROUPS["collision"][1])


def _finish(outputs: tuple, shape: tuple, into=None) -> tuple:
    """``outputs`` broadcast to the block's ``shape``: new arrays, or (``into``) written
    into its arrays, a view where its item is None (:func:`_block_function`)."""
    if into is None:
        return tuple(np.broadcast_to(o, shape).copy() for o in outputs)
    done = []
    for target, o in zip(into, outputs, strict=True):
        if target is None:  # not wanted: a view, never copied
            done.append(np.broadcast_to(o, shape))
            continue
        if o is not target:  # as ``a[...] = o`` would
            np.copyto(target, np.broadcast_to(o, shape), casting="unsafe")
        done.append(target)
    return tuple(done)


def _split(n: int, c: int) -> tuple:
    """Block sizes of an axis of ``n`` values in blocks of ``c``."""
    return (c,) * (n // c) + ((n % c,) if n % c else ())



def _dataset_attrs(base: dict, grid: dict, nodes: int) -> dict:
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
            "F(u0*) plus the probability of the speeds above u0* at which the pair sticks "
            "again, found in compiled code (modes relative, and paper without body forces "
            "on the axis: agglomtool.collision.sticking), none in mode stokes, elsewhere "
            "bracketed with the tier's kernel from candidates that include "
            f"{nodes} equal-probability nodes above u0* "
            "(agglomtool.collision.sticking_numeric; the nodes' quadrature where no bracket "
            "settles: agglomtool.bed.speeds)"),
        "quadrature_nodes": int(nodes),
        "material_sources": json.dumps(sources),
    }
