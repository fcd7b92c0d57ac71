"""Resumable sweeps: a zarr store written block by block, with provenance and a writer lock.

Layout of a store directory::

    sweep.json        what the sweep is: its fingerprint (see :func:`fingerprint`), the
                      SHA-256 of every layout file, and a SHA-256 over both
    map.zarr/         the grid, laid out once (zarr v3); every block writes its own region
    done/<i_j_..>.json  one completion record per finished block: its checksums
    writer.lock       held (an OS file lock) by the process writing the store
    writer.json       who holds it: process id, host, start time

How nothing is lost or mixed:

* **Provenance.** The fingerprint covers everything that determines the numbers: the base
  scene, the grid (dimensions, values, order), the chunks, the quadrature nodes, the output
  variables, the contents (SHA-256) of every materials file the sweep uses (user files
  included) and the agglomtool version. A run whose fingerprint differs from the store's
  is refused with a :class:`ValueError` listing what differs, unless ``overwrite=True``.
* **Integrity: every byte checked.** Every zarr chunk goes through a CRC32C checksum codec,
  and each completion record holds a CRC-32 of every array region the block wrote. The
  layout files (every ``zarr.json``: metadata and attributes; the coordinates' chunks) are
  listed with their SHA-256 in ``sweep.json``. On every run the layout is compared with one
  made afresh from the sweep's plan, and what differs is rewritten (a :class:`StoreWarning`
  names the files); the finished blocks are read back and checked, and a block that cannot
  be read, fails its checksum or belongs to another sweep is recomputed, with a
  :class:`StoreWarning` saying so. :func:`open_store` checks the record and the layout, and
  every chunk as it is read: a store damaged, changed or deleted after it was opened is a
  ValueError naming it, never values read as missing.
* **One writer.** A second process writing the same store is refused
  (:class:`StoreLockedError`) while the first runs. The lock is an operating-system file
  lock (:mod:`filelock`): the kernel releases it when its holder dies, so a killed run
  never leaves the store locked.
* **Crash safety.** A block's record is written (atomically) only after its data, by the
  process that wrote the data (a worker, on a cluster), so an interrupted run leaves at
  most blocks without records, which the next run recomputes.
  :func:`hold_store` keeps the lock over a whole lifecycle (the CLI's sweep, export and
  removal); :func:`remove_store` deletes the records first, so a removal cut short leaves
  a store the same sweep mends.
* **Inputs read once.** The materials files are read and hashed once, at the start of a
  run (:func:`agglomtool.materials.pinned`); every block, here or on a worker, computes from
  those bytes, and the fingerprint holds their SHA-256.

Each variable is written by exactly one block per zarr chunk: a variable over fewer
dimensions than the grid (``mu_g`` over ``T``, say) is written by the blocks whose index is
0 along the dimensions it lacks. Blocks therefore never write the same chunk, and can run
at the same time on the workers of a dask.distributed cluster (:func:`run_with_store` with
``client=``). The final Dataset is opened lazily from the store; ``open_store(path)
.to_netcdf(file)`` (or :func:`export_netcdf`) writes one netCDF file.
"""

from __future__ import annotations

import base64
import contextlib
import datetime
import hashlib
import json
import os
import shutil
import socket
import sys
import threading
import uuid
import warnings
import zlib
from pathlib import Path
from typing import NamedTuple, cast

import dask
import dask.array
import numpy as np
import xarray as xr

from .cluster import _blocks, _owned, run_blocks

__all__ = ["run_with_store", "open_store", "export_netcdf", "fingerprint", "StoreWarning",
           "hold_store", "remove_store",
           "StoreLockedError", "StoreMismatchError", "FORMAT_VERSION"]

#: Version of the store layout; a store of another layout version is refused.
FORMAT_VERSION = 3
_FORMAT = "agglomtool sweep store"
_RECORD, _DATA, _DONE = "sweep.json", "map.zarr", "done"
_LOCK, _OWNER = "writer.lock", "writer.json"
#: Files of a store; a non-empty directory holding none of them is not a store.
_OURS = {_RECORD, _DATA, _DONE, _LOCK, _OWNER}


class StoreWarning(UserWarning):
    """A store was repaired: unreadable or mismatching blocks or records are recomputed."""


class StoreMismatchError(ValueError):
    """A store holds a different sweep. ``str()`` gives the way out in the API's terms
    (``overwrite=True``); ``for_cli()`` in the command line's (``--overwrite``)."""

    def __init__(self, what: str):
        self.what = what
        super().__init__(f"{what}. Use another store, or pass overwrite=True to discard it "
                         "and start again")

    def for_cli(self) -> str:
        return (f"{self.what}. Give another --store (or -o), or add --overwrite to discard "
                "it and start again")


class StoreLockedError(ValueError):
    """Another process is writing the store."""


# ---------------------------------------------------------------------------------------
# Fingerprint


def _digest(values: np.ndarray) -> dict:
    a = np.ascontiguousarray(values)
    out = {"size": int(a.size), "dtype": a.dtype.str,
           "sha256": hashlib.sha256(a.tobytes()).hexdigest()}
    if a.size:
        out["first"], out["last"] = a.flat[0].item(), a.flat[-1].item()
    return out


def _materials_of(scene: dict, grid: dict) -> dict:
    """``{kind: sorted names}`` of the materials a sweep of the scene values ``scene``
    over ``grid`` (``{dim: values}``) evaluates."""
    kinds = {"solid_i": "solid", "solid_j": "solid", "liquid": "liquid", "gas": "gas"}
    used: dict[str, set] = {}
    for field, kind in kinds.items():
        values = np.asarray(grid[field]).tolist() if field in grid else [scene.get(field)]
        used.setdefault(kind, set()).update(str(v) for v in values if v is not None)
    return {k: sorted(v) for k, v in used.items()}


def fingerprint(ds: xr.Dataset) -> dict:
    """Everything that determines the numbers of the lazy sweep ``ds``, as a JSON-able dict.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep built by :func:`agglomtool.maps.build` (dask-backed).

    Returns
    -------
    dict
        ``format``, ``agglomtool_version``, ``scene`` (the base scene without the swept
        fields), ``dims``, ``grid`` (per dimension: size, dtype, SHA-256, first and last
        value), ``chunks``, ``nodes``, ``variables`` (dims and dtype of every output) and
        ``materials`` (``"kind name" -> "file sha256"`` for every material used).
    """
    return _fingerprint(ds, ds.chunks)


def _fingerprint(ds: xr.Dataset, chunks) -> dict:
    """:func:`fingerprint` with the block sizes ``chunks`` (``{dim: sizes}``) given."""
    return _fingerprint_of(ds.attrs, list(ds.dims), {d: ds[d].values for d in ds.dims},
                           chunks, {k: (v.dims, v.dtype) for k, v in ds.data_vars.items()})


def _fingerprint_of(attrs: dict, dims: list, grid: dict, chunks, variables: dict) -> dict:
    """:func:`fingerprint` of a sweep given by its global attributes ``attrs``, dimensions,
    coordinates (``{dim: values}``), block sizes and ``{variable: (dims, dtype)}``."""
    from .. import materials

    scene = json.loads(attrs.get("scene", "{}"))
    return {
        "format": [_FORMAT, FORMAT_VERSION],
        "agglomtool_version": attrs.get("agglomtool_version"),
        "scene": {k: v for k, v in scene.items() if k not in dims},
        "dims": dims,
        "grid": {d: _digest(grid[d]) for d in dims},
        "chunks": {d: [int(c) for c in chunks[d]] for d in dims} if chunks else {},
        "nodes": attrs.get("quadrature_nodes"),
        "variables": {k: [list(d), np.dtype(t).str] for k, (d, t) in variables.items()},
        "materials": materials.fingerprint(_materials_of(scene, grid)),
    }


def _sha(fp: dict) -> str:
    return hashlib.sha256(json.dumps(fp, sort_keys=True).encode()).hexdigest()


def _short(value, path: str = "") -> str:
    """A stored or new value as the refusal prints it: a dimension's chunk sizes counted,
    with a few of them (``30 chunks [1, 1, 1, ..., 1]``); other values as JSON, cut at 80
    characters."""
    if path.startswith("chunks ") and isinstance(value, list):
        n = len(value)
        shown = value if n <= 4 else [*value[:3], "...", value[-1]]
        return f"{n} chunk{'s' if n != 1 else ''} [{', '.join(str(v) for v in shown)}]"
    text = json.dumps(value, sort_keys=True)
    return text if len(text) <= 80 else text[:77] + "..."


def _differences(old: dict, new: dict) -> list[str]:
    """What differs between two fingerprints, one readable line per leaf."""
    out = []

    def walk(a, b, path):
        if isinstance(a, dict) and isinstance(b, dict):
            for k in sorted(set(a) | set(b), key=str):
                if k not in a:
                    out.append((path, f"{path}{k}: not in the store, now "
                                      f"{_short(b[k], f'{path}{k}')}"))
                elif k not in b:
                    out.append((path, f"{path}{k}: stored {_short(a[k], f'{path}{k}')}, "
                                      "now absent"))
                else:
                    walk(a[k], b[k], f"{path}{k} ")
        elif a != b:
            leaf = path.strip()
            if leaf.startswith("materials ") and isinstance(a, str) and isinstance(b, str):
                (fa, _, _), (fb, _, _) = a.rpartition(" "), b.rpartition(" ")
                what = (f"{fa} has changed since the store was made" if fa == fb
                        else f"stored from {fa}, now from {fb}")
                out.append((leaf.rpartition(" ")[0], f"{leaf}: {what}"))
                return
            out.append((leaf.rpartition(" ")[0],
                        f"{leaf}: stored {_short(a, leaf)}, now {_short(b, leaf)}"))

    walk(old, new, "")
    # a grid dimension's hash is only worth a line when its size, first and last agree
    parents: dict[str, list[str]] = {}
    for parent, line in out:
        parents.setdefault(parent, []).append(line)
    return [line for parent, line in out
            if not (line.split(":")[0].endswith(" sha256")
                    and len(parents[parent]) > 1)]


# ---------------------------------------------------------------------------------------
# Blocks


def _block_name(idx: tuple) -> str:
    return "_".join(str(i) for i in idx) + ".json"


def _crc(a: np.ndarray) -> int:
    return zlib.crc32(np.ascontiguousarray(a).tobytes())


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{socket.gethostname()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


@contextlib.contextmanager
def _quiet_zarr():
    """Silence zarr's note that fixed-length strings (names as coordinates) have no v3 spec
    yet: the store is read back by agglomtool only; the netCDF export is the exchange file."""
    with warnings.catch_warnings():
        try:
            from zarr.errors import UnstableSpecificationWarning

            warnings.simplefilter("ignore", UnstableSpecificationWarning)
        except ImportError:  # pragma: no cover - older zarr
            pass
        yield


def _write_block(plan, data_path: str, region: dict, owned: list, used: dict,
                 expected_materials: dict, done_path: str, head: dict) -> dict:
    """Compute one block, write its region of the store, then its completion record;
    runs locally or on a worker.

    ``plan`` is the sweep's :class:`~agglomtool.maps.plan.SweepPlan`, ``region`` the block's
    ``{dim: slice}``, ``owned`` the variables it writes. The record (``done_path``) is
    ``head`` (the block's index and the sweep's fingerprint) with ``{variable: crc32}`` of
    the data written, written (atomically) after the data, where the data were written: the
    client does no file work per block. Returns the block's :func:`_summary`.
    """
    import zarr

    from .. import materials

    with materials.pinned(plan.materials):  # the files as read at the start of the run
        found = materials.fingerprint(used)
        if found != expected_materials:
            diff = "; ".join(_differences(expected_materials, found))
            raise ValueError(f"on host {socket.gethostname()} the materials files differ "
                             f"from those of the sweep's fingerprint: {diff}")
        values = plan.evaluate(region, owned)
    group = zarr.open_group(data_path, mode="r+")
    crcs = {}
    for name in owned:
        a = np.asarray(values[name]).copy(order="C")  # (ascontiguousarray makes 0-d 1-d)
        cast(zarr.Array, group[name])[tuple(region[d] for d in plan.variables[name][0])] = a
        crcs[name] = _crc(a)
    _atomic_write(Path(done_path), json.dumps({**head, "crc32": crcs}))
    return _summary(values)


#: Variables whose codes a store's run counts block by block, and those whose range it
#: keeps (:func:`_summary`): what the flagged points' warning and the deciding regime read
#: (:func:`agglomtool.maps.speed_flag.warn_flagged`, :func:`agglomtool.maps.regime.
#: deciding_regime`), so that the client never reads the map back for them.
_COUNTED = ("u_star_flag", "speed_flag")
_RANGED = ("mu_l",)


def _summary(values: dict) -> dict:
    """``{name: {code: points}}`` of the counted variables among ``values`` (one block's)
    and ``{name: [min, max]}`` (NaN skipped) of the ranged ones."""
    out: dict = {}
    for name, a in values.items():
        if name in _COUNTED:
            codes, counts = np.unique(np.asarray(a), return_counts=True)
            out[name] = {int(c): int(n) for c, n in zip(codes, counts, strict=True)}
        elif name in _RANGED:
            a = np.asarray(a, dtype=float)
            out[name] = [float(np.fmin.reduce(a, axis=None, initial=np.inf)),
                         float(np.fmax.reduce(a, axis=None, initial=-np.inf))]
    return out


def _add_summary(total: dict, part: dict) -> None:
    """Add a block's :func:`_summary` ``part`` to ``total``."""
    for name, value in part.items():
        if name in _COUNTED:
            counts = total.setdefault(name, {})
            for code, n in value.items():
                counts[code] = counts.get(code, 0) + n
        else:
            lo, hi = total.get(name, (np.inf, -np.inf))
            total[name] = [min(lo, value[0]), max(hi, value[1])]


def _finish_summary(total: dict) -> dict:
    """The summary of a whole map: a range that saw no number is NaN to NaN (as xarray's
    min and max of an all-NaN variable)."""
    return {name: value if name in _COUNTED or value[0] <= value[1] else [np.nan, np.nan]
            for name, value in total.items()}


# ---------------------------------------------------------------------------------------
# The store


def _check_path(store) -> Path:
    if not isinstance(store, str | os.PathLike):
        raise ValueError(f"store = {store!r} must be a directory path (str or Path)")
    path = Path(store)
    if path.exists() and not path.is_dir():
        raise ValueError(f"store = '{path}' is an existing file, not a directory; give the path "
                         "of a directory (created if missing) for the sweep's blocks")
    # the store, or the directory it will be created in: written as the sweep runs, and
    # its writer lock is a file in it even where every block is there
    here = next((p for p in (path, *path.absolute().parents) if p.exists()), None)
    if here is not None and not os.access(here, os.W_OK | os.X_OK):
        raise ValueError(f"store = '{path}' is not writable ('{here}': a read-only file "
                         "system, or no permission): a store holds a writer lock and the "
                         "sweep's blocks; give a directory this process may write")
    return path


#: Writer locks held by this process: lock file -> [FileLock, holding thread, depth]. A
#: thread holding a store's lock may take it again (the CLI holds it around the sweep, the
#: export and the removal of the store); any other taker is refused.
_HELD: dict[str, list] = {}
_HELD_GUARD = threading.Lock()


@contextlib.contextmanager
def _writer_lock(path: Path):
    from filelock import FileLock, Timeout

    key = os.path.realpath(path / _LOCK)
    with _HELD_GUARD:
        held = _HELD.get(key)
        if held is not None and held[1] == threading.get_ident():
            held[2] += 1
        else:
            held = None
    if held is not None:  # taken again by its holder
        try:
            yield
        finally:
            with _HELD_GUARD:
                held[2] -= 1
        return
    lock = FileLock(str(path / _LOCK), timeout=0)
    try:
        lock.acquire()
    except Timeout:
        try:
            who = json.loads((path / _OWNER).read_text())
            by = f"process {who['pid']} on host {who['host']} (since {who['started']})"
        except (OSError, ValueError, KeyError, TypeError):
            by = "another process"
        raise StoreLockedError(
            f"store '{path}' is being written by {by}; wait for it to finish (then run "
            "again: finished blocks are reused) or use another store") from None
    with _HELD_GUARD:
        _HELD[key] = [lock, threading.get_ident(), 1]
    try:
        _atomic_write(path / _OWNER, json.dumps({
            "pid": os.getpid(), "host": socket.gethostname(),
            "started": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")}))
        yield
    finally:
        with _HELD_GUARD:
            _HELD.pop(key, None)
        lock.release()


@contextlib.contextmanager
def hold_store(store):
    """Hold the writer lock of the store directory ``store`` (created if missing) for a
    whole lifecycle: sweep, export and removal (:func:`remove_store`) under one lock, so
    that no other process reuses a store while it is exported or deleted.

    A directory this call created and that holds no sweep when it ends is removed again.

    Raises
    ------
    StoreLockedError
        If another process is writing the store.
    ValueError
        If ``store`` is a file or a directory that is not a sweep store.
    """
    path = _check_path(store)
    _refuse_foreign(path)
    created = not path.exists()
    path.mkdir(parents=True, exist_ok=True)
    try:
        with _writer_lock(path):
            yield path
            if (created and path.is_dir()
                    and not ({p.name for p in path.iterdir()} - {_LOCK, _OWNER})):
                remove_store(path)
    finally:
        if created:
            with contextlib.suppress(OSError):
                path.rmdir()


def remove_store(store) -> None:
    """Delete the sweep store ``store`` under its writer lock (taken here if this thread
    does not hold it already).

    Files go in an order that keeps every intermediate state one that a rerun of the same
    sweep mends: the completion records first (the blocks are then unfinished), then the
    record, the zarr arrays, and last the lock file, unlinked while held. Files that are
    not a store's (none are made by agglomtool) are left, with the directory.
    """
    path = Path(store)
    if not path.is_dir():
        return
    with _writer_lock(path):
        done = path / _DONE
        if done.is_dir():
            for rec in sorted(done.iterdir()):
                rec.unlink(missing_ok=True)
            done.rmdir()
        (path / _RECORD).unlink(missing_ok=True)
        if (path / _DATA).exists():
            shutil.rmtree(path / _DATA)
        for stale in path.glob(".*.tmp"):  # interrupted writes of this or a killed process
            if stale.is_dir():
                shutil.rmtree(stale, ignore_errors=True)
            else:
                stale.unlink(missing_ok=True)
        (path / _OWNER).unlink(missing_ok=True)
        (path / _LOCK).unlink(missing_ok=True)  # while held: a waiter that took the old
        # inode is refused by filelock (it checks that the file it locked still exists)
    with contextlib.suppress(OSError):
        path.rmdir()


class _Layout(NamedTuple):
    """What a store's zarr layout holds, taken from the sweep's plan alone: the sweep
    Dataset's global attributes, dimensions, coordinates (``{dim: (values, attrs)}``),
    variables (``{name: (dims, dtype, attrs, value)}``; the value of a variable over no
    grid dimension, else None) and block sizes (``{dim: sizes}``)."""

    attrs: dict
    dims: list
    coords: dict
    variables: dict
    chunks: dict

    @classmethod
    def of(cls, plan) -> _Layout:
        from .layout import _dataset_attrs
        from .meta import field_attrs, variable_attrs

        variables = {}
        for name, (dims, dtype, _) in plan.variables.items():
            value = None if dims else np.asarray(plan.eager[name])
            variables[name] = (dims, dtype if value is None else value.dtype,
                               variable_attrs(name), value)
        return cls(_dataset_attrs(plan.base, plan.grid, plan.nodes), list(plan.dims),
                   {k: (np.asarray(v), field_attrs(k)) for k, v in plan.grid.items()},
                   variables, dict(plan.chunks))

    def fingerprint(self) -> dict:
        """:func:`fingerprint` of the sweep (the same dict as of its lazy Dataset)."""
        grid = {d: values for d, (values, _) in self.coords.items()}
        return _fingerprint_of(self.attrs, self.dims, grid, self.chunks,
                               {k: v[:2] for k, v in self.variables.items()})


def _cf_attrs(attrs: dict, dtype) -> dict:
    """A variable's attributes as xarray writes them to zarr v3: arrays as lists, and a
    float's ``_FillValue`` (NaN) as the base64 of its bytes."""
    out = {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in attrs.items()}
    if np.dtype(dtype).kind == "f":
        out["_FillValue"] = base64.standard_b64encode(
            np.array(np.nan, dtype=dtype).tobytes()).decode()
    return out


def _layout_files(layout: _Layout, sha: str) -> dict:
    """``{file: bytes}`` of the zarr layout of a sweep (relative POSIX paths under
    ``map.zarr``): the group's and every array's metadata, the coordinates' chunks and the
    values of the variables over no grid dimension; the arrays of the blocks are left
    unwritten. Made with zarr in memory, the same files, byte for byte, as xarray's
    ``to_zarr(compute=False)`` of the sweep's template writes (tests/test_store_layout.py),
    without its dask graph and its file-system round trip per array."""
    import zarr
    from zarr.codecs import Crc32cCodec, ZstdCodec

    files: dict = {}
    with _quiet_zarr():
        group = zarr.create_group(zarr.storage.MemoryStore(files), zarr_format=3,
                                  attributes={**layout.attrs, "store_fingerprint_sha256": sha})
        for name, (dims, dtype, attrs, value) in layout.variables.items():
            arr = group.create_array(
                name, shape=tuple(len(layout.coords[d][0]) for d in dims), dtype=dtype,
                chunks=tuple(layout.chunks[d][0] for d in dims),
                compressors=[ZstdCodec(level=1), Crc32cCodec()],
                fill_value=np.nan if np.dtype(dtype).kind == "f" else None,
                attributes=_cf_attrs(attrs, dtype), dimension_names=dims)
            if value is not None:
                arr[...] = value
        for name, (values, attrs) in layout.coords.items():
            arr = group.create_array(
                name, shape=values.shape, dtype=values.dtype,
                fill_value=np.nan if values.dtype.kind == "f" else None,
                attributes=_cf_attrs(attrs, values.dtype), dimension_names=(name,))
            arr[...] = values
    return {k: v.to_bytes() for k, v in files.items()}


def _write_files(data: Path, files: dict) -> None:
    """Write ``{relative path: bytes}`` under ``data``."""
    made = set()
    for rel, content in files.items():
        target = data / rel
        if target.parent not in made:
            target.parent.mkdir(parents=True, exist_ok=True)
            made.add(target.parent)
        target.write_bytes(content)


def _write_layout(layout: _Layout, data: Path, fp: dict) -> dict:
    """Write the zarr layout of the sweep at ``data``: metadata, coordinates, empty arrays;
    returns its manifest (:func:`_manifest`)."""
    files = _layout_files(layout, _sha(fp))
    _write_files(data, files)
    return _files_manifest(files, layout.variables)


def _files_manifest(files: dict, data_vars) -> dict:
    """:func:`_manifest` of layout files in memory (``{file: bytes}``)."""
    return {rel: hashlib.sha256(files[rel]).hexdigest() for rel in sorted(files)
            if _is_layout_file(rel, data_vars)}


def _is_layout_file(rel: str, data_vars) -> bool:
    """Whether the file ``rel`` (relative to ``map.zarr``) belongs to the layout: the
    group's and every array's ``zarr.json`` and every file outside the data variables
    (the coordinates' chunks); the chunks of the data variables are the blocks' (checked
    against their completion records)."""
    parts = rel.split("/")
    return parts[0] not in data_vars or parts[1:] == ["zarr.json"]


def _manifest(data: Path, data_vars) -> dict:
    """``{file: sha256}`` of the layout files under ``data`` (relative POSIX paths). Only
    the layout is walked: of a data variable's folder, its ``zarr.json`` alone, so the
    time does not grow with the blocks written."""
    files = []
    with os.scandir(data) as top:
        for entry in top:
            if not entry.is_dir():
                files.append(entry.name)
            elif entry.name in data_vars:
                files.append(f"{entry.name}/zarr.json")
            else:
                for folder, _, names in os.walk(entry.path):
                    rel = Path(folder).relative_to(data).as_posix()
                    files += [f"{rel}/{n}" for n in names]
    out = {}
    for rel in sorted(files):
        p = data / rel
        if p.is_file() and _is_layout_file(rel, data_vars):
            out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def _record_text(fp: dict, manifest: dict) -> str:
    """The record ``sweep.json``: the fingerprint, the manifest of the layout files, and a
    SHA-256 over both (``check``) that tells a damaged record from another sweep's."""
    body = {"fingerprint": fp, "layout": manifest}
    return json.dumps({**body, "sha256": _sha(fp), "check": _sha(body)}, indent=1)


def _layout(layout: _Layout, path: Path, fp: dict) -> None:
    """Clear the store and lay out the grid: coordinates, metadata, empty arrays."""
    _clear(path)
    (path / _DONE).mkdir()
    manifest = _write_layout(layout, path / _DATA, fp)
    _atomic_write(path / _RECORD, _record_text(fp, manifest))


def _mend_layout(layout: _Layout, path: Path, fp: dict, stacklevel: int = 4) -> dict:
    """Compare every layout file of the store (metadata, attributes, coordinates) with a
    layout made afresh from the plan; replace what differs or is missing, delete what the
    layout does not hold, with a :class:`StoreWarning` naming the files. Returns the
    manifest of the layout."""
    data = path / _DATA
    files = _layout_files(layout, _sha(fp))
    fresh = _files_manifest(files, layout.variables)
    have = _manifest(data, set(layout.variables)) if data.is_dir() else {}
    bad = sorted((k for k in set(fresh) | set(have) if fresh.get(k) != have.get(k)),
                 key=lambda k: (not k.endswith("zarr.json"), k))  # metadata named first
    for rel in bad:
        target = data / rel
        if rel in fresh:
            target.parent.mkdir(parents=True, exist_ok=True)
            tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
            tmp.write_bytes(files[rel])
            os.replace(tmp, target)
        else:
            target.unlink(missing_ok=True)
            for parent in target.parents:  # and the folders it leaves empty
                if parent == data:
                    break
                with contextlib.suppress(OSError):
                    parent.rmdir()
    if bad:
        what = ", ".join(f"{_DATA}/{r}" for r in bad[:4]) + (
            f" (and {len(bad) - 4} more)" if len(bad) > 4 else "")
        warnings.warn(f"store '{path}': {what} did not match the sweep's layout (damaged, "
                      "missing or from another sweep); rewritten from the sweep's plan",
                      StoreWarning, stacklevel=stacklevel)
    return fresh


def _clear(path: Path) -> None:
    for name in (_DATA, _DONE):
        if (path / name).exists():
            shutil.rmtree(path / name)
    (path / _RECORD).unlink(missing_ok=True)


def _load_record(path: Path) -> tuple[dict | None, str | None]:
    """``(record, None)`` of the store ``path``'s ``sweep.json`` if it is whole (its
    ``check`` holds); ``(None, why)`` if missing (``why`` None) or damaged."""
    try:
        record = json.loads((path / _RECORD).read_bytes().decode("utf-8"))
    except FileNotFoundError:
        return None, None
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        return None, f"unreadable ({type(exc).__name__}: {exc})"
    if not (isinstance(record, dict) and isinstance(record.get("fingerprint"), dict)
            and isinstance(record.get("layout"), dict)):
        return None, "not a record of this store layout"
    if record.get("check") != _sha({"fingerprint": record["fingerprint"],
                                    "layout": record["layout"]}):
        return None, "fails its checksum"
    return record, None


def _read_record(path: Path):
    """The whole record of the store, or ``None``; a damaged one is said
    (:class:`StoreWarning`) and rebuilt by the caller."""
    record, why = _load_record(path)
    if why is not None:
        warnings.warn(f"{path / _RECORD} is {why}; it is rebuilt", StoreWarning, stacklevel=4)
    return record


def _zarr_sha(path: Path):
    """The fingerprint SHA-256 kept in the zarr metadata, or ``None``."""
    try:
        meta = json.loads((path / _DATA / "zarr.json").read_text())
        return meta["attributes"]["store_fingerprint_sha256"]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _refuse_foreign(path: Path) -> None:
    """Refuse a non-empty directory holding none of a store's files (never touch it)."""
    entries = {p.name for p in path.iterdir()} if path.is_dir() else set()
    if entries and not entries & _OURS:
        old = " written by an older agglomtool" if "manifest.json" in entries else ""
        raise ValueError(
            f"store = '{path}' is a directory that is not a sweep store{old} and is not "
            f"empty (it holds {', '.join(sorted(entries)[:3])}"
            f"{', ...' if len(entries) > 3 else ''}); give a new or empty directory"
            + (", or delete it" if old else ""))


def _refuse_other_layout(path: Path) -> None:
    """Refuse a store whose readable record says it has another layout version."""
    try:
        layout = json.loads((path / _RECORD).read_text())["fingerprint"]["format"]
    except (OSError, ValueError, KeyError, TypeError):
        return
    if layout != [_FORMAT, FORMAT_VERSION] and isinstance(layout, list) and layout[:1] == [
            _FORMAT]:
        raise StoreMismatchError(
            f"store '{path}' has the layout of another agglomtool ({layout[1]!r}; this one "
            f"writes {FORMAT_VERSION})")


def _prepare(layout: _Layout, path: Path, fp: dict, overwrite: bool) -> None:
    """Make ``path`` a store of the sweep of ``layout``: new, resumed, or refused."""
    sha = _sha(fp)
    entries = {p.name for p in path.iterdir()} - {_LOCK, _OWNER}
    if not entries:
        _layout(layout, path, fp)
        return
    if not entries & _OURS:
        _refuse_foreign(path)
    if overwrite:
        _layout(layout, path, fp)
        return
    _refuse_other_layout(path)
    record = _read_record(path)
    stored = record["fingerprint"] if record is not None else None
    if stored is not None and _sha(stored) != sha:
        lines = _differences(stored, fp)
        raise StoreMismatchError(
            f"store '{path}' holds a different sweep; what differs: " + "; ".join(lines))
    zsha = _zarr_sha(path)
    if stored is None and zsha is not None and zsha != sha:
        raise StoreMismatchError(
            f"store '{path}' holds a different sweep (its fingerprint {zsha[:12]} is not "
            f"this sweep's {sha[:12]}; its record {_RECORD} is missing or unreadable, so the "
            "differences cannot be listed)")
    finished = (path / _DONE).is_dir() and any((path / _DONE).iterdir())
    if stored is None and (zsha != sha or not finished):
        # nothing says which sweep the blocks are of, or no block was finished (a layout
        # interrupted before its record): lay it out again
        if finished:
            warnings.warn(f"store '{path}': neither {_RECORD} nor the zarr metadata says "
                          "which sweep it holds; every block is recomputed", StoreWarning,
                          stacklevel=3)
        _layout(layout, path, fp)
        return
    # this sweep's store (by its record, or by the zarr metadata where the record was lost
    # after blocks were finished): every layout file checked and mended from the plan
    (path / _DONE).mkdir(exist_ok=True)
    manifest = _mend_layout(layout, path, fp)
    if record is None or record["layout"] != manifest:
        _atomic_write(path / _RECORD, _record_text(fp, manifest))


def _check_blocks(dims: list, path: Path, sha: str, blocks, var_dims: dict,
                  summary: dict | None = None) -> tuple[set, list]:
    """Read back every recorded block; ``(good indices, [(index, reason)] of bad ones)``.
    The good blocks' :func:`_summary` is added to ``summary``, where given."""
    import zarr

    good, bad = set(), []
    try:
        with _quiet_zarr():
            group = zarr.open_group(str(path / _DATA), mode="r")
    except Exception as exc:  # noqa: BLE001 - any damage means: recompute everything
        return set(), [(None, f"the zarr group cannot be opened ({exc})")]
    for idx, sl in blocks:
        rec_path = path / _DONE / _block_name(idx)
        if not rec_path.exists():
            continue
        reason = None
        try:
            rec = json.loads(rec_path.read_text())
            owned = _owned(var_dims, dims, idx)
            if rec.get("fingerprint") != sha:
                reason = "its record belongs to another sweep"
            elif sorted(rec.get("crc32", {})) != sorted(owned):
                reason = "its record lists other variables"
            else:
                read = {}
                for name in owned:
                    read[name] = np.asarray(cast(zarr.Array, group[name])[
                        tuple(sl[d] for d in var_dims[name])])
                    if _crc(read[name]) != rec["crc32"][name]:
                        reason = f"{name} fails its checksum"
                        break
        except Exception as exc:  # noqa: BLE001 - unreadable for any reason: recompute
            reason = f"it cannot be read ({type(exc).__name__}: {exc})"
        if reason is None:
            good.add(idx)
            if summary is not None:
                _add_summary(summary, _summary(read))
        else:
            bad.append((idx, reason))
            rec_path.unlink(missing_ok=True)
    return good, bad


def _active_client():
    """The dask.distributed Client in effect, if distributed is in use; else ``None``."""
    if "distributed" not in sys.modules:
        return None
    from distributed import default_client

    try:
        return default_client()
    except ValueError:
        return None


def run_with_store(ds: xr.Dataset, store, *, progress: bool = False, overwrite: bool = False,
                   client=None, verify: bool = True) -> xr.Dataset:
    """Compute the lazy sweep ``ds`` block by block into the zarr store ``store``.

    Finished blocks of an earlier run of the same sweep are checked and reused; blocks that
    are missing, unreadable or fail their checksum are computed.

    Parameters
    ----------
    ds : xarray.Dataset
        A lazy sweep (:func:`agglomtool.maps.build`). Its blocks are evaluated from the
        scene, grid, chunks and nodes it records (:class:`~agglomtool.maps.plan.SweepPlan`),
        not through its task graph.
    store : str or path
        A directory (created if missing): new, empty, or a store of the same sweep.
    progress : bool
        Show a progress bar (tqdm) on stderr: points and blocks done, rate, time left.
    overwrite : bool
        Discard a store of a different sweep and start again (only a directory that is a
        sweep store is ever cleared).
    client : distributed.Client, optional
        Run the blocks as tasks on this cluster's workers, each writing its own region; the
        store must be a path the workers can reach (a shared file system). ``None``: the
        active client if there is one, else this process.
    verify : bool
        Read back and check every finished block of an earlier run (the default).

    Returns
    -------
    xarray.Dataset
        The sweep, opened lazily from the store (:func:`open_store`).

    Raises
    ------
    ValueError
        If ``store`` is a file or a non-empty directory that is not a sweep store, or holds
        a different sweep (the message lists what differs) and ``overwrite`` is False.
    StoreLockedError
        If another process is writing the store.

    Warns
    -----
    StoreWarning
        When finished blocks are unreadable, fail their checksum or belong to another
        sweep: they are recomputed.
    """
    from .. import materials
    from .plan import SweepPlan

    plan = SweepPlan.from_dataset(ds)
    with materials.pinned(plan.materials):
        out = _run_store(plan, store, progress=progress, overwrite=overwrite, client=client,
                         verify=verify)
    materials.warn_if_changed(plan.materials, "the sweep")
    return out


def _run_store(plan, store, *, progress: bool = False, overwrite: bool = False, client=None,
               verify: bool = True, announce=None, summary: dict | None = None
               ) -> xr.Dataset:
    """:func:`run_with_store` of a :class:`~agglomtool.maps.plan.SweepPlan`: its blocks
    evaluated one by one (or on a cluster's workers), each written to its region.
    ``announce(seconds, method)`` is called once, before the progress bar: after a few
    timed blocks computed here (:func:`agglomtool.maps.estimate.run_blocks_here`).
    ``summary``, where given, receives the whole map's :func:`_summary` (the flags' code
    counts, the range of ``mu_l``) from its blocks as they are written or checked; it is
    left empty where ``verify`` is False (finished blocks are then not read)."""
    from .estimate import run_blocks_here
    from .progress import SweepBar

    path = _check_path(store)
    if not isinstance(overwrite, bool):
        raise ValueError(f"overwrite = {overwrite!r} must be True or False")
    _refuse_foreign(path)
    path.mkdir(parents=True, exist_ok=True)
    layout = _Layout.of(plan)
    fp = layout.fingerprint()
    sha = _sha(fp)
    dims = layout.dims
    var_dims = {k: tuple(v[0]) for k, v in layout.variables.items()}
    if client is None:
        client = _active_client()
    with _writer_lock(path):
        _prepare(layout, path, fp, overwrite)
        total: dict = {}
        if verify:
            good, bad = _check_blocks(dims, path, sha, plan.blocks(), var_dims, total)
        else:
            good, bad = {idx for idx, _ in plan.blocks()
                         if (path / _DONE / _block_name(idx)).exists()}, []
        if bad:
            where = "block" if bad[0][0] is None else f"block {bad[0][0]}"
            warnings.warn(
                f"store '{path}': {len(bad)} finished block(s) are recomputed: {where}: "
                f"{bad[0][1]}" + (f" (and {len(bad) - 1} more)" if len(bad) > 1 else ""),
                StoreWarning, stacklevel=3)
        todo = ((idx, sl) for idx, sl in plan.blocks() if idx not in good)
        expected = fp["materials"]
        used = _materials_of(json.loads(layout.attrs["scene"]), plan.grid)
        data_path = str(path / _DATA)

        def task(idx, sl):
            return (data_path, sl, _owned(var_dims, dims, idx), used, expected,
                    str(path / _DONE / _block_name(idx)),
                    {"block": list(idx), "fingerprint": sha})

        done_points = sum(plan.block_points(plan.block_slices(i)) for i in good)
        bar = None

        def start(seconds=None, method=None):
            nonlocal bar
            if announce is not None:
                announce(seconds, method)
            bar = SweepBar(plan.points, plan.n_blocks, f"sweep -> {path}", progress)
            bar.update(done_points, len(good))

        def record(idx, part):  # the block and its record are written
            _add_summary(total, part)
            bar.update(plan.block_points(plan.block_slices(idx)))

        try:
            if client is not None and client is not False and len(good) < plan.n_blocks:
                start()
                run_blocks(client, todo, task, _write_block, record, shared=plan)
            else:
                run_blocks_here(plan, lambda idx, sl: _write_block(plan, *task(idx, sl)),
                                lambda idx, sl, result: record(idx, result), start, good)
        finally:
            if bar is not None:
                bar.close()
    if summary is not None and verify:
        summary.update(_finish_summary(total))
    return open_store(path)


def open_store(store) -> xr.Dataset:
    """The Dataset of a finished store, opened lazily (dask) from its zarr arrays.

    Every byte is checked: the record (``sweep.json``) against its own checksum, the
    layout files (metadata, attributes, coordinates) against the record's manifest, and
    every chunk, as it is read, against its block's completion record. A chunk that no
    longer matches (the store changed or was deleted after it was opened) is a ValueError
    naming the store, never a value silently read as missing.

    Raises
    ------
    ValueError
        If ``store`` is not a sweep store, some blocks are not finished, or a file of it is
        damaged (the message names the file; running the sweep again mends it).
    """
    path = Path(store)
    record, why = _load_record(path)
    if record is None:
        try:
            legacy = json.loads((path / _RECORD).read_text())["fingerprint"]["format"]
        except (OSError, ValueError, KeyError, TypeError):
            legacy = None
        if legacy is not None and legacy != [_FORMAT, FORMAT_VERSION]:
            raise ValueError(f"store {path} has layout {legacy}, this agglomtool reads "
                             f"{[_FORMAT, FORMAT_VERSION]}; run the sweep again into a new "
                             "store (or with overwrite=True / --overwrite)")
        if why is None:
            raise ValueError(f"{path} is not a sweep store (no readable {_RECORD}); run the "
                             "sweep with store= to make one")
        raise ValueError(f"store {path}: {path / _RECORD} is {why}; run the same sweep "
                         "again with this store to mend it")
    fp = record["fingerprint"]
    if fp.get("format") != [_FORMAT, FORMAT_VERSION]:
        raise ValueError(f"store {path} has layout {fp.get('format')}, this agglomtool reads "
                         f"{[_FORMAT, FORMAT_VERSION]}; run the sweep again into a new store")
    dims = fp["dims"]
    data_vars = set(fp["variables"])
    have = _manifest(path / _DATA, data_vars) if (path / _DATA).is_dir() else {}
    bad = sorted(k for k in set(have) | set(record["layout"])
                 if have.get(k) != record["layout"].get(k))
    if bad:
        raise ValueError(f"store {path}: {path / _DATA / bad[0]}"
                         + (f" (and {len(bad) - 1} more files)" if len(bad) > 1 else "")
                         + " does not match the store's record (damaged, missing or from "
                         "another sweep); run the same sweep again with this store to mend it")
    sha = record["sha256"]
    blocks = list(_blocks({d: fp["chunks"][d] for d in dims}))
    crcs, missing = {}, []
    for idx, _ in blocks:
        try:
            rec = json.loads((path / _DONE / _block_name(idx)).read_text())
            if rec.get("fingerprint") != sha:
                raise ValueError("another sweep's record")
            crcs[idx] = rec["crc32"]
        except (OSError, ValueError, KeyError, TypeError):
            missing.append(idx)
    if missing:
        raise ValueError(f"store {path} is incomplete: {len(missing)} of {len(blocks)} blocks "
                         f"missing or unreadable (first: {missing[0]}); run the sweep again to "
                         "finish it")
    with _quiet_zarr():
        ds = xr.open_zarr(path / _DATA, consolidated=False, zarr_format=3)
    ds.attrs.pop("store_fingerprint_sha256", None)
    token = uuid.uuid4().hex[:12]
    checked = {}
    for name in fp["variables"]:
        var = ds[name].variable
        chunks = tuple(tuple(fp["chunks"][d]) for d in var.dims)
        reader = _CheckedArray(path, name, var.dims, dims, chunks, crcs,
                               var.dtype, var.shape)
        data = dask.array.from_array(reader, chunks=chunks, asarray=False, lock=False,
                                     name=f"agglomtool-store-{name}-{token}",
                                     meta=np.empty((0,) * var.ndim, dtype=var.dtype))
        checked[name] = var.copy(data=data)
    return ds.assign(checked)  # one merge for all the variables, not one each


class _CheckedArray:
    """The zarr array ``name`` of a store, read one block's chunk at a time and checked
    against the block's completion record (its CRC-32) as it is read."""

    def __init__(self, path: Path, name: str, var_dims, dims, chunks, crcs, dtype, shape):
        self.path, self.name, self.var_dims, self.dims = path, name, tuple(var_dims), dims
        self.starts = [np.concatenate([[0], np.cumsum(c)]).astype(int) for c in chunks]
        self.crcs, self.dtype, self.shape = crcs, np.dtype(dtype), tuple(shape)
        self.ndim = len(self.shape)
        self._array = None

    def __getstate__(self):  # (to a worker) without the open zarr array
        return {**self.__dict__, "_array": None}

    def __getitem__(self, key):
        key = key if isinstance(key, tuple) else (key,)
        sl = [k.indices(n) for k, n in zip(key, self.shape, strict=True)]
        if any(stop <= start for start, stop, _ in sl):
            return np.empty(tuple(max(0, stop - start) for start, stop, _ in sl), self.dtype)
        at = {}
        for d, (start, stop, _), st in zip(self.var_dims, sl, self.starts, strict=True):
            j = int(np.searchsorted(st, start))
            if st[j] != start or st[j + 1] != stop:
                raise ValueError(f"store {self.path}: {self.name} read across blocks")
            at[d] = j
        idx = tuple(at.get(d, 0) for d in self.dims)
        where = f"store {self.path}: {self.name} of block {idx}"
        try:
            import zarr

            if self._array is None:
                with _quiet_zarr():
                    self._array = zarr.open_array(str(self.path / _DATA / self.name),
                                                  mode="r")
            a = np.asarray(self._array[tuple(slice(a, b) for a, b, _ in sl)])
        except Exception as exc:  # noqa: BLE001 - a damaged or vanished file: say which
            raise ValueError(f"{where} cannot be read ({type(exc).__name__}: {exc}); the "
                             "store was changed or deleted after it was opened; run the "
                             "sweep again") from None
        if _crc(a) != self.crcs[idx].get(self.name):
            raise ValueError(f"{where} no longer matches its completion record (the store was "
                             "changed or deleted after it was opened); run the sweep again "
                             "with this store to mend it")
        return a


def export_netcdf(store, output) -> Path:
    """Write the finished store as one netCDF file ``output`` (atomically); returns its path.

    Variables are compressed (zlib level 4, lossless); the file is CF-1.8, as
    :func:`agglomtool.write_map` writes.
    """
    from .export import write_map

    ds = open_store(store)
    try:
        with dask.config.set(scheduler="synchronous"):
            return write_map(ds, output, history="agglomtool.maps.store.export_netcdf("
                             f"{str(store)!r}, {str(output)!r})")
    finally:
        ds.close()
