"""Command line: ``agglomtool COMMAND``. Each command is one call of the Python API.

Start-up is kept fast: this module imports only the standard library and the light field
specification; the package's heavy parts (CoolProp, Numba, xarray, dask, matplotlib) are
imported by the command that needs them, so ``--help`` and ``--version`` answer at once.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Mapping
from typing import Any

from ._fields import CATEGORICAL_FIELDS, CHOICES, DEFAULTS, DERIVED, FIELD_META, short_unit
from ._version import __version__

#: Exit status for bad input, and for an interrupted command (128 + SIGINT).
EXIT_BAD_INPUT, EXIT_INTERRUPTED = 2, 130


class CommandError(Exception):
    """A failure to report as one line (no traceback)."""


def _cmd_reference(args: argparse.Namespace) -> int:
    """Evaluate the paper's two reference cases (Table 2) and print u0* and e_w."""
    from ._validate import check_field
    from .examples import reference_cases

    check_field("--beta", args.beta, key="beta_deg")  # the Scene's collision angle
    for case in reference_cases():
        print(case.report(beta_deg=args.beta, mode=args.mode))
        print()
    return 0


def _show_progress(args: argparse.Namespace) -> bool:
    """The progress bar: asked for (--progress), else where stderr is a terminal, never with
    --quiet."""
    return bool(args.progress or (not args.quiet and sys.stderr.isatty()))


class _LogToStderr:
    """While open, the ``agglomtool.maps`` logger's INFO and above go to stderr as
    ``agglomtool: MESSAGE`` lines (a sweep's estimate, the compile note), and only there."""

    def __enter__(self):
        import logging

        self.logger = logging.getLogger("agglomtool.maps")
        self.handler = logging.StreamHandler(sys.stderr)
        self.handler.setFormatter(logging.Formatter("agglomtool: %(message)s"))
        self.saved = self.logger.level, self.logger.propagate
        self.logger.addHandler(self.handler)
        self.logger.setLevel(logging.INFO)
        self.logger.propagate = False
        return self

    def __exit__(self, *exc):
        self.logger.removeHandler(self.handler)
        self.logger.level, self.logger.propagate = self.saved


def _cmd_map(args: argparse.Namespace) -> int:
    """Sweep the scene and grid of a TOML file; write the map as compressed netCDF."""
    from pathlib import Path

    from .maps.cluster import NoWorkersError
    from .maps.config import load_config
    from .maps.export import check_netcdf_name, write_map
    from .maps.grid import sweep
    from .maps.store import hold_store, remove_store

    cfg = load_config(args.config)
    out = check_netcdf_name(args.output)  # before any work
    store = Path(args.store) if args.store else out.with_name(out.name + ".parts")
    args._store = store  # for the message if interrupted
    client = None
    if args.scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ImportError("--scheduler needs dask.distributed: pip install "
                              "'agglomtool[cluster]'") from None
        client = Client(args.scheduler)
    robust = cfg.uncertain is not None
    if robust and (args.store or args.scheduler):
        raise CommandError("a robust map ([uncertain] in the file) is computed in memory, "
                           "here: --store and --scheduler are not for it")
    complevel = 0 if args.no_compress else 4
    try:
        with _LogToStderr():  # the estimate line, always; the compile note without a bar
            if robust:
                ds = sweep(cfg.scene, chunks=cfg.options["chunks"], nodes=cfg.options["nodes"],
                           progress=_show_progress(args), uncertain=cfg.uncertain,
                           samples=cfg.options["samples"], threshold=cfg.options["threshold"],
                           seed=cfg.options["seed"], **cfg.grid)
                write_map(ds, out, complevel=complevel, history=_command(args))
            else:
                # one owner from the sweep to the store's removal: the lock is held until
                # the store is gone, so no other run reuses blocks whose files vanish
                with hold_store(store):
                    ds = sweep(cfg.scene, chunks=cfg.options["chunks"],
                               nodes=cfg.options["nodes"], store=store,
                               progress=_show_progress(args), overwrite=args.overwrite,
                               client=client if client is not None else False, **cfg.grid)
                    write_map(ds, out, complevel=complevel, history=_command(args))
                    ds.close()
                    if not args.keep_parts:
                        remove_store(store)
    except NoWorkersError as exc:
        raise CommandError(str(exc)) from None
    finally:
        if client is not None:
            client.close()
    sizes = " x ".join(f"{k} {v}" for k, v in ds["propensity"].sizes.items())
    print(f"wrote {out} ({sizes}; {out.stat().st_size / 1e6:.3g} MB)")
    if robust:
        und = float((ds["undecided"] == 1).mean())  # 2: no impact speed, not undecided
        print(f"robust map: {ds.attrs['robust_samples']} draws per point; the answer is not "
              f"decided at {100 * und:.0f} % of the points (0.1 < P(propensity > "
              f"{ds.attrs['robust_threshold']:g}) < 0.9)")
    if ds.attrs.get("deciding_regime"):
        print(f"note: {ds.attrs['deciding_regime']}")
    return 0


def _cmd_bed(args: argparse.Namespace) -> int:
    """Propensity of a bed of mixed solids and sizes (TOML); write it as netCDF."""

    from .bed.config import load_bed_config
    from .bed.export import export_efficiency
    from .bed.propensity import bed_propensity, bed_sweep
    from .maps.export import check_netcdf_name, check_output_dir, write_map

    cfg = load_bed_config(args.config)
    out = check_netcdf_name(args.output)  # before the bed is computed
    if args.efficiency:  # .csv or .nc
        check_output_dir(args.efficiency)
    opts = cfg.options
    if cfg.grid:
        if args.efficiency:
            raise CommandError("--efficiency needs a bed without [grid] (one operating point)")
        ds = bed_sweep(cfg.scene, cfg.components, mix=opts["mix"], nodes=opts["nodes"],
                       directions=opts["directions"], progress=_show_progress(args),
                       **cfg.grid)
        p = ds["propensity"]
        sizes = " x ".join(f"{k} {v}" for k, v in p.sizes.items())
        lost, total = int(p.isnull().sum()), int(p.size)
        if lost == total:  # the warning says why (speed_flag)
            print(f"bed propensity: no answer at any of the {total} points ({sizes}; "
                  "speed_flag says why)")
        else:
            lo, hi = float(p.min()), float(p.max())
            span = f"{lo:.4g}" if f"{lo:.4g}" == f"{hi:.4g}" else f"{lo:.4g}-{hi:.4g}"
            print(f"bed propensity {span} over {sizes}"
                  + (f"; no answer at {lost} of {total} points (speed_flag says why)"
                     if lost else ""))
    else:
        ds = bed_propensity(cfg.scene, cfg.components, nodes=opts["nodes"],
                            directions=opts["directions"])
        parts = ", ".join(f"{c} {float(v):.4g}" for c, v in
                          zip(ds.component.values, ds.propensity_by_component.values,
                              strict=True))
        print(f"bed propensity {float(ds.propensity):.4g} (by component: {parts}); "
              f"U_mf {float(ds.Umf):.4g} m/s, U {float(ds.U):.4g} m/s")
        if args.efficiency:
            print(f"wrote {export_efficiency(ds, args.efficiency, history=_command(args))}")
    write_map(ds, out, history=_command(args))
    print(f"wrote {out}")
    return 0


def _command(args: argparse.Namespace) -> str:
    """The command line that ran, as a file's ``history`` records it."""
    import shlex

    return shlex.join(["agglomtool", *args._argv])


def _parse_sel(items) -> dict:
    """``--sel NAME=VALUE`` items: a Scene field's number in SI or with a unit ("400 um",
    through :func:`agglomtool.units.to_si`), another dimension's number, or a name."""
    sel: dict[str, Any] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name, value = name.strip(), value.strip()
        if not sep or not name or not value:
            raise CommandError(f"--sel {item!r}: write NAME=VALUE, e.g. --sel d_i=500e-6 or "
                               "--sel \"d_i=500 um\"")
        if name in sel:  # one picture shows one value of a fixed dimension
            raise CommandError(f"--sel {name} is given twice ({item!r} after {name} = "
                               f"{sel[name]!r}); a picture fixes a dimension at one value: "
                               f"give one --sel {name}, or place {name} on an axis or facet "
                               "(--x, --y, --col, --row) to see several")
        if name in FIELD_META:
            from .units import to_si

            try:
                sel[name] = float(to_si(name, value, *FIELD_META[name]))
            except ValueError as exc:
                raise CommandError(f"--sel {item!r}: {exc}") from None
            continue
        try:
            sel[name] = float(value)
        except ValueError:
            sel[name] = value
    return sel


def _cmd_compare(args: argparse.Namespace) -> int:
    """Compare the options of one field under paired draws of the uncertain inputs."""
    from .uncertainty.compare import compare
    from .uncertainty.config import load_compare_config

    cfg = load_compare_config(args.config)
    n = args.n if args.n is not None else cfg.n
    options: dict[str, Any] = {cfg.field: cfg.options}
    ds = compare(cfg.scene, uncertain=cfg.uncertain, n=n, seed=cfg.seed, **options)
    q = ds.propensity_quantile
    what = ("the values the database assumes" if cfg.uncertain == "assumed"
            else ds.attrs["uncertain_inputs"])
    print(f"{cfg.field}: propensity over {n} plausible inputs (paired draws; uncertain: "
          f"{what})")
    print(f"  {'option':18s} {'mean':>6s} {'5 %':>6s} {'50 %':>6s} {'95 %':>6s}")
    for opt in ds.option.values:
        row = [float(ds.propensity_mean.sel(option=opt))] + [
            float(q.sel(option=opt, quantile=p)) for p in (0.05, 0.5, 0.95)]
        print(f"  {opt:18s} " + " ".join(f"{v:6.3f}" for v in row))
    for line in ds.attrs["verdicts"].splitlines():
        print(line)
    if ds.attrs.get("assumed_not_drawn"):
        print(f"assumed but not drawn: {ds.attrs['assumed_not_drawn']}")
    if args.output:
        from .maps.export import write_map

        # through write_map, as maps: names as character arrays (a netCDF library's crash
        # on variable-length strings), compressed, CF-ready
        print(f"wrote {write_map(ds, args.output, history=_command(args))}")
    return 0


def _cmd_plot(args: argparse.Namespace) -> int:
    """Draw the operating window of a map file."""
    from .plots import operating_window

    fig = operating_window(args.map, var=args.var, x=args.x, y=args.y, col=args.col,
                           row=args.row, sel=_parse_sel(args.sel), path=args.output)
    print(f"wrote {args.output}: {fig.layout.describe()}")
    return 0


def _scene_from_args(args: argparse.Namespace):
    from .scene import Scene, typed_without_effect

    given = {name: getattr(args, f"scene_{name}") for name in DEFAULTS
             if getattr(args, f"scene_{name}", None) is not None}
    if "body_forces" in given:
        given["body_forces"] = given["body_forces"] == "on"
    scene = Scene(**given)
    found = typed_without_effect(scene, given)
    if found:
        raise CommandError(f"--{found[0].replace('_', '-')}: {found[1]}")
    return scene


def _cmd_collide(args: argparse.Namespace) -> int:
    """One collision of a scene, as a readable report."""
    from .scene import Resolved, critical_outputs

    scene = _scene_from_args(args)
    r = Resolved(scene.values())
    u0 = float(r.u_typical)
    res = r.collide(u0, details=True)
    crit = critical_outputs(r)
    us, flag, ca = float(crit["u_star"]), int(crit["u_star_flag"]), float(crit["Ca_star"])
    p_i, p_j = r.particles
    lines = [
        f"scene: {scene.solid_i} ({float(p_i.d) * 1e6:g} um) - {scene.solid_j or scene.solid_i}"
        f" ({float(p_j.d) * 1e6:g} um), {scene.liquid} h0 = {float(p_i.h0) * 1e6:g} um, "
        f"{scene.gas} at {scene.T - 273.15:g} degC, {scene.P / 1e5:g} bar, "
        f"beta = {scene.beta_deg:g} deg, mode {scene.mode}",
        f"properties: mu_g = {float(r.mu_g):.4g} Pa s, rho_g = {float(r.rho_g):.4g} kg/m3, "
        f"mu_l = {float(r.liquid.mu):.4g} Pa s, gamma = {float(r.liquid.gamma):.4g} N/m, "
        f"rho_l = {float(r.liquid.rho):.4g} kg/m3",
        f"fluidization: U_mf = {float(r.Umf):.4g} m/s, U = {float(r.U):.4g} m/s, "
        f"U_e = {float(r.U_e):.4g} m/s",
        f"impact speed u0 = {u0:.4g} m/s ({scene.speed}"
        + (", the median" if scene.speed != "fixed" else "") + ")",
        res.explain(),
    ]
    if flag == 2:
        lines.append(f"critical impact speed: above the ceiling of {scene.u_ceiling:g} m/s: the "
                     "pair sticks at every speed a bed can give it")
    elif flag == 1:
        lines.append("critical impact speed u0* = 0: the coating is no thicker than the "
                     "asperities, no bridge forms, the pair never sticks")
    else:
        lines += [f"critical impact speed u0* = {us:.4g} m/s (margin u0/u0* = {u0 / us:.3g})",
                  f"capillary number at u0*: Ca = {ca:.3g} -> "
                  + ("viscous-limited" if ca > 1.0 else "capillary-limited")]
    lines += _assumed_lines(scene)
    print("\n".join(lines))
    return 0


def _assumed_lines(scene) -> list[str]:
    """The database values the report used that are assumptions, with their plausible
    laws (``agglomtool compare`` and ``uncertain="assumed"`` draw from them)."""
    from .uncertainty.assumed import assumed_draws, chosen_fields

    inputs, not_drawn = assumed_draws(scene.values(), chosen=chosen_fields(scene))
    if not inputs and not not_drawn:
        return []
    scale = {"asperity_height": (1e6, "um"), "restitution_dry": (1.0, ""),
             "theta_deg": (1.0, "deg")}
    out = ["assumed values used (the materials database's and the speed estimate's, with "
           "their plausible ranges):"]
    from . import materials

    said = set()
    for a in inputs.values():
        if a.field.startswith("composition_wt "):  # one line for the whole composition
            if a.entry not in said:
                said.add(a.entry)
                wt: Mapping[str, float] = materials.liquid_entry(a.entry).composition_wt or {}
                lo, hi = a.law.params
                out.append(f"  {a.entry} composition_wt = "
                           + ", ".join(f"{k} {w:g}" for k, w in wt.items())
                           + f" wt % (each oxide's share times a lognormal factor, 5-95 % "
                           f"{lo:g}-{hi:g}, rescaled to 100 wt %)")
            continue
        if a.field == "speed":  # the model choice: a name, drawn with weights
            from .uncertainty.assumed import speed_model_weights

            w = speed_model_weights(scene.values())
            out.append(f"  impact-speed model = {scene.values()['speed']} (drawn among "
                       + ", ".join(f"{k} {v:.2f}" for k, v in w.items()) + ")")
            continue
        f, unit = scale.get(a.field, (1.0, ""))
        lo, hi = (v * f for v in a.law.params)
        what = ("lognormal, 5-95 %" if a.law.law == "lognormal" else "uniform on")
        out.append(f"  {a.entry} {a.field} = {a.value * f:g} {unit}".rstrip()
                   + f" ({what} {lo:g}-{hi:g} {unit})".replace(" )", ")"))
    out += [f"  {t}" for t in not_drawn]
    out.append("  (agglomtool compare, or uncertain=\"assumed\" in Python, says how much the "
               "answer depends on them)")
    return out


def _cmd_materials(args: argparse.Namespace) -> int:
    """What the materials database holds, with sources."""
    from . import materials

    for kind in materials.KINDS:
        print(f"{_plural(kind)}:")
        for name in materials.names(kind):
            entry = getattr(materials, "liquid_entry" if kind == "liquid" else kind)(name)
            extra = f" [{entry.model}]" if kind == "liquid" else ""
            print(f"  {name}{extra}")
            print("    source: " + " ".join(entry.source.split()))
            print("    confidence: " + " ".join(entry.confidence.split()))
        print()
    return 0


def _plural(kind: str) -> str:
    """The database's kind of entry in the plural ("gas" -> "gases")."""
    return kind + ("es" if kind.endswith("s") else "s")


def _database_names(kind: str) -> str:
    """The database's names of ``kind`` for a help text (reads TOML only)."""
    try:
        from . import materials

        return ", ".join(materials.names(kind))
    except Exception:  # noqa: BLE001 - a broken user file must not break --help
        return f"see 'agglomtool materials' ({_plural(kind)})"


def _default_text(name: str) -> str:
    value = DEFAULTS.get(name)  # a field's name; DEFAULTS has one entry per field
    if value is None:
        return DERIVED.get(name, "none")
    if name == "T":
        return f"{value:g} K = {DEFAULTS['T'] - 273.15:g} degC"
    return f"{value:g}" if isinstance(value, float) else str(value)


#: An example quantity per unit, for help texts.
_EXAMPLES = {"K": "850 degC", "Pa": "1.5 bar", "m": "5 um", "m/s": "30 cm/s",
             "deg": "30 deg", "m2/s2": "0.01 m**2/s**2"}


def _add_scene_options(p: argparse.ArgumentParser) -> None:
    kinds = {"gas": "gas", "solid_i": "solid", "solid_j": "solid", "liquid": "liquid"}
    for name in DEFAULTS:
        flag = "--" + name.replace("_", "-")
        if name == "body_forces":
            p.add_argument("--body-forces", dest="scene_body_forces", choices=["on", "off"],
                           help="weight, buoyancy and drag (default: on)")
        elif name in CHOICES:
            p.add_argument(flag, dest=f"scene_{name}", choices=CHOICES[name], metavar="NAME",
                           help=f"one of {', '.join(CHOICES[name])} "
                                f"(default: {_default_text(name)})")
        elif name in CATEGORICAL_FIELDS:
            p.add_argument(flag, dest=f"scene_{name}", metavar="NAME",
                           help=f"one of {_database_names(kinds[name])} "
                                f"(default: {_default_text(name)})")
        else:
            long_name = FIELD_META[name][1]
            unit = short_unit(name) or "-"
            given = ("-" if unit == "-" else  # a number: no unit to write
                     f"{unit}, or a quantity such as \"{_EXAMPLES.get(unit, '1 ' + unit)}\"")
            p.add_argument(flag, dest=f"scene_{name}", metavar=unit.upper(),
                           help=f"{long_name} [{given}] (default: {_default_text(name)})")


def _add_progress_options(p: argparse.ArgumentParser) -> None:
    which = p.add_mutually_exclusive_group()
    which.add_argument("--progress", action="store_true",
                       help="show the progress bar (points done, rate, time left) on stderr "
                       "even when it is not a terminal (default: only on a terminal)")
    which.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def build_parser(command: str | None = "collide") -> argparse.ArgumentParser:
    """The parser; ``command`` is the sub-command about to run (the scene options of
    ``collide``, whose help lists the database's names, are built only for it)."""
    parser = argparse.ArgumentParser(
        prog="agglomtool",
        description="Will wet or ash-coated particles in a fluidized bed stick together?",
    )
    parser.add_argument("--version", action="version", version=f"agglomtool {__version__}")
    strict_help = ("treat plausibility warnings (unit slips, sizes outside a solid's range, "
                   "...) as errors; before or after the command")
    threads_help = ("threads of the compiled kernels in this process (default: every core "
                    "Numba found); fewer where other jobs hold cores, before or after the "
                    "command")
    parser.add_argument("--strict", action="store_true", help=strict_help)
    parser.add_argument("--threads", type=int, metavar="N", default=None, help=threads_help)
    # Every command takes --strict and --threads too (after its name); SUPPRESS keeps one
    # given before the command from being reset by the command's default.
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--strict", action="store_true", default=argparse.SUPPRESS,
                        help=strict_help)
    common.add_argument("--threads", type=int, metavar="N", default=argparse.SUPPRESS,
                        help=threads_help)
    sub = parser.add_subparsers(dest="command", required=True)
    _add_parser = sub.add_parser
    # every subcommand takes the common options  # mypy: patching the bound method
    sub.add_parser = lambda *a, **kw: _add_parser(*a, parents=[common], **kw)  # type: ignore[method-assign]
    ref = sub.add_parser(
        "reference",
        help="the paper's reference cases (water, slag): critical impact speed and e_w",
    )
    ref.add_argument("--beta", type=float, nargs="+", default=[0.0, 45.0, 90.0],
                     metavar="DEG", help="collision angles [deg] (default: 0 45 90)")
    ref.add_argument("--mode", default="paper", choices=CHOICES["mode"], metavar="NAME",
                     help=f"model tier, one of {', '.join(CHOICES['mode'])} (default: paper)")
    ref.set_defaults(func=_cmd_reference)

    mp = sub.add_parser("map", help="sweep a scene over a grid (TOML) into a netCDF map")
    mp.add_argument("config", help="TOML file with [scene], [grid] and [options]")
    mp.add_argument("-o", "--output", required=True, help="netCDF file to write")
    mp.add_argument("--store", help="the sweep's store, a directory (zarr; default "
                    "OUTPUT.parts); an interrupted map run again resumes from it")
    mp.add_argument("--keep-parts", action="store_true", help="keep the block directory")
    mp.add_argument("--overwrite", action="store_true",
                    help="start the store again if it holds a different sweep (default: refuse,"
                    " saying what differs)")
    mp.add_argument("--scheduler", metavar="ADDRESS",
                    help="run the blocks on a dask.distributed cluster, e.g. "
                    "tcp://scheduler-host:8786 (the store must be on a file system every "
                    "worker reaches)")
    mp.add_argument("--no-compress", action="store_true",
                    help="write the netCDF uncompressed (default: zlib level 4)")
    _add_progress_options(mp)
    mp.set_defaults(func=_cmd_map)

    pl = sub.add_parser("plot", help="operating-window picture of a map",
                        description="Draw a map. Every dimension of more than one value is "
                        "an axis, a facet column or row, or fixed with --sel; dimensions left "
                        "open are placed by the tool, which says where.")
    pl.add_argument("map", help="netCDF map written by 'agglomtool map'")
    pl.add_argument("-o", "--output", required=True, help="PNG file to write")
    pl.add_argument("--var", default="propensity", metavar="NAME",
                    help="variable to colour, e.g. propensity, u_star, e_w, stage, margin "
                    "(default: propensity)")
    for name, what in (("x", "the x axis"), ("y", "the y axis"), ("col", "facet columns"),
                       ("row", "facet rows")):
        pl.add_argument(f"--{name}", metavar="DIM", help=f"dimension for {what}")
    pl.add_argument("--sel", action="append", metavar="DIM=VALUE",
                    help="fix a dimension at a grid value (SI units, a quantity with units, or "
                    "a name), e.g. --sel d_i=500e-6 --sel \"d_i=500 um\" --sel solid_j=ilmenite; "
                    "repeatable")
    pl.set_defaults(func=_cmd_plot)

    cm = sub.add_parser("compare", help="which option sticks less, under the uncertain "
                        "inputs: decided, or not? (TOML)")
    cm.add_argument("config", help="TOML file with [scene], [compare], [uncertain], [options]")
    cm.add_argument("-n", type=int, default=None, metavar="N",
                    help="paired draws per option (default: the file's [options] n, else "
                         "4096)")
    cm.add_argument("-o", "--output", help="also write the comparison as netCDF")
    cm.set_defaults(func=_cmd_compare)

    co = sub.add_parser("collide", help="one collision of a scene, as a readable report",
                        description="One collision of a scene: properties, outcome, u0*. "
                        "Numbers in SI units (T in K, lengths in m).")
    if command == "collide":
        _add_scene_options(co)
    co.set_defaults(func=_cmd_collide)

    be = sub.add_parser("bed", help="propensity of a bed of mixed solids and sizes (TOML)",
                        description="Bed-level agglomeration propensity of the [scene] and "
                        "[[component]] tables of a TOML file, over its optional [grid].")
    be.add_argument("config", help="TOML file with [scene], [[component]], [grid], [options]")
    be.add_argument("-o", "--output", required=True, help="netCDF file to write")
    be.add_argument("--efficiency", metavar="FILE",
                    help="also write the coalescence-efficiency matrix (.csv or .nc); for a "
                    "file without [grid] (one operating point)")
    _add_progress_options(be)
    be.set_defaults(func=_cmd_bed)

    ma = sub.add_parser("materials", help="what the materials database holds, with sources")
    ma.set_defaults(func=_cmd_materials)
    return parser


@contextlib.contextmanager
def _threads(n: int | None):
    """Run with ``n`` threads in the compiled kernels (None: as they are), restored after."""
    if n is None:
        yield
        return
    import numba

    most = numba.config.NUMBA_NUM_THREADS
    if not 1 <= n <= most:
        raise CommandError(f"--threads {n}: this process can use 1 to {most} threads (the "
                           "cores Numba found; the environment variable NUMBA_NUM_THREADS "
                           "sets that ceiling)")
    before = numba.get_num_threads()
    numba.set_num_threads(n)
    try:
        yield
    finally:
        numba.set_num_threads(before)


def _dashes(arg: str) -> str:
    """An option typed with the field's own name (``--d_i``, ``--U_Umf=2``) as the command
    line spells it (``--d-i``); values are left as they are."""
    if not arg.startswith("--"):
        return arg
    name, eq, value = arg.partition("=")
    return name.replace("_", "-") + eq + value


@contextlib.contextmanager
def _interrupts():
    """The interrupts (SIGINT, Ctrl-C) received while a command runs, as a list that is
    empty until one comes. Numba's compiler, for one, catches the KeyboardInterrupt raised
    inside it and fails with an error of its own ('no compiled object yet'): the command
    then knows it was interrupted. The KeyboardInterrupt that such a library reports as
    ignored is not printed; other such reports are, as before."""
    import signal
    import threading

    received: list[int] = []
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield received  # a caller's own handler, or not the main thread: left alone
        return

    def on_interrupt(signum, frame):
        received.append(signum)
        raise KeyboardInterrupt

    def unraisable(report, before=sys.unraisablehook):
        if not (received and isinstance(report.exc_value, KeyboardInterrupt)):
            before(report)

    hook = sys.unraisablehook
    signal.signal(signal.SIGINT, on_interrupt)
    sys.unraisablehook = unraisable
    try:
        yield received
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        sys.unraisablehook = hook


def main(argv: list[str] | None = None) -> int:
    argv = [_dashes(a) for a in (sys.argv[1:] if argv is None else argv)]
    command = next((a for a in argv if not a.startswith("-")), None)
    try:
        args = build_parser(command).parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error argparse reported
        return int(exc.code or 0)
    args._argv = argv  # for the history of the files a command writes
    import warnings

    from .plausibility import PlausibilityWarning

    said: set[str] = set()

    def show(message, category, *rest, **kw):  # one readable line, not file:line: source
        if str(message) not in said:  # once, though several steps may find it
            said.add(str(message))
            print(f"agglomtool: warning: {message}", file=sys.stderr)

    try:
        with warnings.catch_warnings(), _threads(args.threads), _interrupts() as interrupted:
            warnings.showwarning = show
            warnings.simplefilter("error" if args.strict else "default", PlausibilityWarning)
            try:
                return args.func(args)
            except Exception:
                if interrupted:  # an interrupt a library turned into an error of its own
                    raise KeyboardInterrupt from None
                raise
    except PlausibilityWarning as exc:
        print(f"agglomtool: error (--strict): {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        store = getattr(args, "_store", None)
        hint = (f"; finished blocks are kept in {store}: run the same command again to resume"
                if store is not None else "")
        print(f"\nagglomtool: interrupted{hint}", file=sys.stderr)  # after a progress line
        return EXIT_INTERRUPTED
    except ImportError as exc:  # an optional package is missing: say which and how
        print(f"agglomtool: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except (CommandError, ValueError, TypeError, KeyError, OSError) as exc:  # bad input
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        if hasattr(exc, "for_cli"):  # the way out in the command line's terms (--overwrite)
            msg = exc.for_cli()
        print(f"agglomtool: error: {msg}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
