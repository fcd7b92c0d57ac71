"""Command line: ``agglomtool COMMAND``. Each command is one call of the Python API."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from . import __version__
from .examples import reference_cases


def _cmd_reference(args: argparse.Namespace) -> int:
    """Evaluate the paper's two reference cases (Table 2) and print u0* and e_w."""
    for case in reference_cases():
        print(case.report(beta_deg=args.beta, mode=args.mode))
        print()
    return 0


def _cmd_map(args: argparse.Namespace) -> int:
    """Sweep the scene and grid of a TOML file; write the map as netCDF."""
    import shutil
    from pathlib import Path

    from .maps.config import load_config
    from .maps.grid import sweep

    cfg = load_config(args.config)
    out = Path(args.output)
    store = Path(args.store) if args.store else out.with_name(out.name + ".parts")
    ds = sweep(cfg.scene, chunks=cfg.options["chunks"], nodes=cfg.options["nodes"],
               store=store, progress=not args.quiet, **cfg.grid)
    tmp = out.with_name(out.name + ".tmp")
    ds.to_netcdf(tmp)
    ds.close()
    tmp.replace(out)
    if not args.keep_parts:
        shutil.rmtree(store)
    sizes = " x ".join(f"{k} {v}" for k, v in ds.sizes.items())
    print(f"wrote {out} ({sizes})")
    return 0


def _cmd_plot(args: argparse.Namespace) -> int:
    """Draw the operating window of a map file."""
    from .plots import operating_window

    operating_window(args.map, var=args.var, path=args.output)
    print(f"wrote {args.output}")
    return 0


def _scene_from_args(args: argparse.Namespace):
    from .scene import Scene, field_names

    given = {}
    for name in field_names():
        value = getattr(args, f"scene_{name}", None)
        if value is not None:
            given[name] = value
    if "body_forces" in given:
        given["body_forces"] = given["body_forces"] == "on"
    return Scene(**given)


def _cmd_collide(args: argparse.Namespace) -> int:
    """One collision of a scene, as a readable report."""
    from .scene import Resolved, capillary_number

    scene = _scene_from_args(args)
    r = Resolved(scene.values())
    u0 = float(r.u_typical)
    res = r.collide(u0, details=True)
    us = float(r.u_star)
    ca = float(capillary_number(r.liquid.mu, r.liquid.gamma, us))
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
        f"critical impact speed u0* = {us:.4g} m/s (margin u0/u0* = "
        f"{u0 / us if us > 0 else float('inf'):.3g})",
        f"capillary number at u0*: Ca = {ca:.3g} -> "
        + ("viscous-limited" if ca > 1.0 else "capillary-limited"),
    ]
    print("\n".join(lines))
    return 0


def _cmd_materials(args: argparse.Namespace) -> int:
    """What the materials database holds, with sources."""
    from . import materials

    for kind in materials.KINDS:
        print(f"{kind}s:")
        for name in materials.names(kind):
            entry = getattr(materials, "liquid_entry" if kind == "liquid" else kind)(name)
            extra = f" [{entry.model}]" if kind == "liquid" else ""
            print(f"  {name}{extra}")
            print("    source: " + " ".join(entry.source.split()))
            print("    confidence: " + " ".join(entry.confidence.split()))
        print()
    return 0


def _add_scene_options(p: argparse.ArgumentParser) -> None:
    from .scene import CATEGORICAL_FIELDS, FIELD_META, Scene, field_names

    defaults = Scene(u0=0.5).values()
    for name in field_names():
        if name == "body_forces":
            p.add_argument("--body-forces", dest="scene_body_forces", choices=["on", "off"])
            continue
        flag = "--" + name.replace("_", "-")
        if name in CATEGORICAL_FIELDS:
            p.add_argument(flag, dest=f"scene_{name}", type=str,
                           help=f"(default {defaults[name]})")
        else:
            unit, long_name = FIELD_META[name]
            p.add_argument(flag, dest=f"scene_{name}", type=float,
                           help=f"{long_name} [{unit}] (default {defaults[name]})")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="agglomtool",
        description="Will wet or ash-coated particles in a fluidized bed stick together?",
    )
    parser.add_argument("--version", action="version", version=f"agglomtool {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    ref = sub.add_parser(
        "reference",
        help="the paper's reference cases (water, slag): critical impact speed and e_w",
    )
    ref.add_argument("--beta", type=float, nargs="+", default=[0.0, 45.0, 90.0],
                     help="collision angles [deg] (default: 0 45 90)")
    ref.add_argument("--mode", default="paper", help="model tier (default: paper)")
    ref.set_defaults(func=_cmd_reference)

    mp = sub.add_parser("map", help="sweep a scene over a grid (TOML) into a netCDF map")
    mp.add_argument("config", help="TOML file with [scene], [grid] and [options]")
    mp.add_argument("-o", "--output", required=True, help="netCDF file to write")
    mp.add_argument("--store", help="directory of finished blocks (default OUTPUT.parts); "
                    "an interrupted map run again resumes from it")
    mp.add_argument("--keep-parts", action="store_true", help="keep the block directory")
    mp.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    mp.set_defaults(func=_cmd_map)

    pl = sub.add_parser("plot", help="operating-window picture of a map")
    pl.add_argument("map", help="netCDF map written by 'agglomtool map'")
    pl.add_argument("-o", "--output", required=True, help="PNG file to write")
    pl.add_argument("--var", default="propensity", help="variable to colour "
                    "(default propensity)")
    pl.set_defaults(func=_cmd_plot)

    co = sub.add_parser("collide", help="one collision of a scene, as a readable report")
    _add_scene_options(co)
    co.set_defaults(func=_cmd_collide)

    ma = sub.add_parser("materials", help="what the materials database holds, with sources")
    ma.set_defaults(func=_cmd_materials)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, KeyError) as exc:  # bad input: say what, not a traceback
        print(f"agglomtool: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    np.set_printoptions(precision=4)
    sys.exit(main())
