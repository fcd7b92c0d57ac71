"""Pictures of sweeps: the operating window of a map.

Thin: every function takes a Dataset from :func:`agglomtool.sweep` or a bed map (or a netCDF
file of one) and draws it with matplotlib, a panel per facet. Nothing is computed here but
unit conversions for display (K to degC, m to um, Pa to bar).

A picture draws only what the data hold: cells span the grid values, the colour bar the
values shown (none for a field of one value, which a note states), the legend what is drawn;
the title names the materials and the notes every fixed scene value.

No dimension is ever hidden: the two axes, the facet columns and rows, and fixed selections
are chosen by the caller or, where left open, by :func:`plan_layout`, which refuses (with the
dims and sizes it could not place) rather than silently pick one slice of a dimension.
"""

from __future__ import annotations

import json
import textwrap
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
import xarray as xr

__all__ = ["Layout", "operating_window", "plan_layout", "open_map", "speed_model_windows"]

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
#: Hatch of the cells where the impact-speed model has no answer (``speed_flag`` != 0).
_NO_SPEED_HATCH = "\\\\"
#: Hatch of a robust map's cells whose nominal point has an impact speed but some of its
#: draws have none (``undecided`` = 2 there): no robust answer.
_NO_ROBUST_HATCH = "++"
_NO_ROBUST_LABEL = ("no robust answer (the impact-speed model has no answer at some "
                    "draws)")


def _speed_flag_of(ds, var: str) -> bool:
    """Whether ``var`` is made of the impact speed, so that its points with a nonzero
    ``speed_flag`` have no value (a map's outputs that name the flag as ancillary, and a
    robust map's summaries of the propensity)."""
    return "speed_flag" in ds and var != "speed_flag" and (
        ds[var].attrs.get("ancillary_variables") == "speed_flag"
        or var.startswith("propensity") or var in ("p_unsafe", "undecided"))


def _no_speed_label(ds, codes) -> str:
    """The legend's words for the points with no impact speed, with their reasons."""
    names = dict(zip(np.atleast_1d(ds["speed_flag"].attrs.get("flag_values", [])).tolist(),
                     str(ds["speed_flag"].attrs.get("flag_meanings", "")).split(),
                     strict=False))
    return "no impact speed (speed model: " + ", ".join(
        names.get(int(c), str(int(c))).replace("_", " ") for c in codes) + ")"


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
    import os
    from pathlib import Path

    if not isinstance(ds, str | os.PathLike):
        raise ValueError(f"ds = {ds!r} is not allowed: an xarray.Dataset (a map) or the path "
                         "of a netCDF map file")
    path = Path(ds)
    if not path.is_file():
        raise ValueError(f"map file {str(path)!r} does not exist")
    from .maps.export import read_names

    try:
        return read_names(xr.open_dataset(path))
    except (OSError, ValueError) as exc:
        raise ValueError(f"map file {str(path)!r} is not a readable netCDF map: {exc}") from None


def _fmt_value(name: str, value, *, converted: bool = False) -> str:
    """A coordinate value in display units: ``850 degC``, ``550 um``, ``ilmenite``
    (``converted``: ``value`` is in display units already)."""
    if isinstance(value, str | np.str_):
        return str(value)
    v = float(value)
    if name in _DISPLAY:
        scale, offset, unit = _DISPLAY[name]
    else:
        scale, offset, unit = 1.0, 0.0, _unit_text(_field_unit(name))
    shown = v if converted else v * scale + offset
    return f"{shown:.4g}" + ("" if unit == "-" else f" {unit}")


#: Relative distance within which a number selects a grid value: the values are shown
#: (errors, hints, titles' footnotes) to 6 significant digits, which round by up to 5e-6.
_SEL_RTOL = 1e-5


def _resolve_sel(ds: xr.Dataset, var: str, sel: dict) -> dict:
    """``sel`` as the grid values it selects: a number the nearest grid value within
    :data:`_SEL_RTOL` (the only one there), a name the value it spells (materials in any
    spelling the database accepts). A ``ValueError`` names a value that selects none."""
    from ._validate import material_key

    out = {}
    for name, value in sel.items():
        if name not in ds[var].dims:
            raise ValueError(f"sel: {name!r} is not a dimension of {var}; dimensions: "
                             f"{list(ds[var].dims)}")
        coord = ds[name].values
        if coord.dtype.kind in "US":
            names = [str(c) for c in coord]
            keys = [material_key(c) for c in names]
            if str(value) in names:
                out[name] = str(value)
            elif keys.count(material_key(value)) == 1:
                out[name] = names[keys.index(material_key(value))]
            else:
                raise ValueError(f"sel: {name} = {value!r} is not in the map; values: "
                                 f"{', '.join(names)}")
            continue
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"sel: {name} = {value!r} is not a number") from None
        near = np.flatnonzero(np.isclose(coord, v, rtol=_SEL_RTOL, atol=0.0))
        k = int(np.argmin(np.abs(coord - v)))
        if near.size > 1 and np.isclose(coord[k], v, rtol=1e-12, atol=0.0):
            near = np.array([k])  # grid values closer than the digits shown: typed in full
        if near.size != 1:
            shown = ", ".join(f"{c:g}" for c in coord[:12]) + (" ..." if coord.size > 12 else "")
            full = ", ".join(repr(float(c)) for c in coord[near])
            what = ("is not a grid value" if near.size == 0 else
                    f"is near {near.size} grid values ({full}): type one in full")
            raise ValueError(f"sel: {name} = {v:g} {what} (in the map's units, "
                             f"{ds[name].attrs.get('units', '')}); values: {shown}")
        out[name] = coord[near[0]]
    return out


def _sel(ds: xr.Dataset, var: str, sel: dict) -> xr.Dataset:
    """Select fixed values (:func:`_resolve_sel`)."""
    return ds.sel(_resolve_sel(ds, var, sel))


def plan_layout(ds: xr.Dataset, var: str = "propensity", *, x=None, y=None, col=None,
                row=None, sel=None) -> Layout:
    """Place every dimension of ``var`` (of more than one value) in a picture.

    Dimensions named by the caller go where asked. The rest, in order: ``y`` and ``x`` from
    the numeric dimensions (temperature against coating thickness first; a dimension of
    more than :data:`MAX_FACET` values, which no facet takes, before one that a facet
    takes), then columns and rows for dimensions of at most :data:`MAX_FACET` values. A
    dimension that cannot be placed raises ``ValueError`` naming it and its size (choose it
    with ``sel``): a picture never shows one slice of a dimension without saying so.
    """
    if not isinstance(var, str) or var not in ds:
        raise ValueError(f"var = {var!r} is not a variable of the map; variables: "
                         f"{sorted(map(str, ds.data_vars))}")
    if sel is not None and not isinstance(sel, dict):
        raise ValueError(f"sel = {sel!r} is not allowed: a dict {{dimension: value}}")
    # every selection names a dimension and one of its values, kept as that value
    sel = _resolve_sel(ds, var, dict(sel or {}))
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
    # a numeric dimension too long for a facet can only be an axis: such dimensions take
    # the axes left open before the preferred ones do (two of them: both axes)
    long = [d for d in numeric if ds.sizes[d] > MAX_FACET]
    open_axes = (x is None) + (y is None)
    if y is None and x is None and numeric:
        y_from = long if len(long) >= 2 else numeric
        y = next((d for d in _Y_PREF if d in y_from), y_from[0])
        numeric.remove(y)
        free.remove(y)
        chosen.append(f"y = {y}")
    if x is None:
        x_from = [d for d in long if d != y] if 0 < len(long) <= open_axes else numeric
        x_from = [d for d in x_from if d in numeric] or numeric
        pick = next((d for d in _X_PREF if d in x_from), x_from[0] if x_from else None)
        if pick is None and y is not None:
            if f"y = {y}" not in chosen:  # the caller's y, not the tool's: not moved unsaid
                raise ValueError(f"y = {y!r} leaves no dimension for x: {var} varies along "
                                 f"{y} alone, which a line plot draws along x; give x = "
                                 f"{y!r} (--x {y}), or no axis")
            chosen = [f"x = {y}" if c == f"y = {y}" else c for c in chosen]
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


def _logish(values) -> bool:
    """A log axis: positive values over more than a factor 20, or over a factor 5 or more
    and spaced more evenly in their logarithm than in themselves (1, 3, 10)."""
    v = np.sort(np.asarray(values, dtype=float))
    if not (v.size > 2 and np.all(v > 0)):
        return False
    ratio = v[-1] / v[0]

    def spread(d):
        return np.std(d) / np.mean(d)

    return bool(ratio > 20.0 or (ratio >= 5.0 and spread(np.diff(np.log(v)))
                                 < spread(np.diff(v))))


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


#: Variables drawn on a logarithmic colour scale (their 0 and inf are flags, not colours).
_LOG_VARS = ("u_star", "margin", "Ca_star", "St")
#: Units a file may give a dimensionless quantity (CF's "1", older maps' "dimensionless").
_DIMENSIONLESS = ("1", "dimensionless", "", "-")
#: Units as a picture shows them.
_UNIT_TEXT = {"degree": "deg", "m**2/s**2": "m2/s2", "kg/m**3": "kg/m3", "Pa*s": "Pa s"}
#: Scene fields a bed map does not use: its components give the solids, sizes, coatings
#: and asperities, and it averages over collision directions.
_BED_UNUSED = ("solid_i", "solid_j", "d_i", "d_j", "h0_j", "ha_i", "ha_j", "beta_deg")
#: Figure text sizes [pt].
_TITLE_PT, _NOTE_PT = 10, 7


def _wrap(text: str, width: int) -> str:
    """``text`` in lines of at most ``width`` characters, names (silica-sand) kept whole."""
    return textwrap.fill(text, width, break_on_hyphens=False, break_long_words=False)


def _unit_text(units) -> str:
    """A unit as shown: ``-`` for any spelling of dimensionless, ``deg``, ``kg/m3``."""
    if units is None or str(units).strip() in _DIMENSIONLESS:
        return "-"
    return _UNIT_TEXT.get(str(units), str(units))


def _label(long_name: str, units, width: int) -> str:
    return _wrap(f"{long_name} [{_unit_text(units)}]", width)


class _Axis:
    """One axis of a panel grid: where each value sits, the cells' edges (midpoints between
    values, the outer edges at the first and last value: no cell reaches beyond the data)
    and the ticks."""

    def __init__(self, da: xr.DataArray, name: str, width: int):
        coord = da[name]
        values = coord.values
        self.name = name
        self.categorical = not np.issubdtype(values.dtype, np.number)
        self.log = False
        if self.categorical:
            self.order = np.arange(values.size)
            self.pos = np.arange(values.size, dtype=float)
            self.edges = np.arange(values.size + 1) - 0.5
            self.ticks: tuple[np.ndarray, list[str]] | None = (self.pos,
                                                               [str(v) for v in values])
            self.label = _wrap(coord.attrs.get("long_name", name), width)
            return
        scale, offset, unit = _DISPLAY.get(name, (1.0, 0.0, None))
        shown = np.asarray(values, dtype=float) * scale + offset
        self.order = np.argsort(shown, kind="stable")
        self.pos = shown[self.order]
        self.log = _logish(values)
        v = np.log(self.pos) if self.log else self.pos
        if v.size > 1:
            mid = 0.5 * (v[1:] + v[:-1])
            edges = np.concatenate([[v[0]], mid, [v[-1]]])
            self.edges = np.exp(edges) if self.log else edges
            self.edges[0], self.edges[-1] = self.pos[0], self.pos[-1]
        else:  # one value: a narrow cell around it
            half = 0.05 * abs(self.pos[0]) or 0.5
            self.edges = np.array([self.pos[0] - half, self.pos[0] + half])
        few = self.pos.size <= 6
        self.ticks = (self.pos, [f"{p:.4g}" for p in self.pos]) if few else None
        units = unit if unit is not None else coord.attrs.get("units", _field_unit(name))
        self.label = _label(coord.attrs.get("long_name", name), units, width)

    def apply(self, ax, which: str) -> None:
        """Scale, limits (the data's range) and ticks on ``ax``'s ``which`` axis."""
        from matplotlib.ticker import NullLocator

        axis = ax.xaxis if which == "x" else ax.yaxis
        if self.log:
            (ax.set_xscale if which == "x" else ax.set_yscale)("log")
        (ax.set_xlim if which == "x" else ax.set_ylim)(self.edges[0], self.edges[-1])
        if self.ticks is not None:
            axis.set_ticks(self.ticks[0], labels=self.ticks[1])
            axis.set_minor_locator(NullLocator())
        elif self.log and self.edges[-1] < 1e3 * self.edges[0]:
            # under three decades Matplotlib labels minor ticks too ("3x10^-1" beside
            # "4x10^-1", overlapping): label 1, 2 and 5 of each decade, as plain numbers
            from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

            axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
            axis.set_minor_formatter(NullFormatter())


def _field_unit(name: str):
    from ._fields import FIELD_META

    return FIELD_META.get(name, (None,))[0]


def _scene(ds) -> dict:
    try:
        return json.loads(ds.attrs.get("scene", "{}"))
    except (TypeError, ValueError):
        return {}


def _fmt_field(name: str, value) -> str:
    """``name = value`` of a scene field in display units (``T = 25 degC``)."""
    if isinstance(value, bool):
        return f"{name} = {'on' if value else 'off'}"
    if isinstance(value, str | np.str_):
        return f"{name} = {value}"
    if name in _DISPLAY:
        return f"{name} = {_fmt_value(name, value)}"
    unit = _unit_text(_field_unit(name))
    return f"{name} = {float(value):.4g}" + ("" if unit == "-" else f" {unit}")


def _shown_values(ds, sub, name, scene) -> list:
    """The values of scene field ``name`` in the picture: a dimension's, a selection's, or
    the scene's (``solid_j`` None: those of ``solid_i``)."""
    if name in sub.dims:
        return [str(v) for v in sub[name].values]
    if name in sub.coords:
        return [str(sub[name].values.item())]
    if scene.get(name) is None and name == "solid_j":
        return _shown_values(ds, sub, "solid_i", scene)
    return [str(scene[name])] if scene.get(name) is not None else []


def _components(ds) -> list | None:
    try:
        return json.loads(ds.attrs["components"]) if "components" in ds.attrs else None
    except (TypeError, ValueError):
        return None


def _materials_phrase(ds, sub, placed, scene) -> str:
    """``water on silica-sand / ilmenite``, ``water on a silica-sand + ilmenite bed``:
    every material the picture shows, by name (a placed dimension by its name)."""

    def name(field):
        if field in placed:
            return f"each {field}"
        vals = _shown_values(ds, sub, field, scene)
        return " / ".join(vals) if vals else None

    liquid = name("liquid")
    comps = _components(ds)
    if comps is not None:
        solids = " + ".join(c["solid"] for c in comps)
        return (f"{liquid} on " if liquid else "") + f"a {solids} bed"
    si, sj = name("solid_i"), name("solid_j")
    pair = f"{si} / {sj}" if si and sj else (si or "")
    return (f"{liquid} on {pair}" if liquid else pair).strip()


def _fixed_items(ds, sub, scene) -> list[str]:
    """``name = value`` for every scene value the picture's data depend on and that no
    axis, panel, selection or title states."""
    if not scene:
        return []
    dims = set(sub.dims) | {d for d in ds.dims if d in sub.coords}
    bed = _components(ds) is not None
    skip = set(dims) | {"liquid", "solid_i", "solid_j"} | (set(_BED_UNUSED) if bed else set())
    speed = scene.get("speed")
    any_speed = "speed" in dims or speed is None
    uses = {
        "U_Umf": scene.get("U") is None and "U" not in dims,
        "sigma_ln": any_speed or speed == "lognormal",
        "granular_temperature": any_speed or speed == "maxwellian",
        "fluctuation_ratio": any_speed or speed == "excess-gas",
        "u0": any_speed or speed in ("fixed", "lognormal"),
        **{f: any_speed or str(speed).startswith("bubble-")
           for f in ("bed_height", "column_diameter", "orifice_area", "height",
                     "wake_fraction")},
    }
    derived = {"d_j": "d_i", "h0_j": "h0"}
    database = []
    items = []
    for field_name, value in scene.items():
        if field_name in skip or not uses.get(field_name, True):
            continue
        if field_name == "h0" and bed and all(c.get("h0") is not None
                                              for c in _components(ds) or []):
            continue
        if value is None:
            if field_name in derived:
                items.append(f"{field_name} = {derived[field_name]}")
            elif field_name in ("ha_i", "ha_j", "e", "theta_deg"):
                database.append(field_name)
            continue
        items.append(_fmt_field(field_name, value))
    if database:
        items.append(", ".join(database) + " from the materials database")
    return items


def _component_text(ds, sub) -> str | None:
    """The bed's components with their fractions, sizes, coatings and asperities."""
    comps = _components(ds)
    if comps is None:
        return None
    mix = str(ds.attrs.get("mix", ""))
    swept = "fraction" in ds.dims
    parts = []
    for k, c in enumerate(comps):
        is_mix = swept and mix in (c["solid"], str(k))
        if is_mix:
            frac = ("mass fraction = " + _fmt_value("fraction", sub["fraction"].values.item())
                    if "fraction" in sub.coords and sub["fraction"].ndim == 0
                    else "mass fraction as shown")
        elif swept:
            frac = ("mass fraction: the rest" if len(comps) == 2 else
                    f"the rest shared in proportion to {float(c['fraction']):.3g}")
        else:
            frac = f"mass fraction = {float(c['fraction']):.3g}"
        size = []
        if c.get("d") is not None:
            size.append("d = " + ", ".join(f"{float(d) * 1e6:.4g}" for d in c["d"]) + " um")
        if c.get("d50") is not None:
            size.append(f"d50 = {float(c['d50']) * 1e6:.4g} um")
            if float(c.get("gsd", 1.0)) != 1.0:
                size.append(f"gsd = {float(c['gsd']):.3g}, {int(c.get('classes', 1))} classes")
        if c.get("h0") is not None:
            size.append(f"h0 = {float(c['h0']) * 1e6:.4g} um")
        size.append(f"ha = {float(c['ha']) * 1e6:.4g} um" if c.get("ha") is not None
                    else "ha from the materials database")
        parts.append(f"{c['solid']} ({frac}; {', '.join(size)})")
    return "Bed: " + " + ".join(parts)


def _assumed_text(ds, sub, scene) -> str | None:
    """The database assumptions the shown data depend on (materials not shown left out)."""
    comps = _components(ds)
    if comps is not None:  # a bed: every pair of its components, with their asperities
        from .scene import assumed_inputs

        items = []
        for liquid in _shown_values(ds, sub, "liquid", scene):
            for a in comps:
                for b in comps:
                    values = {**scene, "liquid": liquid, "solid_i": a["solid"],
                              "solid_j": b["solid"], "ha_i": a.get("ha"), "ha_j": b.get("ha")}
                    items += [t for t in assumed_inputs(values) if t not in items]
    else:
        text = str(ds.attrs.get("assumed_inputs", "none"))
        if not text or text == "none":
            return None
        shown = set()
        for name in ("solid_i", "solid_j", "liquid", "gas"):
            shown.update(_shown_values(ds, sub, name, scene))
        items = [t.strip() for t in text.split(";")]
        if shown:
            items = [t for t in items if t.split(" ", 1)[0] in shown]
    return ("Assumed values (materials database): " + "; ".join(items)) if items else None


def _nice_levels(lo: float, hi: float) -> np.ndarray:
    """1-2-5 levels within [lo, hi] (at most 8), for u0* contours [m/s]."""
    exps = np.arange(np.floor(np.log10(lo)) - 1, np.ceil(np.log10(hi)) + 1)
    cand = np.sort(np.outer(10.0**exps, [1.0, 2.0, 5.0]).ravel())
    lev = cand[(cand >= lo) & (cand <= hi)]
    while lev.size > 8:
        lev = lev[::2]
    return lev


def _hatch_cells(ax, xa: _Axis, ya: _Axis, mask: np.ndarray, hatch: str) -> None:
    """Hatch the cells (not the spaces between points) where ``mask`` (y, x) holds."""
    from matplotlib.collections import PolyCollection

    rows, cols = np.nonzero(mask)
    x0, x1 = xa.edges[cols], xa.edges[cols + 1]
    y0, y1 = ya.edges[rows], ya.edges[rows + 1]
    verts = np.stack([np.stack([x0, y0], 1), np.stack([x1, y0], 1), np.stack([x1, y1], 1),
                      np.stack([x0, y1], 1)], axis=1)
    pc = PolyCollection(cast(Any, verts), facecolors="none", edgecolors="0.55", linewidths=0.0,
                        hatch=hatch)
    pc.set_hatchcolor("0.55")  # visible on dark and pale colours alike
    ax.add_collection(pc)


def _contours(ax, xa: _Axis, ya: _Axis, z: np.ndarray) -> bool:
    """u0* contours (labelled, readable on any colour) where u0* is finite and varies;
    True if any was drawn."""
    import matplotlib.patheffects as pe

    finite = z[np.isfinite(z) & (z > 0)]
    if (xa.categorical or ya.categorical or not finite.size or z.shape[0] < 2
            or z.shape[1] < 2 or not finite.max() > finite.min() * 1.05):
        return False
    levels = _nice_levels(finite.min(), finite.max())
    if not levels.size:
        return False
    zz = np.where(np.isfinite(z) & (z > 0), z, np.nan)

    def fmt(v):
        return f"{v:g} m/s"

    def draw(levels):
        cs = ax.contour(xa.pos, ya.pos, zz, levels=levels, colors="black", linewidths=0.9)
        return cs, ax.clabel(cs, fmt=fmt, fontsize=7, inline_spacing=2)

    cs, labels = draw(levels)
    # a line too short to carry its label (u0* finite in a strip a few cells wide) cannot
    # be read: such levels are left out
    placed = {t.get_text() for t in labels}
    labelled = np.array([v for v in levels if fmt(v) in placed])
    if labelled.size < levels.size:
        cs.remove()  # its labels with it
        if not labelled.size:
            return False
        cs, labels = draw(labelled)
    for t in labels:
        t.set_path_effects([pe.withStroke(linewidth=2.5, foreground="white")])
    cs.set_path_effects([pe.Stroke(linewidth=2.2, foreground="white"), pe.Normal()])
    return True


#: Colour of a robust map's boundary and band (visible on the propensity's colours).
_BAND = "#1f9bd1"
#: P(unsafe) between these bounds: not decided (agglomtool.maps.robust.UNDECIDED).
_UNDECIDED = (0.1, 0.9)


def _robust_band(ax, xa: _Axis, ya: _Axis, p: np.ndarray) -> set:
    """The window's boundary (P(unsafe) = 0.5), its band (0.1, 0.9) and the undecided
    cells of a robust map; the names of what was drawn."""
    drawn = set()
    lo, hi = _UNDECIDED
    undecided = (p > lo) & (p < hi)
    if undecided.any():
        _hatch_cells(ax, xa, ya, undecided, "xx")
        drawn.add("undecided")
    if xa.categorical or ya.categorical or p.shape[0] < 2 or p.shape[1] < 2:
        return drawn
    for level, style, lw, name in ((0.5, "-", 2.0, "boundary"), (lo, "--", 1.2, "band"),
                                   (hi, "--", 1.2, "band")):
        if np.nanmin(p) < level < np.nanmax(p):
            ax.contour(xa.pos, ya.pos, p, levels=[level], colors=_BAND, linewidths=lw,
                       linestyles=style)
            drawn.add(name)
    return drawn


def _regime_text(sub) -> str | None:
    """What decides the shown data where it has no finite u0* (agglomtool.maps.regime)."""
    from .maps.regime import deciding_regime

    return deciding_regime(sub) or None


def _robust_text(ds) -> str:
    n = ds.attrs.get("robust_samples")
    inputs = ds.attrs.get("robust_uncertain_inputs", "")
    names = "; ".join(part.split(" = ")[0] for part in inputs.split("; ") if part)
    return (f"Robust map: {n} draws per point, the same at every point, of {names}; P is "
            "the share of draws whose propensity exceeds the threshold.")


def _short(var: str) -> str:
    return {"u_star": "u0*", "Ca_star": "Ca at u0*"}.get(var, var)


def _special_reason(var: str, infinite: bool, ceiling: float) -> str:
    """Why ``var`` is infinite (or 0) where it is: u0* and the quantities made of it."""
    sticks = f"sticks at every speed up to the u0* ceiling ({ceiling:g} m/s)"
    no_bridge = "no bridge: the coating is no thicker than the asperities"
    reasons = {"u_star": (sticks, no_bridge), "Ca_star": (sticks, no_bridge),
               "margin": (no_bridge, sticks)}
    if var not in reasons:
        return ""
    return f": {reasons[var][0 if infinite else 1]}"


def _uniform_note(var: str, long_name: str, unit: str, z: np.ndarray, ceiling: float,
                  marked: bool) -> str:
    """What a field without a range of colours holds: ``all points: ... = 1``, or which
    values without a range it has."""
    finite = z[np.isfinite(z) & ((z > 0) if var in _LOG_VARS else True)]
    kinds = []
    if np.isposinf(z).any():
        kinds.append("infinite" + _special_reason(var, True, ceiling))
    if var in _LOG_VARS and (z == 0.0).any():
        kinds.append("0" + _special_reason(var, False, ceiling))
    if finite.size:
        kinds.append(f"{finite[0]:.4g}" + ("" if unit == "-" else f" {unit}"))
    if np.isnan(z).any():
        kinds.append("not computed (NaN)")
    if len(kinds) == 1:
        return f"all points: {long_name} " + ("" if kinds[0].startswith("inf") else "= ") \
            + kinds[0]
    head = (f"{long_name} = {kinds[-1]} where finite" if finite.size
            else f"no point has a finite {long_name}")
    if marked:
        return head + (", the other points marked" if finite.size else ": the marks say why")
    return head + "; " + ", ".join(kinds[:-1] if finite.size else kinds)


def _panel_title(nd: dict) -> str:
    return ", ".join(f"{k} = {_fmt_value(k, v)}" for k, v in nd.items())


def operating_window(ds, var: str = "propensity", *, x=None, y=None, col=None, row=None,
                     sel=None, path=None, title: str | None = None, contours: bool = True):
    """Operating-window picture: ``var`` coloured over two dims, faceted, ``u0*`` contours.

    What is drawn is what the data hold: the cells span the grid values only (edges at the
    midpoints between values, the outer edges at the first and last value), the colour bar
    spans the shown values only, a field of one value gets no colour bar but a note in each
    panel (``all points: ...``), and the legend lists only what is drawn. The title names
    every material shown; notes below the panels state every fixed scene value the data
    depend on and the database's assumptions about the materials shown.

    Parameters
    ----------
    ds : xarray.Dataset or path
        A sweep result or a bed map, or a netCDF file of one.
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
        Figure title (default: the variable, the materials, and the fixed selections).
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
    from matplotlib.colors import BoundaryNorm, ListedColormap, LogNorm, Normalize
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ._fields import U_CEILING

    ds = open_map(ds)
    layout = plan_layout(ds, var, x=x, y=y, col=col, row=row, sel=sel)
    sub = _sel(ds, var, layout.sel)
    x, y, col, row = layout.x, layout.y, layout.col, layout.row
    placed = [d for d in (x, y, col, row) if d is not None]
    da = sub[var]
    for d in da.dims:  # single-valued dims: stated in the title, not an axis
        if d not in placed:
            da = da.isel({d: 0})
    da = da.load()
    scene = _scene(ds)
    ceiling = float(scene.get("u_ceiling") or U_CEILING)
    long_name = ds[var].attrs.get("long_name", var)
    unit = _unit_text(ds[var].attrs.get("units"))
    cats = _categories(ds[var])

    ncol = sub.sizes[col] if col else 1
    nrow = sub.sizes[row] if row else 1
    single = ncol * nrow == 1
    pw, ph = (4.6, 3.5) if single else (3.3, 2.6)
    width = 40 if single else 34  # characters per axis-label line
    fig, axs = plt.subplots(nrow, ncol, squeeze=False, sharex=True, sharey=True,
                            figsize=(pw * ncol + 1.3, ph * nrow))
    xa = _Axis(da, x, width)
    ya = _Axis(da, y, width) if y is not None else None
    order = [d for d in (row, col, y, x) if d is not None]
    data = da.transpose(*order)
    z_all = np.asarray(data.values, dtype=float)
    us_all = None
    if "u_star" in sub and (var == "u_star" or (contours and y is not None)):
        us = sub["u_star"].broadcast_like(sub[var])
        for d in us.dims:
            if d not in placed:
                us = us.isel({d: 0})
        us_all = np.asarray(us.transpose(*order).values, dtype=float)

    # a robust map (sweep(..., uncertain=...)): the window's boundary where the propensity
    # exceeds its threshold with probability 1/2, its band (0.1 and 0.9) and the cells
    # where the answer is not decided
    pu_all = None
    if ("p_unsafe" in sub and y is not None and cats is None
            and var in ("propensity", "propensity_mean")):
        pu = sub["p_unsafe"].broadcast_like(sub[var])
        for d in pu.dims:
            if d not in placed:
                pu = pu.isel({d: 0})
        pu_all = np.asarray(pu.transpose(*order).values, dtype=float)
    robust_drawn = set()
    # a robust map's points whose draws have no impact speed at some draws (undecided = 2):
    # their summaries are NaN, marked as such (those with no nominal speed are below)
    nr_all = None
    if ("undecided" in sub and cats is None
            and (var.startswith("propensity") or var == "p_unsafe")):
        nr = sub["undecided"].broadcast_like(sub[var])
        for d in nr.dims:
            if d not in placed:
                nr = nr.isel({d: 0})
        nr_all = np.asarray(nr.transpose(*order).values) == 2
        if "speed_flag" in sub:
            sf_nr = sub["speed_flag"].broadcast_like(sub[var])
            for d in sf_nr.dims:
                if d not in placed:
                    sf_nr = sf_nr.isel({d: 0})
            nr_all &= np.asarray(sf_nr.transpose(*order).values) == 0
        if not nr_all.any():
            nr_all = None
    # where the impact-speed model has no answer (speed_flag): marked, with the reason
    sf_all = None
    if _speed_flag_of(sub, var):
        sf = sub["speed_flag"].broadcast_like(sub[var])
        for d in sf.dims:
            if d not in placed:
                sf = sf.isel({d: 0})
        sf_all = np.asarray(sf.transpose(*order).values)
        if not sf_all.any():
            sf_all = None

    # colours: categories present, or the shown data's own range (none if one value)
    norm: Any = None
    cmap: Any = None
    legend: list[Any] = []
    note = None
    if cats is not None:
        codes = sorted(cats)
        present = [c for c in codes if np.any(z_all == c)]
        palette = matplotlib.colormaps["tab10"]
        cmap = ListedColormap([palette(codes.index(c) % 10) for c in present] or ["0.9"])
        norm = BoundaryNorm(np.arange(len(present) + 1) - 0.5, max(cmap.N, 1))
        index = {c: k for k, c in enumerate(present)}
        z_plot = np.ma.masked_invalid(np.vectorize(lambda v: index.get(v, np.nan),
                                                   otypes=[float])(z_all))
        legend += [Patch(facecolor=cmap(index[c]), label=cats[c]) for c in present]
    else:
        log = var in _LOG_VARS
        good = np.isfinite(z_all) & ((z_all > 0) if log else True)
        vals = z_all[good]
        z_plot = np.ma.masked_where(~good, z_all)
        if vals.size and vals.max() > vals.min():
            norm = (LogNorm if log else Normalize)(vals.min(), vals.max())
            cmap = matplotlib.colormaps["magma_r" if "propensity" in var else "viridis"]
        else:
            cmap = ListedColormap(["0.88"])
            norm = Normalize(0.0, 1.0)
            z_plot = np.ma.masked_where(~good, np.full(z_all.shape, 0.5))
            marked = var in _LOG_VARS and (y is None or us_all is not None)  # inf and 0
            note = _uniform_note(var, long_name, unit, z_all, ceiling, marked)

    hatches, edge_marks = {}, {}
    contoured = False
    mesh = None
    for i in range(nrow):
        for j in range(ncol):
            ax = axs[i, j]
            idx = tuple(k for k, d in ((i, row), (j, col)) if d is not None)
            z = z_plot[idx]
            nd = {d: sub[d].values[k] for k, d in ((i, row), (j, col)) if d is not None}
            if ya is None:  # y is None
                zz: np.ndarray = np.ma.filled(np.ma.asarray(z, dtype=float), np.nan)[xa.order]
                raw = z_all[idx][xa.order]
                if note is not None and cats is None:  # one value or none: no y range
                    zz = np.where(np.ma.getmaskarray(z)[xa.order], np.nan, 0.5)
                    one = raw[np.isfinite(raw) & ((raw > 0) if var in _LOG_VARS else True)]
                    ax.set_ylim(0.0, 1.0)
                    ax.set_yticks([0.5] if one.size else [],
                                  labels=[f"{one[0]:.4g}"] if one.size else [])
                ax.plot(xa.pos, zz, marker="o", ms=3, color="k", lw=1.0, clip_on=False)
                if sf_all is not None:  # no impact speed: marked at the panel's bottom
                    flagged = sf_all[idx][xa.order] != 0
                    if flagged.any():
                        ax.plot(xa.pos[flagged], np.zeros(flagged.sum()), ls="none",
                                marker="x", ms=6, color="0.35", clip_on=False,
                                transform=ax.get_xaxis_transform())
                        edge_marks["x"] = _no_speed_label(
                            sub, np.unique(sf_all[sf_all != 0]))
                if nr_all is not None:  # no robust answer: marked at the panel's bottom
                    lost = nr_all[idx][xa.order]
                    if lost.any():
                        ax.plot(xa.pos[lost], np.zeros(lost.sum()), ls="none", marker="+",
                                ms=7, color="0.35", clip_on=False,
                                transform=ax.get_xaxis_transform())
                        edge_marks["+"] = _NO_ROBUST_LABEL
                if note is None:
                    ax.margins(y=0.06)
                if cats is not None:
                    ax.set_yticks(range(len(index)), labels=[cats[c] for c in index])
                elif var in _LOG_VARS:
                    if note is None:
                        ax.set_yscale("log")
                    # points with no finite value: marked at the panel's top or bottom edge
                    for mask, at_y, marker, label in (
                            (np.isposinf(raw), 1.0, "^", f"{_short(var)} infinite"
                             + _special_reason(var, True, ceiling)),
                            (raw == 0.0, 0.0, "v", f"{_short(var)} = 0"
                             + _special_reason(var, False, ceiling))):
                        if mask.any():
                            ax.plot(xa.pos[mask], np.full(mask.sum(), at_y), ls="none",
                                    marker=marker, ms=6, color="0.35", clip_on=False,
                                    transform=ax.get_xaxis_transform())
                            edge_marks[marker] = label
            else:
                zz = z[np.ix_(ya.order, xa.order)]
                mesh = ax.pcolormesh(xa.edges, ya.edges, zz, cmap=cmap, norm=norm,
                                     shading="flat")
                if us_all is not None:
                    u = us_all[idx][np.ix_(ya.order, xa.order)]
                    masks = ((np.isposinf(u), "//", "u0* infinite"
                              + _special_reason("u_star", True, ceiling)),
                             (u == 0.0, "..", "u0* = 0" + _special_reason("u_star", False,
                                                                          ceiling)))
                    for mask, hatch, label in masks:
                        if mask.any():
                            _hatch_cells(ax, xa, ya, mask, hatch)
                            hatches[hatch] = label
                    if contours:
                        contoured |= _contours(ax, xa, ya, u)
                if sf_all is not None:
                    flagged = sf_all[idx][np.ix_(ya.order, xa.order)] != 0
                    if flagged.any():
                        _hatch_cells(ax, xa, ya, flagged, _NO_SPEED_HATCH)
                        hatches[_NO_SPEED_HATCH] = _no_speed_label(
                            sub, np.unique(sf_all[sf_all != 0]))
                if nr_all is not None:
                    lost = nr_all[idx][np.ix_(ya.order, xa.order)]
                    if lost.any():
                        _hatch_cells(ax, xa, ya, lost, _NO_ROBUST_HATCH)
                        hatches[_NO_ROBUST_HATCH] = _NO_ROBUST_LABEL
                if pu_all is not None:
                    robust_drawn |= _robust_band(ax, xa, ya,
                                                 pu_all[idx][np.ix_(ya.order, xa.order)])
                ya.apply(ax, "y")
            xa.apply(ax, "x")
            if note is not None:
                kept = note.replace(" m/s", "\u00a0m/s")  # a number and its unit together
                ax.text(0.5, 0.5, _wrap(kept, 34 if single else 28),
                        transform=ax.transAxes, ha="center", va="center", fontsize=8,
                        bbox=dict(boxstyle="round", facecolor="white", alpha=0.9,
                                  edgecolor="0.6"))
            ax.set_title(_panel_title(nd), fontsize=9)
            if i == nrow - 1:
                ax.set_xlabel(xa.label)
            if j == 0:
                ax.set_ylabel(ya.label if ya is not None else _label(long_name, unit, width))
            if xa.categorical and i == nrow - 1:
                ax.tick_params(axis="x", labelrotation=30 if ncol > 1 else 0)
    fig.subplots_adjust(wspace=0.15,
                        hspace=0.3 if not col and not row else 0.35)
    if mesh is not None and cats is None and note is None:
        cb = fig.colorbar(mesh, ax=axs.ravel().tolist(), pad=0.025,
                          fraction=0.05 if single else 0.035)
        cb.set_label(_label(long_name, unit, 30))
    legend += [Patch(facecolor="white", edgecolor="0.4", hatch=h, label=lab)
               for h, lab in hatches.items()]
    legend += [Line2D([], [], ls="none", marker=m, ms=6, color="0.35", label=lab)
               for m, lab in edge_marks.items()]
    if contoured:
        legend.append(Line2D([], [], color="black", lw=0.9, label="u0* contours [m/s]"))
    if robust_drawn:
        thr = float(sub["p_unsafe"].attrs.get("threshold", 0.5))
        lo, hi = _UNDECIDED
        if "boundary" in robust_drawn:
            legend.append(Line2D([], [], color=_BAND, lw=2.0, label=(
                f"window boundary: P(propensity > {thr:g}) = 0.5")))
        if "band" in robust_drawn:
            legend.append(Line2D([], [], color=_BAND, lw=1.2, ls="--", label=(
                f"confidence band: P = {lo:g} and {hi:g}")))
        if "undecided" in robust_drawn:
            legend.append(Patch(facecolor="none", edgecolor=_BAND, hatch="xx", label=(
                f"not decided ({lo:g} < P < {hi:g})")))

    # texts: title above everything, legend and notes below everything, none overlapping
    phrase = _materials_phrase(ds, sub, placed, scene)
    chosen = _selections(ds, da, placed)
    fixed = _fixed_items(ds, sub, scene)
    if title is None:  # the variable and the materials; below, the fixed selections
        title = f"{long_name}: {phrase}" if phrase else long_name
        title += "\n" + ", ".join(chosen) if chosen else ""
    else:  # the caller's title: the materials and selections go to the notes
        fixed = ([f"materials: {phrase}"] if phrase else []) + chosen + fixed
    notes = [t for t in (_component_text(ds, sub),
                         ("Fixed: " + ", ".join(fixed)) if fixed else None,
                         _assumed_text(ds, sub, scene),
                         _robust_text(ds) if robust_drawn else None,
                         _regime_text(sub)) if t]
    if contoured:
        _labels_inside(fig, axs)
    _place_texts(fig, axs, title, legend, notes)
    fig.layout = layout  # type: ignore[attr-defined]  # read by the CLI and the tests
    if path is not None:  # a name without a suffix is a PNG there (not name.png beside it)
        from pathlib import Path

        fmt = None if Path(path).suffix else "png"
        fig.savefig(path, dpi=150, bbox_inches="tight", format=fmt)
    return fig


def _labels_inside(fig, axs) -> None:
    """Move a contour label that sticks out of its panel (a line next to an edge) inside,
    beside its line, so that no label is clipped."""
    from matplotlib.text import Text

    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    for ax in axs.ravel():
        box = ax.get_window_extent(r)
        for t in ax.texts:
            if not isinstance(t, Text) or t.get_transform() != ax.transData:
                continue
            ext = t.get_window_extent(r)
            dx = max(0.0, box.x0 - ext.x0) - max(0.0, ext.x1 - box.x1)
            dy = max(0.0, box.y0 - ext.y0) - max(0.0, ext.y1 - box.y1)
            if dx or dy:
                px, py = ax.transData.transform(t.get_position())
                t.set_position(ax.transData.inverted().transform((px + dx, py + dy)))


def _place_texts(fig, axs, title: str, legend: list, notes: list) -> None:
    """The title above the panels' titles, the legend below the lowest label, each note
    below the one before; measured on the drawn figure, so nothing overlaps."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    to_fig = fig.transFigure.inverted()
    boxes = [ax.get_tightbbox(r) for ax in fig.axes if ax.get_visible()]
    lo = min(to_fig.transform((0, b.y0))[1] for b in boxes)
    hi = max(to_fig.transform((0, b.y1))[1] for b in boxes)
    panels = [ax.get_window_extent(r) for ax in axs.ravel()]
    x0 = to_fig.transform((min(b.x0 for b in panels), 0))[0]
    x1 = to_fig.transform((max(b.x1 for b in panels), 0))[0]
    cx = 0.5 * (x0 + x1)
    fig_w = fig.get_figwidth()
    gap = 0.08 / fig.get_figheight()  # inches to figure fraction
    fig.suptitle("\n".join(_wrap(line, int(fig_w * 13)) for line in
                           title.split("\n")),
                 fontsize=_TITLE_PT, x=cx, y=hi + 2 * gap, va="bottom")
    y = lo - gap
    if legend:
        longest = max(len(h.get_label()) for h in legend)
        ncol = next(k for k in range(min(3, len(legend)), 0, -1)
                    if k == 1 or k * (0.065 * longest + 0.6) <= fig_w)  # inches at 8 pt
        lg = fig.legend(handles=legend, loc="upper center", ncol=ncol,
                        fontsize=8, frameon=False, bbox_to_anchor=(cx, y),
                        bbox_transform=fig.transFigure)
        y = to_fig.transform((0, lg.get_window_extent(r).y0))[1] - gap
    for text in notes:
        t = fig.text(cx, y, _wrap(text, int(fig_w * 19)), ha="center", va="top",
                     fontsize=_NOTE_PT, color="0.3")
        y = to_fig.transform((0, t.get_window_extent(r).y0))[1] - gap


def _selections(ds, da, placed) -> list[str]:
    """``T = 25 degC`` for each dimension fixed by a selection or of one value (materials
    are named by :func:`_materials_phrase`)."""
    named = {"liquid", "solid_i", "solid_j"}
    return [f"{d} = {_fmt_value(d, da[d].values.item())}" for d in da.coords
            if d in ds.dims and d not in placed and d not in named and da[d].ndim == 0]


def speed_model_windows(scene, *, models=None, var: str = "propensity", x=None, y=None,
                        row=None, path=None, calibrated: bool = True, nodes: int = 16,
                        **grid):
    """The operating window of ``scene`` under each impact-speed model, side by side.

    Sweeps ``scene`` over ``grid`` (two or three dimensions, as for
    :func:`agglomtool.sweep`) and over the ``speed`` models, and draws the map with one
    facet column per model (:func:`operating_window`): how far the window moves with the
    choice of model.

    Parameters
    ----------
    scene : Scene
        The operating point; its own ``speed`` is replaced by each model.
    models : sequence of str, optional
        The models to draw (names of
        :data:`agglomtool.bed.speed_models.IMPACT_SPEED_MODELS`); default those valid at
        ``scene`` (:func:`agglomtool.impact_speed_methods`, with ``calibrated``).
    var, x, y, row, path
        As for :func:`operating_window` (the columns are the models).
    nodes : int
        Quadrature nodes of the impact-speed distribution.
    **grid
        The swept fields and their values.

    Returns
    -------
    matplotlib.figure.Figure
        With the map as its attribute ``data`` (the :class:`xarray.Dataset`).
    """
    from .bed.speed_models import IMPACT_SPEED_MODELS
    from .maps.grid import sweep
    from .scene import impact_speed_methods

    if "speed" in grid:
        raise ValueError("speed is the facet of this picture: give the models as models=[...]"
                         ", not in the grid")
    if models is None:
        models = [m for m in impact_speed_methods(scene, calibrated=calibrated)
                  if m in IMPACT_SPEED_MODELS]
    models = list(models)
    bad = [m for m in models if m not in IMPACT_SPEED_MODELS]
    if bad or not models:
        raise ValueError(f"models = {models!r}: give one or more of "
                         f"{', '.join(IMPACT_SPEED_MODELS)} (the impact-speed models)")
    ds = sweep(scene, speed=models, nodes=nodes, **grid)
    fig = operating_window(ds, var, x=x, y=y, col="speed", row=row, path=path)
    fig.data = ds
    return fig

