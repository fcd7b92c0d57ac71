"""Pictures of sweeps: the operating window of a map.

Thin: every function takes a Dataset from :func:`agglomtool.maps.sweep` (or a netCDF file
of one) and draws it with matplotlib; nothing is computed here but unit conversions for
the axes (K to degC, m to um).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["choose_axes", "operating_window"]

#: Preferred axes: (y first choices, x first choices).
_Y_PREF = ("T", "P", "U_Umf", "U")
_X_PREF = ("h0", "d_i", "u0", "U_Umf", "beta_deg")

_DISPLAY = {  # name -> (scale, offset, label)
    "T": (1.0, -273.15, "temperature [degC]"),
    "h0": (1e6, 0.0, "coating thickness h0 [um]"),
    "h0_j": (1e6, 0.0, "coating thickness of j [um]"),
    "d_i": (1e6, 0.0, "diameter of i [um]"),
    "d_j": (1e6, 0.0, "diameter of j [um]"),
    "ha_i": (1e6, 0.0, "asperity height of i [um]"),
    "P": (1e-5, 0.0, "pressure [bar]"),
}


def _display(ds, name):
    attrs = ds[name].attrs
    default = (1.0, 0.0, f"{attrs.get('long_name', name)} [{attrs.get('units', '')}]")
    scale, offset, label = _DISPLAY.get(name, default)
    return np.asarray(ds[name].values, dtype=float) * scale + offset, label


def _logish(values) -> bool:
    v = np.asarray(values, dtype=float)
    return bool(v.size > 2 and np.all(v > 0) and v.max() / v.min() > 20.0)


def choose_axes(ds: xr.Dataset, var: str = "propensity"):
    """``(y, x, facet)`` dims for a picture of ``var``; ``x`` or ``facet`` may be None.

    ``y`` and ``x`` are numeric dims of more than one value, preferring temperature against
    coating thickness; ``facet`` is a further dim of at most 6 values (panels).
    """
    dims = [d for d in ds[var].dims if ds.sizes[d] > 1]
    numeric = [d for d in dims if np.issubdtype(ds[d].dtype, np.number)]
    if not numeric:
        raise ValueError(f"{var} has no numeric dimension with more than one value to plot")
    y = next((d for d in _Y_PREF if d in numeric), numeric[0])
    rest = [d for d in numeric if d != y]
    x = next((d for d in _X_PREF if d in rest), rest[0] if rest else None)
    others = [d for d in dims if d not in (x, y)]
    facet = next((d for d in others if ds.sizes[d] <= 6), None)
    return y, x, facet


def operating_window(ds, var: str = "propensity", *, path=None, title: str | None = None):
    """Operating-window picture: ``var`` coloured over two dims, ``u0*`` contours.

    Parameters
    ----------
    ds : xarray.Dataset or path
        A sweep result, or a netCDF file of one.
    var : str
        The variable to colour (default the agglomeration propensity, 0 to 1).
    path : path, optional
        Write the figure there (PNG, 150 dpi).
    title : str, optional
        Figure title (default: the liquid and solids of the map).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    if not isinstance(ds, xr.Dataset):
        ds = xr.open_dataset(ds)
    if var not in ds:
        raise ValueError(f"{var!r} is not a variable of the map; variables: {list(ds.data_vars)}")
    y, x, facet = choose_axes(ds, var)
    fixed = {d: ds.sizes[d] // 2 for d in ds[var].dims if d not in (x, y, facet)}
    sub = ds.isel(fixed)
    panels = list(range(ds.sizes[facet])) if facet else [None]
    ncol = min(3, len(panels))
    nrow = -(-len(panels) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol + 0.8, 3.9 * nrow), squeeze=False,
                             sharex=True, sharey=True, layout="constrained")
    units = ds[var].attrs.get("units", "")
    is_prob = var == "propensity"
    mappable = None
    for k, ax in zip(panels, axes.ravel(), strict=False):
        part = sub.isel({facet: k}) if facet else sub
        yv, ylab = _display(part, y)
        if x is None:
            ax.plot(yv, part[var].values)
            ax.set_xlabel(ylab)
            ax.set_ylabel(f"{var} [{units}]")
            continue
        xv, xlab = _display(part, x)
        z = part[var].transpose(y, x).values.astype(float)
        norm = None
        if not is_prob and var in ("u_star", "margin", "Ca_star", "St"):
            finite = z[np.isfinite(z) & (z > 0)]
            if finite.size:
                norm = LogNorm(finite.min(), finite.max())
        mappable = ax.pcolormesh(xv, yv, z, shading="nearest", cmap="magma_r" if is_prob
                                 else "viridis", vmin=0.0 if is_prob else None,
                                 vmax=1.0 if is_prob else None, norm=norm)
        if "u_star" in part and x in part["u_star"].dims and y in part["u_star"].dims:
            us = part["u_star"].transpose(y, x).values.astype(float)
            good = us[np.isfinite(us) & (us > 0)]
            if good.size and good.max() / good.min() > 1.5:
                levels = np.unique(np.round(np.geomspace(good.min(), good.max(), 7), 3))
                levels = levels[levels > 0]
                if levels.size > 1:
                    cs = ax.contour(xv, yv, np.where(np.isfinite(us), us, np.nan), levels=levels,
                                    colors="white", linewidths=0.8)
                    ax.clabel(cs, fmt=lambda v: f"u0*={v:.3g} m/s", fontsize=7)
        for name, axis, setter in ((x, ax.xaxis, ax.set_xscale), (y, ax.yaxis, ax.set_yscale)):
            if _logish(part[name].values):
                setter("log")
                axis.set_major_formatter(ScalarFormatter())
                axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(xlab)
        ax.set_ylabel(ylab)
        if facet:
            fv = part[facet].values
            val = fv.item() if fv.ndim == 0 else fv
            label = ds[facet].attrs.get("long_name", facet)
            ax.set_title(f"{label} = {val}" if isinstance(val, str) else f"{facet} = {val:g}",
                         fontsize=9)
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    if mappable is not None:
        fig.colorbar(mappable, ax=axes, label=f"{ds[var].attrs.get('long_name', var)} [{units}]")
    if title is None:
        import json

        scene = json.loads(ds.attrs.get("scene", "{}"))
        title = (f"{scene.get('liquid', '')} on {scene.get('solid_i', '')}"
                 + (f" / {scene['solid_j']}" if scene.get("solid_j") else ""))
        if fixed:
            title += " (" + ", ".join(f"{d} = {ds[d].values[i]}" for d, i in fixed.items()) + ")"
    fig.suptitle(title, fontsize=10)
    if path is not None:
        fig.savefig(path, dpi=150)
    return fig
