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
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except ValueError as exc:  # bad input: say what, not a traceback
        print(f"agglomtool: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    np.set_printoptions(precision=4)
    sys.exit(main())
