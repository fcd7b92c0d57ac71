"""The coalescence-efficiency matrix of a bed, for population-balance codes (CSV, netCDF)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import xarray as xr

from ..maps.export import read_names, write_map

__all__ = ["export_efficiency", "read_efficiency", "EXPORTED"]

#: Pair variables written (besides the class table): name -> (units, long_name); units as
#: CF and UDUNITS write them ("1": dimensionless).
EXPORTED = {
    "efficiency": ("1", "coalescence efficiency (direction-averaged sticking probability)"),
    "rate_weight": ("1", "collision-rate weight of the ordered pair of classes"),
    "u_star_min": ("m/s", "critical impact speed u0*, minimum over directions"),
}
#: Class columns: name -> (units, long_name); a name has no units (None).
CLASS_COLUMNS = {
    "component": (None, "component (solid name) of the class"),
    "d": ("m", "solid diameter of the class"),
    "d_lo": ("m", "lower edge of the class"),
    "d_hi": ("m", "upper edge of the class"),
}


def _check(ds) -> None:
    if not isinstance(ds, xr.Dataset) or "efficiency" not in ds or \
            ds["efficiency"].dims != ("cls_i", "cls_j"):
        raise ValueError("ds must be the Dataset of agglomtool.bed.bed_propensity (an "
                         "'efficiency' over (cls_i, cls_j)); for a bed_sweep(matrix=True) "
                         "select one point (ds.isel(T=0, ...))")


def _matrix_dataset(ds: xr.Dataset) -> xr.Dataset:
    out = xr.Dataset({k: ds[k] for k in EXPORTED if k in ds})
    keep = [c for c in out.coords if str(c).endswith(("cls_i", "cls_j"))]
    out = out.reset_coords(drop=True).assign_coords({c: ds[c] for c in keep})
    out.attrs.update({k: v for k, v in ds.attrs.items() if isinstance(v, str | int | float)})
    return out


def export_efficiency(ds: xr.Dataset, path, *, history: str | None = None) -> Path:
    """Write the coalescence-efficiency matrix of ``ds`` to ``path`` (``.csv`` or ``.nc``).

    Parameters
    ----------
    ds : xarray.Dataset
        The result of :func:`agglomtool.bed.bed_propensity`, or one point of a
        ``bed_sweep(..., matrix=True)`` (which holds the efficiency only).
    path : str or Path
        ``*.csv``: one row per ordered pair of classes ``(i, j)`` with both classes'
        component, diameter and edges [m], ``efficiency`` [-], ``rate_weight`` [-] and
        ``u_star_min`` [m/s]; ``#`` comment lines first give the units and the bed's
        propensity. ``*.nc``: the matrices over ``(cls_i, cls_j)`` with the class
        coordinates, units and long names as attributes, and the bed's global attributes
        (a CF-1.8 file, as :func:`agglomtool.write_map` writes).
    history : str, optional
        ``*.nc``: the command recorded in the file's ``history`` line (the command line
        when the CLI writes); default ``agglomtool.bed.export_efficiency(ds, '<name>')``.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    _check(ds)
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".nc":
        return write_map(_matrix_dataset(ds), path, history=history if history is not None
                         else f"agglomtool.bed.export_efficiency(ds, {path.name!r})")
    if suffix != ".csv":
        raise ValueError(f"path = {str(path)!r}: the suffix must be .csv or .nc")
    ni, nj = ds.sizes["cls_i"], ds.sizes["cls_j"]
    ii, jj = np.meshgrid(np.arange(ni), np.arange(nj), indexing="ij")
    cols = ["i", "j"]
    units = ["1", "1"]
    values = [ii.ravel(), jj.ravel()]
    for side, idx in (("i", ii.ravel()), ("j", jj.ravel())):
        for name, (unit, _) in CLASS_COLUMNS.items():
            cols.append(f"{name}_{side}")
            units.append(unit or "")  # a name: no units
            values.append(np.asarray(ds[f"{name}_cls_{side}"].values)[idx])
    for name, (unit, _) in EXPORTED.items():
        if name not in ds:  # a bed_sweep's matrix has the efficiency only
            continue
        cols.append(name)
        units.append(unit)
        values.append(np.asarray(ds[name].values).ravel())
    with open(path, "w", newline="") as fh:
        fh.write("# agglomtool coalescence-efficiency matrix (one row per ordered pair of "
                 "size classes)\n")
        if "propensity" in ds:
            fh.write(f"# bed propensity: {float(ds['propensity']):.17g}\n")
        fh.write("# units: " + ",".join(units) + "\n")
        w = csv.writer(fh)
        w.writerow(cols)
        for row in zip(*values, strict=True):
            w.writerow([x if isinstance(x, str) else repr(float(x)) if
                        isinstance(x, float | np.floating) else int(x) for x in row])
    return path


def read_efficiency(path) -> xr.Dataset:
    """Read a matrix written by :func:`export_efficiency` back into a Dataset over
    ``(cls_i, cls_j)`` (the form :func:`export_efficiency` writes to netCDF)."""
    path = Path(path)
    if path.suffix.lower() == ".nc":
        with xr.open_dataset(path) as f:
            return read_names(f.load())
    with open(path, newline="") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    rows = list(csv.reader(lines))
    header, body = rows[0], rows[1:]
    col = {name: [r[k] for r in body] for k, name in enumerate(header)}
    i = np.array(col["i"], dtype=int)
    j = np.array(col["j"], dtype=int)
    ni, nj = i.max() + 1, j.max() + 1
    coords = {}
    for side, idx, n in (("i", i, ni), ("j", j, nj)):
        first = np.array([np.flatnonzero(idx == k)[0] for k in range(n)])
        dim = f"cls_{side}"
        coords[dim] = xr.DataArray(np.arange(n, dtype=np.int32), dims=[dim], attrs={
            "units": "1", "long_name": "size class (all components)"})
        for name, (unit, long_name) in CLASS_COLUMNS.items():
            raw = np.array(col[f"{name}_{side}"])[first]
            vals = raw if name == "component" else raw.astype(float)
            attrs = {"long_name": long_name} if unit is None else {"units": unit,
                                                                    "long_name": long_name}
            coords[f"{name}_{dim}"] = xr.DataArray(vals, dims=[dim], attrs=attrs)
    data = {}
    for name, (unit, long_name) in EXPORTED.items():
        if name not in col:
            continue
        m = np.full((ni, nj), np.nan)
        m[i, j] = np.array(col[name], dtype=float)
        data[name] = xr.DataArray(m, dims=["cls_i", "cls_j"],
                                  attrs={"units": unit, "long_name": long_name})
    return xr.Dataset(data, coords=coords)
