"""Writing a map (or a bed) as one compressed CF-1.8 netCDF file."""

from __future__ import annotations

import glob
import os
import reprlib
import socket
import uuid
from pathlib import Path

import numpy as np
import xarray as xr

from .meta import CONVENTIONS, history_line

__all__ = ["write_map", "COMPLEVEL", "cf_ready", "read_names"]

#: zlib level of the written variables: 4 is most of level 9's gain at a fraction of its time.
COMPLEVEL = 4

#: Integer types of netCDF's classic model, which CF-1.8 keeps to (no 64-bit integers).
_INT32 = np.iinfo(np.int32)


def write_map(ds: xr.Dataset, path, *, complevel: int = COMPLEVEL,
              history: str | None = None) -> Path:
    """Write ``ds`` to the netCDF file ``path``, every variable zlib-compressed.

    The file follows the CF-1.8 conventions (:func:`cf_ready`): ``Conventions``, a
    ``history`` line, no fill value on coordinates, flags of the variables' own type. The
    file is written next to ``path`` and renamed when complete, so an interrupted write
    never leaves a truncated map behind. ``complevel=0`` writes uncompressed.

    Parameters
    ----------
    ds : xarray.Dataset
        A map of :func:`agglomtool.sweep`, a bed of :func:`agglomtool.bed_propensity` or
        :func:`agglomtool.bed_sweep`, or any Dataset.
    path : str or Path
        The file to write.
    complevel : int
        zlib level, 0-9.
    history : str, optional
        What to record as the command in the ``history`` line (the command line when the
        CLI writes); default ``agglomtool.write_map(ds, '<file name>')``.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    if not isinstance(complevel, int) or not 0 <= complevel <= 9:
        raise ValueError(f"complevel = {complevel!r} is outside the allowed range 0-9")
    if not isinstance(ds, xr.Dataset):
        raise ValueError(f"ds = {reprlib.repr(ds)} is not allowed: an xarray.Dataset (a map)")
    if not isinstance(path, str | os.PathLike):
        raise ValueError(f"path = {path!r} is not allowed: a file path (str or pathlib.Path)")
    path = check_netcdf_name(path)
    out, encoding = cf_ready(ds, history if history is not None
                             else f"agglomtool.write_map(ds, {path.name!r})")
    if complevel:
        for name, var in out.variables.items():
            if var.dtype.kind in "fiub" and var.ndim > 0:
                encoding[name].update(zlib=True, complevel=complevel, shuffle=True,
                                      chunksizes=_chunk_shape(var.shape))
    tmp = _temporary(path)
    try:
        out.to_netcdf(tmp, encoding=encoding)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


#: File name endings of pictures and documents: a netCDF map written there is a mistake.
_NOT_NETCDF = (".png", ".jpg", ".jpeg", ".svg", ".pdf", ".eps", ".tif", ".tiff", ".csv",
               ".txt", ".toml")


def check_netcdf_name(path) -> Path:
    """:func:`check_output_dir`, and a ``ValueError`` where the name is a directory's, or
    ends as a picture's or a text file's (a netCDF file there would be read as neither)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"output {str(path)!r} is a directory; give a file name (.nc)")
    if path.suffix.lower() in _NOT_NETCDF:
        raise ValueError(f"cannot write a netCDF file as {str(path)!r}: {path.suffix!r} is "
                         "the ending of a picture or a text file; give a name ending in .nc "
                         "(a picture of a map: agglomtool plot MAP.nc -o PICTURE.png)")
    return check_output_dir(path)


def check_output_dir(path) -> Path:
    """``path`` as a Path, if its directory exists and this process may write there; a
    ``ValueError`` naming the directory if it does not, is a file or is not writable
    (netCDF's own error calls them all 'Permission denied', after the work)."""
    path = Path(path)
    parent = path.parent
    if not parent.exists():
        raise ValueError(f"cannot write {str(path)!r}: its directory {str(parent)!r} does not "
                         "exist; create it first or give another path")
    if not parent.is_dir():
        raise ValueError(f"cannot write {str(path)!r}: {str(parent)!r} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):  # before the work whose result it writes
        raise ValueError(f"cannot write {str(path)!r}: its directory {str(parent)!r} is not "
                         "writable (a read-only file system, or no permission); give another "
                         "path")
    return path


def _temporary(path: Path) -> Path:
    """A temporary name next to ``path`` of this write alone (host, process, random part),
    so that writers of the same file never share one; those left by killed processes of
    this host are removed."""
    host = socket.gethostname().replace(".", "_")
    for stale in path.parent.glob(f".{glob.escape(path.name)}.{glob.escape(host)}.*.tmp"):
        try:
            pid = int(stale.name[len(f".{path.name}.{host}."):].split(".")[0])
            os.kill(pid, 0)
        except ProcessLookupError:  # its writer is gone
            stale.unlink(missing_ok=True)
        except (ValueError, OSError):  # not ours, or a live process of another user
            pass
    return path.with_name(f".{path.name}.{host}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")


def cf_ready(ds: xr.Dataset, command: str) -> tuple[xr.Dataset, dict]:
    """``(dataset, encoding)`` that ``to_netcdf`` writes as a CF-1.8 file; ``ds`` is left
    as it is.

    - ``Conventions`` is set where missing; a ``history`` line (UTC time, agglomtool's
      version, ``command``) goes before any earlier lines.
    - A numeric axis whose values are out of order (a grid may list them in any order) is
      written in increasing order, data with it: CF coordinates are strictly monotonic. A
      repeated value is a ValueError naming the coordinate.
    - Coordinates get no ``_FillValue`` (CF 2.5.1: a coordinate has no missing values).
    - ``flag_values`` take the type the variable has in the file (int8 for a boolean,
      which xarray stores as a byte), as CF 3.5 asks; attributes read back from a store
      come as lists of 64-bit integers.
    - 64-bit integers, which CF-1.8's netCDF classic types lack, are written as 32-bit
      ones; a value that does not fit is a ValueError naming the variable.
    """
    if not isinstance(ds, xr.Dataset):
        raise ValueError(f"ds must be an xarray.Dataset, got {type(ds).__name__}")
    out = ds.copy()
    unordered = []
    for dim in out.dims:
        if dim in out.coords and out[dim].dtype.kind in "fiu" and out.sizes[dim] > 1:
            step = np.diff(out[dim].values)
            if np.all(step > 0) or np.all(step < 0):
                continue
            if len(np.unique(out[dim].values)) != out.sizes[dim]:
                raise ValueError(f"coordinate {dim} repeats a value ({out[dim].values}); a "
                                 "CF coordinate is strictly monotonic")
            unordered.append(dim)
    if unordered:
        out = out.sortby(unordered)
    encoding = {}
    for name, var in out.variables.items():
        attrs = dict(var.attrs)
        enc: dict[str, object] = {}  # netCDF encoding: dtype, _FillValue, ...
        stored = np.dtype(np.int8) if var.dtype == bool else var.dtype
        if var.dtype.kind in "iu" and var.dtype.itemsize > 4:
            lo, hi = (int(var.min()), int(var.max())) if var.size else (0, 0)
            if lo < _INT32.min or hi > _INT32.max:
                raise ValueError(f"variable {name}: values {lo}-{hi} are outside the 32-bit "
                                 f"integers ({_INT32.min}-{_INT32.max}) a CF-1.8 file holds")
            stored = np.dtype(np.int32)
            enc["dtype"] = stored
        for key in ("flag_values", "flag_masks"):
            if key in attrs:
                raw = np.atleast_1d(np.asarray(attrs[key]))
                cast = raw.astype(stored)
                if not np.array_equal(cast, raw):
                    raise ValueError(f"variable {name}: {key} = {raw.tolist()} do not fit its "
                                     f"type {stored}")
                attrs[key] = cast
        if name in out.coords:
            enc["_FillValue"] = None
        if _holds_text(var):
            # names as CF character arrays, not netCDF-4 strings: the netCDF library of
            # netCDF4 1.7.3 and later crashes the process (a segmentation fault) when a file
            # holding variable-length strings is opened again after another of its handles
            # was closed (a map open in a session while a picture of it is drawn).
            # read_names turns them back into str.
            enc["dtype"] = "S1"
            enc["_Encoding"] = "utf-8"
        var.attrs = attrs
        encoding[name] = enc
    attrs = dict(out.attrs)
    attrs.setdefault("Conventions", CONVENTIONS)
    earlier = str(attrs.get("history", "")).strip()
    attrs["history"] = history_line(command) + ("\n" + earlier if earlier else "")
    out.attrs = attrs
    return out, encoding


def _holds_text(var) -> bool:
    """Whether ``var`` holds names (numpy str, or objects that are all str)."""
    if var.dtype.kind == "U":
        return True
    return var.dtype.kind == "O" and all(isinstance(x, str) for x in np.ravel(var.values))


def read_names(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with the names a file holds as character arrays (read back by xarray as
    objects) as numpy str again, the form a map has in memory."""
    text = [name for name, var in ds.variables.items()
            if var.dtype.kind == "O" and _holds_text(var)]
    if not text:
        return ds
    coords = {n: ds[n].astype(str) for n in text if n in ds.coords}
    data = {n: ds[n].astype(str) for n in text if n not in ds.coords}
    return ds.assign_coords(coords).assign(data)


def _chunk_shape(shape: tuple, target: int = 2**20) -> tuple:
    """HDF5 chunks of at most about ``target`` elements, whole along the last dimensions
    (small variables are one chunk: the least overhead per byte)."""
    out, room = [], target
    for n in reversed(shape):
        c = max(1, min(n, room))
        out.append(c)
        room = max(1, room // c)
    return tuple(reversed(out))
