"""Sphinx configuration of agglomtool's documentation.

Build (from the repository's root, after ``pip install -e ".[docs]"``)::

    python3 -m sphinx -W --keep-going -b html docs docs/_build/html

The build works offline: no intersphinx inventories are fetched and the theme loads
nothing from the network. The package is imported from this checkout.
"""

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))  # agglomtool from this checkout, not an installed copy
sys.path.insert(0, str(DOCS / "_ext"))

import agglomtool  # noqa: E402

project = "agglomtool"
author = "the agglomtool developers"
copyright = "2024-2026, the agglomtool developers"  # noqa: A001 - Sphinx's name
release = agglomtool.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.graphviz",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "agglomtool_docs",  # docs/_ext: CLI help at build time, alias references, gallery order
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "_generated", "auto_examples/*.ipynb",
                    "auto_examples/*.py", "auto_examples/*.zip", "**/*.md5",
                    "sg_execution_times.rst"]
templates_path = ["_templates"]

# Every cross-reference must resolve (a missing target is a warning, -W an error).
nitpicky = True
# Third-party types named in signatures and docstrings: without intersphinx (the build is
# offline) there is nothing to link them to. Only these names are exempt.
nitpick_ignore_regex = [
    ("py:.*", r"(numpy|np|xarray|xr|pandas|matplotlib|pint|dask|zarr|pathlib|os|SALib"
              r"|scipy|distributed|argparse|collections|typing|tomllib|filelock)(\..*)?"),
]

# --- autodoc, autosummary, numpydoc ------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_typehints = "none"          # the numpydoc sections state types and units
autodoc_member_order = "bysource"
autodoc_default_options = {"exclude-members": "__init__, __new__, __weakref__"}
numpydoc_show_class_members = False  # the class template lists the members
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()   # formatting is checked by the build itself (-W)
add_module_names = False

# --- MyST (the narrative pages are Markdown) ----------------------------------------------
myst_enable_extensions = ["colon_fence", "deflist", "dollarmath", "amsmath", "fieldlist"]
myst_heading_anchors = 3

# --- graphviz (the model's flow chart) -----------------------------------------------------
graphviz_output_format = "svg"

# --- the gallery --------------------------------------------------------------------------
# The examples run at full size except the Monte Carlo ones, whose sample count is cut to
# 1e5 per run (the paper's 1e6 in a plain run; each example says so and gives the command).
os.environ.setdefault("AGGLOMTOOL_EXAMPLE_SAMPLES", "100000")
os.environ.setdefault("AGGLOMTOOL_EXAMPLE_OUT", str(DOCS / "_build" / "gallery_output"))
os.environ.setdefault("MPLBACKEND", "Agg")

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"^_",  # examples/_output.py is a helper
    "within_subsection_order": "agglomtool_docs.ExampleOrder",
    "image_scrapers": ("agglomtool_docs.tight_scraper",),
    "image_srcset": ["2x"],  # sharp pictures on high-density screens
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_memory": False,
    "show_signature": False,
    "min_reported_time": 1,
    "capture_repr": (),
    "plot_gallery": "True",
    "write_computation_times": False,
    "reference_url": {"agglomtool": None},
}

# --- HTML ---------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"agglomtool {release}"
html_static_path = []
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "navbar_align": "left",
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
    "secondary_sidebar_items": ["page-toc"],
}
html_sidebars = {"index": [], "getting_started": [], "cli": []}
html_show_sourcelink = False
html_copy_source = False

# Internal links are checked on the built site by docs/_ext/check_links.py (in .ci/run);
# should Sphinx's own linkcheck be run, it must not reach out (CI has no web access).
linkcheck_ignore = [r"https?://.*", r"mailto:.*"]
