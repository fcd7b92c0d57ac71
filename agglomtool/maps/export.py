"""Writing a map as one compressed netCDF file."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

__all__ = ["write_map", "COMPLEVEL"]

#: zlib level of the written variables: 4 is most of level 9's gain at a fraction of its time.
COMPLEVEL = 4


def write_map(ds: xr.Dataset, path, *, complevel: int = COMPLEVEL) -> Path:
    """Write ``ds`` to the netCDF file ``path``, every variable zlib-compressed.

    The file is written next to ``path`` and renamed when complete, so an interrupted write
    never leaves a truncated map behind. ``complevel=0`` writes uncompressed.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    if not isinstance(complevel, int) or not 0 <= complevel <= 9:
        raise ValueError(f"complevel = {complevel!r} is outside the allowed range 0-9")
    path = Path(path)
    encoding = {}
    if complevel:
        for name, var in ds.variables.items():
            if var.dtype.kind in "fiub" and var.ndim > 0:
                encoding[name] = {"zlib": True, "complevel": complevel, "shuffle": True,
                                  "chunksizes": _chunk_shape(var.shape)}
    tmp = path.with_name(path.name + ".tmp")
    try:
        ds.to_netcdf(tmp, encoding=encoding)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path


def _chunk_shape(shape: tuple, target: int = 2**20) -> tuple:
    """HDF5 chunks of at most about ``target`` elements, whole along the last dimensions
    (small variables are one chunk: the least overhead per byte)."""
    out, room = [], target
    for n in reversed(shape):
        c = max(1, min(n, room))
        out.append(c)
        room = max(1, room // c)
    return tuple(reversed(out))
