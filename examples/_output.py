"""Where the examples write their pictures, and how big their grids and samples are.

Environment variables (all optional; without them every example runs at full size):

``AGGLOMTOOL_EXAMPLE_OUT``
    Output directory (default ``examples/output``).
``AGGLOMTOOL_EXAMPLE_N``
    Points per grid axis (the smoke tests use a few points).
``AGGLOMTOOL_EXAMPLE_SAMPLES``
    Monte Carlo samples per run (the documentation's gallery uses fewer than the paper's
    1e6; the smoke tests a few thousand).
"""

import os
from pathlib import Path


def output_dir() -> Path:
    out = Path(os.environ.get("AGGLOMTOOL_EXAMPLE_OUT", Path(__file__).parent / "output"))
    out.mkdir(parents=True, exist_ok=True)
    return out


def points(default: int) -> int:
    """Points per grid axis: ``default``, or ``AGGLOMTOOL_EXAMPLE_N`` when set."""
    return int(os.environ.get("AGGLOMTOOL_EXAMPLE_N", default))


def samples(default: int) -> int:
    """Monte Carlo samples: ``default``, or ``AGGLOMTOOL_EXAMPLE_SAMPLES`` when set."""
    return int(os.environ.get("AGGLOMTOOL_EXAMPLE_SAMPLES", default))


def save(fig, name: str, dpi: int = 120) -> Path:
    """Write ``fig`` as ``<output>/<name>.png`` and say where."""
    path = output_dir() / f"{name}.png"
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    print(f"picture: {os.path.relpath(path)}")
    return path


def map_from_config(name: str):
    """The map of ``configs/<name>.toml``, written to ``<output>/<name>.nc``.

    With ``AGGLOMTOOL_EXAMPLE_N`` set, every numeric axis longer than that is resampled to
    that many points between its ends (evenly, or evenly in log where the config's axis is
    geometric), so that the smoke tests run the same example on a small grid.
    """
    import numpy as np

    from agglomtool.maps import sweep, write_map
    from agglomtool.maps.config import load_config

    cfg = load_config(Path(__file__).parent / "configs" / f"{name}.toml")
    grid = dict(cfg.grid)
    for key, axis in grid.items():
        if isinstance(axis, np.ndarray) and axis.size > 2:
            n = points(axis.size)
            geometric = np.all(axis > 0) and np.allclose(np.diff(np.log(axis)),
                                                         np.log(axis[1] / axis[0]))
            grid[key] = (np.geomspace if geometric else np.linspace)(axis[0], axis[-1], n)
    ds = sweep(cfg.scene, nodes=cfg.options["nodes"], **grid)
    write_map(ds, output_dir() / f"{name}.nc")
    print("grid: " + ", ".join(f"{k} {np.size(v)}" for k, v in grid.items())
          + f" ({int(np.prod([np.size(v) for v in grid.values()]))} points)")
    return ds
