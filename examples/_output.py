"""Where the examples write their pictures, and how big their grids are.

``AGGLOMTOOL_EXAMPLE_OUT`` overrides the output directory (default ``examples/output``);
``AGGLOMTOOL_EXAMPLE_N`` overrides the number of points per grid axis (the smoke tests use
a few points).
"""

import os
from pathlib import Path


def output_dir() -> Path:
    out = Path(os.environ.get("AGGLOMTOOL_EXAMPLE_OUT", Path(__file__).parent / "output"))
    out.mkdir(parents=True, exist_ok=True)
    return out


def points(default: int) -> int:
    return int(os.environ.get("AGGLOMTOOL_EXAMPLE_N", default))
