"""Pictures of sweeps: the operating window of a map.

Thin: every function takes a Dataset from :func:`agglomtool.sweep` (or a netCDF file of one)
and draws it with xarray's faceting and matplotlib. Nothing is computed here but unit
conversions for display (K to degC, m to um, Pa to bar).

No dimension is ever hidden: the two axes, the facet columns and rows, and fixed selections
are chosen by the caller or, where left open, by :func:`plan_layout`, which refuses (with the
dims and sizes it could not place) rather than silently pick one slice of a dimension.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

__all__ = ["Layout", "operating_window", "plan_layout", "open_map"]

#: Preferred axes: (y first choices, x first choices).
_Y_PREF = ("T", "U_Umf", "U", "P", "d_i", "d_j")
_X_PREF = ("h0", "h0_j", "d_i", "u0", "U_Umf", "beta_deg", "d_j")
#: Most panels a picture may have before the caller must choose with ``sel``.
MAX_PANELS = 24
#: Most values a dimension may have to be faceted automatically.
MAX_FACET = 8

#: Display conversions: name -> (scale, offset, units shown).
_DISPLAY = {
    "T": (1.0, -273.15, "degC"),
    "P": (1e-5, 0.0, "bar"),
    **{k: (1e6, 0.0, "um") for k in ("d_i", "d_j", "h0", "h0_j", "ha_i", "ha_j")},
}
#: Categorical output variables (besides those with ``flag_values``).
_BOOLEAN_LABELS = {"agglomerated": {0: "rebounds", 1: "sticks"}}


@dataclass
class Layout:
    """Which dim goes where in a picture: ``x``, ``y`` (may be None: a line plot), ``col``,
    ``row`` (may be None) and the fixed selections ``sel`` {dim: value}."""

    var: str
    x: str
    y: str | None
    col: str | None = None
    row: str | None = None
    sel: dict = field(default_factory=dict)
    chosen: list = field(default_factory=list)  # what the tool chose, for describe()

    def describe(self) -> str:
        """One line saying where every dimension went."""
        parts = [f"x = {self.x}"] + ([f"y = {self.y}"] if self.y else [])
        parts += [f"columns = {self.col}"] if self.col else []
        parts += [f"rows = {self.row}"] if self.row else []
        parts += [f"{k} = {_fmt_value(k, v)}" for k, v in self.sel.items()]
        text = f"{self.var}: " + ", ".join(parts)
        if self.chosen:
            text += " (chosen by the tool: " + ", ".join(self.chosen) + ")"
        return text


def open_map(ds) -> xr.Dataset:
    """``ds`` itself, or the map in the netCDF file ``ds`` (a clear error if unreadable)."""
    if isinstance(ds, xr.Dataset):
        return ds
    from pathlib import Path

    path = Path(ds)
    if not path.is_file():
        raise ValueError(f"map file {str(path)!r} does not exist")
    try:
        return xr.open_dataset(path)
    except (OSError, ValueError) as exc:
        raise ValueError(f"map file {str(path)!r} is not a readable netCDF map: {exc}") from None


def _fmt_value(name: str, value, *, converted: bool = False) -> str:
    """A coordinate value in display units: ``850 degC``, ``550 um``, ``ilmenite``
    (``converted``: ``value`` is in display units already)."""
    if isinstance(value, str | np.str_):
        return str(value)
    v = float(value)
    scale, offset, unit = _DISPLAY.get(name, (1.0, 0.0, ""))
    shown = v if converted else v * scale + offset
    return f"{shown:.4g} {unit}".strip()


def _sel(ds: xr.Dataset, var: str, sel: dict) -> xr.Dataset:
    """Select fixed values; numbers match the nearest grid value within 1e-6 relative."""
    out = {}
    for name, value in sel.items():
        if name not in ds[var].dims:
            raise ValueError(f"sel: {name!r} is not a dimension of {var}; dimensions: "
                             f"{list(ds[var].dims)}")
        coord = ds[name].values
        if coord.dtype.kind in "US":
            if str(value) not in coord.astype(str):
                raise ValueError(f"sel: {name} = {value!r} is not in the map; values: "
                                 f"{list(coord.astype(str))}")
            out[name] = str(value)
            continue
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"sel: {name} = {value!r} is not a number") from None
        k = int(np.argmin(np.abs(coord - v)))
        if not np.isclose(coord[k], v, rtol=1e-6, atol=0.0):
            shown = ", ".join(f"{c:g}" for c in coord[:12]) + (" ..." if coord.size > 12 else "")
            raise ValueError(f"sel: {name} = {v:g} is not a grid value (in the map's units, "
                             f"{ds[name].attrs.get('units', '')}); values: {shown}")
        out[name] = coord[k]
    return ds.sel(out)


def plan_layout(ds: xr.Dataset, var: str = "propensity", *, x=None, y=None, col=None,
                row=None, sel=None) -> Layout:
    """Place every dimension of ``var`` (of more than one value) in a picture.

    Dimensions named by the caller go where asked. The rest, in order: ``y`` and ``x`` from
    the numeric dimensions (temperature against coating thickness first), then columns and
    rows for dimensions of at most :data:`MAX_FACET` values. A dimension that cannot be placed
    raises ``ValueError`` naming it and its size (choose it with ``sel``): a picture never
    shows one slice of a dimension without saying so.
    """
    if var not in ds:
        raise ValueError(f"{var!r} is not a variable of the map; variables: "
                         f"{sorted(ds.data_vars)}")
    sel = dict(sel or {})
    for name, value in (("x", x), ("y", y), ("col", col), ("row", row)):
        if value is not None and value not in ds[var].dims:
            raise ValueError(f"{name} = {value!r} is not a dimension of {var}; dimensions: "
                             f"{list(ds[var].dims)}")
        if value is not None and value in sel:
            raise ValueError(f"{value!r} is both {name} and a fixed selection (sel)")
    given = [v for v in (x, y, col, row) if v is not None]
    if len(set(given)) != len(given):
        raise ValueError(f"a dimension is used twice among x, y, col, row: {given}")
    dims = [d for d in ds[var].dims if ds.sizes[d] > 1 and d not in sel]
    free = [d for d in dims if d not in given]
    numeric = [d for d in free if np.issubdtype(ds[d].dtype, np.number)]
    chosen = []
    if x is None and y is None and not numeric and free:
        x = free.pop(0)  # names only: a categorical x axis (a line or bar per panel)
        chosen.append(f"x = {x}")
    if y is None and x is None and numeric:
        y = next((d for d in _Y_PREF if d in numeric), numeric[0])
        numeric.remove(y)
        free.remove(y)
        chosen.append(f"y = {y}")
    if x is None:
        pick = next((d for d in _X_PREF if d in numeric), numeric[0] if numeric else None)
        if pick is None and y is not None:
            x, y = y, None  # one numeric dim: a line plot over it
        elif pick is None:
            raise ValueError(f"{var} has no dimension with more than one value to plot")
        else:
            x = pick
            free.remove(x)
            chosen.append(f"x = {x}")
    for slot in ("col", "row"):
        if (col if slot == "col" else row) is not None:
            continue
        small = [d for d in free if ds.sizes[d] <= MAX_FACET]
        if small:
            pick = min(small, key=lambda d: ds.sizes[d]) if slot == "row" else small[0]
            free.remove(pick)
            chosen.append(f"{'columns' if slot == 'col' else 'rows'} = {pick}")
            if slot == "col":
                col = pick
            else:
                row = pick
    if free:
        left = ", ".join(f"{d} ({ds.sizes[d]} values)" for d in free)
        raise ValueError(
            f"{var} has more dimensions than a picture can show: {left} would be hidden. "
            f"Fix each with sel (e.g. sel={{'{free[0]}': {_example_value(ds, free[0])}}}; on "
            f"the command line --sel {free[0]}={_example_value(ds, free[0])}) or place it "
            "with x, y, col or row")
    panels = (ds.sizes[col] if col else 1) * (ds.sizes[row] if row else 1)
    if panels > MAX_PANELS:
        raise ValueError(f"{panels} panels ({col}: {ds.sizes.get(col, 1)}, {row}: "
                         f"{ds.sizes.get(row, 1)}) exceed {MAX_PANELS}; fix one with sel")
    return Layout(var=var, x=x, y=y, col=col, row=row, sel=sel, chosen=chosen)


def _example_value(ds, name) -> str:
    v = ds[name].values[ds.sizes[name] // 2]
    return repr(str(v)) if isinstance(v, str | np.str_) else f"{float(v):g}"


def _for_display(da: xr.DataArray) -> xr.DataArray:
    """``da`` with its coordinates in display units (degC, um, bar) and labelled."""
    new = {}
    for name in da.coords:
        c = da[name]
        if name not in _DISPLAY or not np.issubdtype(c.dtype, np.number):
            continue
        scale, offset, unit = _DISPLAY[name]
        label = c.attrs.get("long_name", name)
        new[name] = (c.dims, c.values * scale + offset, {"long_name": label, "units": unit})
    return da.assign_coords(new)


def _logish(values) -> bool:
    v = np.asarray(values, dtype=float)
    return bool(v.size > 2 and np.all(v > 0) and v.max() / v.min() > 20.0)


def _categories(da: xr.DataArray) -> dict | None:
    """{code: label} of a categorical variable (flags, booleans), else None."""
    if da.name in _BOOLEAN_LABELS:
        return _BOOLEAN_LABELS[da.name]
    if "flag_values" in da.attrs:
        vals = np.atleast_1d(da.attrs["flag_values"]).tolist()
        names = str(da.attrs.get("flag_meanings", "")).split()
        if len(names) != len(vals):
            names = [str(v) for v in vals]
        return {int(v): n.replace("_", " ") for v, n in zip(vals, names, strict=True)}
    return None


def _nice_levels(lo: float, hi: float) -> np.ndarray:
    """1-2-5 levels within [lo, hi] (at most 8), for u0* contours [m/s]."""
    exps = np.arange(np.floor(np.log10(lo)) - 1, np.ceil(np.log10(hi)) + 1)
    cand = np.sort(np.outer(10.0**exps, [1.0, 2.0, 5.0]).ravel())
    lev = cand[(cand >= lo) & (cand <= hi)]
    while lev.size > 8:
        lev = lev[::2]
    return lev


def _u_star_overlay(ax, us: xr.DataArray, x: str, y: str, ceiling_label: str) -> list:
    """u0* contours (readable on any colour) and hatching where no finite u0* exists."""
    import matplotlib.patheffects as pe

    us = us.transpose(y, x)
    xv, yv, z = us[x].values, us[y].values, np.asarray(us.values, dtype=float)
    handles = []
    finite = z[np.isfinite(z) & (z > 0)]
    if finite.size and finite.max() > finite.min() * 1.05 and z.shape[0] > 1 and z.shape[1] > 1:
        levels = _nice_levels(finite.min(), finite.max())
        if levels.size:
            zz = np.where(np.isfinite(z) & (z > 0), z, np.nan)
            cs = ax.contour(xv, yv, zz, levels=levels, colors="black", linewidths=0.9)
            labels = ax.clabel(cs, fmt=lambda v: f"{v:g} m/s", fontsize=7, inline_spacing=2)
            halo = [pe.withStroke(linewidth=2.5, foreground="white")]
            for t in labels:
                t.set_path_effects(halo)
            for c in getattr(cs, "collections", [cs]):
                c.set_path_effects([pe.Stroke(linewidth=2.2, foreground="white"), pe.Normal()])
    for mask, hatch, label in ((np.isinf(z), "//", ceiling_label),
                               (z == 0.0, "..", "no bridge: coating thinner than asperities")):
        if mask.any():
            cf = ax.contourf(xv, yv, mask.astype(float), levels=[0.5, 1.5], colors="none",
                             hatches=[hatch])
            cf.set_edgecolor("0.55")  # hatch lines visible on dark and pale colours alike
            cf.set_linewidth(0.0)
            handles.append((hatch, label))
    return handles


def operating_window(ds, var: str = "propensity", *, x=None, y=None, col=None, row=None,
                     sel=None, path=None, title: str | None = None, contours: bool = True):
    """Operating-window picture: ``var`` coloured over two dims, faceted, ``u0*`` contours.

    Parameters
    ----------
    ds : xarray.Dataset or path
        A sweep result, or a netCDF file of one.
    var : str
        The variable to colour (default the agglomeration propensity, 0 to 1). Categorical
        variables (``stage``, ``regime``, ``u_star_flag``, ``agglomerated``) get discrete
        colours and a legend.
    x, y, col, row : str, optional
        Dimensions for the axes and the facet columns and rows; those left open are chosen
        by :func:`plan_layout` (and said in the figure's ``layout`` attribute).
    sel : dict, optional
        Fixed values ``{dim: value}`` (numbers in the map's units, SI; names as strings).
    path : path, optional
        Write the figure there (PNG, 150 dpi).
    title : str, optional
        Figure title (default: the variable, the liquid and solids, and the fixed values).
    contours : bool
        Draw ``u0*`` contours (m/s) and hatch where ``u0*`` is above the ceiling or zero.

    Returns
    -------
    matplotlib.figure.Figure
        With the attribute ``layout`` (a :class:`Layout`: where every dimension went).
    """
    try:
        import matplotlib
    except ImportError:
        raise ImportError("pictures need matplotlib: pip install 'agglomtool[plot]'") from None
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm
    from matplotlib.patches import Patch

    ds = open_map(ds)
    layout = plan_layout(ds, var, x=x, y=y, col=col, row=row, sel=sel)
    sub = _sel(ds, var, layout.sel)
    x, y, col, row = layout.x, layout.y, layout.col, layout.row
    da = sub[var]
    for d in da.dims:  # single-valued dims: shown in the title, not as an axis
        if d not in (x, y, col, row):
            da = da.isel({d: 0})
    disp = _for_display(da.load())
    cats = _categories(ds[var])
    kw = {}
    if cats is not None:
        codes = sorted(cats)
        palette = matplotlib.colormaps["tab10"]
        cmap = ListedColormap([palette(i % 10) for i in range(len(codes))])
        bounds = np.concatenate([[codes[0] - 0.5], np.asarray(codes[:-1]) + 0.5,
                                 [codes[-1] + 0.5]])
        kw = dict(cmap=cmap, norm=BoundaryNorm(bounds, cmap.N), add_colorbar=False)
        disp = disp.astype(float)
    elif var == "propensity":
        kw = dict(cmap="magma_r", vmin=0.0, vmax=1.0)
    elif var in ("u_star", "margin", "Ca_star", "St"):
        z = np.asarray(disp.values, dtype=float)
        good = z[np.isfinite(z) & (z > 0)]
        if good.size and good.max() > good.min():
            kw = dict(norm=LogNorm(good.min(), good.max()))
        disp = disp.where(np.isfinite(disp) & (disp > 0))
    facet = dict(col=col, row=row) if (col or row) else {}
    if y is None:
        plot = disp.plot.line(x=x, **facet) if facet else disp.plot.line(x=x)
    else:
        scales = {f"{a}scale": "log" for a, n in (("x", x), ("y", y))
                  if np.issubdtype(ds[n].dtype, np.number) and _logish(ds[n].values)}
        plot = disp.plot.pcolormesh(x=x, y=y, **scales, **facet, **kw)
    if facet:
        fig = plot.fig
        for text in list(plot.row_labels) + list(plot.col_labels):
            if text is not None:  # xarray's margin titles: replaced by one title per panel
                text.set_visible(False)
        panels = [(ax, nd) for ax, nd in zip(plot.axs.flat, plot.name_dicts.flat, strict=True)
                  if nd is not None]
    else:
        fig = plt.gcf()
        panels = [(plt.gca(), {})]
    from ._fields import U_CEILING

    scene = json.loads(ds.attrs.get("scene", "{}"))
    ceiling_label = ("sticks at every speed up to the u0* ceiling "
                     f"({scene.get('u_ceiling', U_CEILING):g} m/s)")
    hatches = {}
    for ax, nd in panels:
        nd = nd or {}
        if y is not None and contours and "u_star" in sub:
            us = sub["u_star"].broadcast_like(sub[var])
            for d in us.dims:
                if d not in (x, y, col, row):
                    us = us.isel({d: 0})
            us = _for_display(us).sel(nd)
            for hatch, label in _u_star_overlay(ax, us, x, y, ceiling_label):
                hatches[hatch] = label
        if y is None and np.issubdtype(ds[x].dtype, np.number) and _logish(ds[x].values):
            ax.set_xscale("log")
        if nd:
            ax.set_title(", ".join(f"{k} = {_fmt_value(k, v, converted=True)}"
                                   for k, v in nd.items()), fontsize=9)
            ax.title.set_visible(True)
    legend = []
    if cats is not None:
        present = set(np.unique(np.asarray(ds[var].values, dtype=int)).tolist())
        legend += [Patch(facecolor=cmap(i), label=cats[c]) for i, c in enumerate(codes)
                   if c in present]
    legend += [Patch(facecolor="white", edgecolor="black", hatch=h, label=lab)
               for h, lab in hatches.items()]
    if contours and y is not None and "u_star" in sub:
        from matplotlib.lines import Line2D

        legend.append(Line2D([], [], color="black", lw=0.9, label="u0* contours [m/s]"))
    if legend:  # below the panels; saved with a tight bounding box
        fig.legend(handles=legend, loc="upper center", ncol=min(3, len(legend)), fontsize=8,
                   frameon=False, bbox_to_anchor=(0.5, 0.0))
    assumed = ds.attrs.get("assumed_inputs", "none")
    if assumed and assumed != "none":  # the answer depends on these: say so on the picture
        import textwrap

        note = textwrap.fill("Assumed values (materials database): " + assumed, 140)
        fig.text(0.5, -0.03 - 0.05 * (-(-len(legend) // 3)), note, ha="center", va="top",
                 fontsize=7, color="0.3")
    if title is None:
        title = _default_title(ds, var, sub, da)
    fig.suptitle(title, fontsize=10, y=1.0 + 0.03 * title.count("\n"), va="bottom")
    fig.layout = layout
    if path is not None:
        fig.savefig(path, dpi=150, bbox_inches="tight")
    return fig


def _default_title(ds, var, sub, da) -> str:
    scene = json.loads(ds.attrs.get("scene", "{}"))
    swept = set(ds.dims)

    def name(field):
        return None if field in swept else scene.get(field)

    what = ds[var].attrs.get("long_name", var)
    liquid, si, sj = name("liquid"), name("solid_i"), name("solid_j")
    parts = [what]
    if liquid:
        temp = name("T")
        parts.append(f"{liquid}" + (f" at {_fmt_value('T', temp)}" if temp else "")
                     + (f" on {si}" if si else "") + (f" / {sj}" if sj else ""))
    fixed = [f"{d} = {_fmt_value(d, sub[d].values.item())}" for d in da.coords
             if d in ds.dims and sub[d].ndim == 0]
    title = ": ".join(parts[:1]) + (f" ({parts[1]})" if len(parts) > 1 else "")
    if fixed:
        title += "\n" + ", ".join(fixed)
    return title
