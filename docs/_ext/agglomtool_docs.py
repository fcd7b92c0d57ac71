"""Build helpers of agglomtool's documentation (a local Sphinx extension).

- The command line's help: ``agglomtool --help`` and every sub-command's ``--help`` are run
  at build time and written to ``docs/_generated/cli/`` for ``docs/cli.md`` to include, so
  the page always shows what the installed command says.
- Aliases: agglomtool re-exports names (``agglomtool.maps.sweep`` is ``agglomtool.sweep``;
  docstrings name ``agglomtool.scene.Scene`` or ``Stage``). The reference documents each
  object once; a cross-reference to any other public spelling of the same object is
  resolved to the documented one. Anything else stays unresolved (and ``nitpicky`` reports
  it).
- The gallery: the order of the examples and a Matplotlib scraper that crops figures like
  the examples' own PNGs (``bbox_inches="tight"``: legends outside the axes are kept).
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from pathlib import Path

from docutils import nodes
from sphinx.util import logging

logger = logging.getLogger(__name__)

#: Sub-commands whose ``--help`` the CLI page shows, in the page's order.
CLI_COMMANDS = ("reference", "map", "plot", "collide", "compare", "bed", "materials")

#: The gallery's order: the paper first, then the designer's questions.
GALLERY_ORDER = (
    "plot_fig6_curves.py",
    "plot_granulator_window.py",
    "plot_material_comparison.py",
    "plot_biomass_window.py",
    "plot_bed_mixtures.py",
    "plot_monte_carlo_table4.py",
    "plot_sobol.py",
)


class ExampleOrder:
    """sphinx-gallery's ``within_subsection_order``: :data:`GALLERY_ORDER`, then by name."""

    def __init__(self, src_dir):
        self.src_dir = src_dir

    def __call__(self, filename: str):
        name = Path(filename).name
        return (GALLERY_ORDER.index(name) if name in GALLERY_ORDER else len(GALLERY_ORDER),
                name)


def tight_scraper(block, block_vars, gallery_conf, **kwargs):
    """sphinx-gallery's Matplotlib scraper, cropping like the examples' own ``savefig``."""
    from sphinx_gallery.scrapers import matplotlib_scraper

    return matplotlib_scraper(block, block_vars, gallery_conf, bbox_inches="tight", **kwargs)


def write_cli_help(app) -> None:
    """Run ``agglomtool [command] --help`` and keep the texts for ``docs/cli.md``."""
    out = Path(app.srcdir) / "_generated" / "cli"
    out.mkdir(parents=True, exist_ok=True)
    root = Path(app.srcdir).parent
    env = {**os.environ, "COLUMNS": "92",
           "PYTHONPATH": os.pathsep.join(filter(None, [str(root),
                                                        os.environ.get("PYTHONPATH")]))}
    for command in ("", *CLI_COMMANDS):
        args = [sys.executable, "-m", "agglomtool", *([command] if command else []), "--help"]
        run = subprocess.run(args, capture_output=True, text=True, env=env, cwd=root,
                             timeout=300, check=False)
        if run.returncode != 0:
            raise RuntimeError(f"{' '.join(args[2:])} failed: {run.stderr}")
        text = "$ " + " ".join(["agglomtool", *args[3:]]) + "\n" + run.stdout
        path = out / f"{command or 'agglomtool'}.txt"
        if not path.exists() or path.read_text() != text:  # unchanged: no rebuild
            path.write_text(text)


def _lookup(name: str):
    """The object a dotted name denotes, or None. Attributes win over submodules of the
    same name (``agglomtool.uncertainty.monte_carlo`` is the function, not its module)."""
    parts = name.split(".")
    try:
        obj = importlib.import_module(parts[0])
    except Exception:  # noqa: BLE001 - not an importable name
        return None
    for i, attr in enumerate(parts[1:], start=1):
        if hasattr(obj, attr):
            obj = getattr(obj, attr)
            continue
        try:
            obj = importlib.import_module(".".join(parts[: i + 1]))
        except Exception:  # noqa: BLE001 - neither an attribute nor a submodule
            return None
    return obj


#: Values Python may share between unrelated names: never matched by identity.
_SHARED = (int, float, complex, str, bytes, bool, type(None))


def _documented(env) -> dict[int, str]:
    """id(object) -> documented full name (values that Python may share excepted)."""
    cache = getattr(env, "_agglomtool_documented", None)
    domain = env.get_domain("py")
    if cache is None or cache[0] != len(domain.objects):
        found = {}
        for name, entry in sorted(domain.objects.items()):
            if entry.aliased:
                continue
            obj = _lookup(name)
            if obj is not None and not isinstance(obj, _SHARED):
                found.setdefault(id(obj), name)
        cache = (len(domain.objects), found)
        env._agglomtool_documented = cache
    return cache[1]


def resolve_alias(app, env, node, contnode):
    """``missing-reference``: a Python reference to another public name of a documented
    object (or a name relative to the documented object's own module) goes to it."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    module, cls = node.get("py:module"), node.get("py:class")
    candidates = [target]
    if module:
        if cls:
            candidates.append(f"{module}.{cls}.{target}")
        candidates.append(f"{module}.{target}")
    # A docstring names its neighbours without a prefix: try the modules that define the
    # object the reference sits in (its page, its class, its module) and their packages.
    owners = [f"{module}.{cls}" if cls else module]
    if "/generated/" in node["refdoc"]:
        owners.append(node["refdoc"].rsplit("/", 1)[1])
    for owner in filter(None, owners):
        home = getattr(_lookup(owner), "__module__", None)
        while home and home.count("."):
            candidates.append(f"{home}.{target}")
            home = home.rpartition(".")[0]
    documented = _documented(env)
    domain = env.get_domain("py")
    for cand in candidates:
        obj = _lookup(cand)
        if obj is None:
            continue
        name = None if isinstance(obj, _SHARED) else documented.get(id(obj))
        if name is None and cand in domain.objects:
            name = cand
        if name is None:
            continue
        return _reference(app, node, contnode, domain, name)
    # Last: a bare name (a summary line out of its module's context) that exactly one
    # documented object carries.
    if "." not in target:
        ends = [n for n in domain.objects if n.endswith("." + target)
                and not domain.objects[n].aliased]
        if len(ends) == 1:
            return _reference(app, node, contnode, domain, ends[0])
    return None


def _reference(app, node, contnode, domain, name):
    entry = domain.objects[name]
    ref = nodes.reference("", "", internal=True, reftitle=name,
                          refuri=app.builder.get_relative_uri(node["refdoc"], entry.docname)
                          + "#" + entry.node_id)
    ref += contnode
    return ref


def setup(app):
    app.connect("builder-inited", write_cli_help)
    app.connect("missing-reference", resolve_alias, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
