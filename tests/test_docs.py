"""The documentation's promises: the getting-started page's Python code runs, and the API
reference lists every public name (the Sphinx build itself runs in .ci/run)."""

import importlib
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parent.parent / "docs"

#: Modules whose ``__all__`` is public API (the top level's lazy names included).
PUBLIC_MODULES = (
    "agglomtool", "agglomtool.scene", "agglomtool.collision", "agglomtool.maps",
    "agglomtool.maps.store", "agglomtool.maps.config", "agglomtool.maps.export",
    "agglomtool.bed", "agglomtool.bed.mixture", "agglomtool.bed.propensity",
    "agglomtool.bed.export", "agglomtool.bed.config", "agglomtool.uncertainty",
    "agglomtool.properties", "agglomtool.materials", "agglomtool.units",
    "agglomtool.plausibility", "agglomtool.plots", "agglomtool.examples",
)
#: Documented in prose on the top-level page rather than by autosummary.
IN_PROSE = {"agglomtool.__version__"}


def python_blocks(path):
    return re.findall(r"^```python\n(.*?)^```", path.read_text(), flags=re.S | re.M)


@pytest.mark.parametrize("index", range(len(python_blocks(DOCS / "getting_started.md"))))
def test_getting_started_code_runs(index, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import warnings

    monkeypatch.chdir(tmp_path)
    code = python_blocks(DOCS / "getting_started.md")[index]
    with warnings.catch_warnings():  # a block may set a filter: keep it inside the test
        exec(compile(code, f"getting_started.md block {index}", "exec"), {})


def documented_names():
    """Full names listed in the autosummary tables of docs/api/*.rst."""
    names = set()
    for rst in (DOCS / "api").glob("*.rst"):
        module = None
        in_table = False
        for line in rst.read_text().splitlines():
            if m := re.match(r"\.\. currentmodule:: (\S+)", line):
                module = m[1]
            elif line.startswith(".. autosummary::"):
                in_table = True
            elif in_table and (m := re.match(r"   (~?)([\w.]+)$", line)):
                name = m[2]
                names.add(name if "." in name and name.startswith("agglomtool")
                          else f"{module}.{name}")
            elif in_table and line and not line.startswith(" "):
                in_table = False
    return names


def _get(full):
    module, _, attr = full.rpartition(".")
    return getattr(importlib.import_module(module), attr)


def test_api_reference_lists_every_public_name():
    documented = documented_names()
    by_id = {id(_get(n)): n for n in documented
             if not isinstance(_get(n), (int, float, str, bool))}
    missing = []
    for module in PUBLIC_MODULES:
        mod = importlib.import_module(module)
        for name in mod.__all__:
            full = f"{module}.{name}"
            obj = getattr(mod, name)
            if full in documented or full in IN_PROSE or isinstance(obj, type(mod)):
                continue  # submodules have pages of their own (checked through __all__)
            if not isinstance(obj, (int, float, str, bool)) and id(obj) in by_id:
                continue  # a re-export of a documented object
            missing.append(full)
    assert not missing, f"public names missing from docs/api: {missing}"
    for name in documented:  # and nothing listed there is stale
        _get(name)


def test_link_checker_finds_broken_files_and_anchors(tmp_path):
    import sys

    sys.path.insert(0, str(DOCS / "_ext"))
    try:
        from check_links import broken_links
    finally:
        sys.path.remove(str(DOCS / "_ext"))
    (tmp_path / "sub").mkdir()
    (tmp_path / "index.html").write_text(
        '<a href="sub/page.html#here">ok</a> <a href="sub/page.html#gone">bad anchor</a>'
        '<a href="missing.html">bad file</a> <a href="https://example.org/x">other site</a>'
        '<img src="sub/pic.png"> <a href="#top" id="top">self</a>')
    (tmp_path / "sub" / "page.html").write_text('<h1 id="here">x</h1><a href="../index.html">')
    (tmp_path / "sub" / "pic.png").write_bytes(b"png")
    assert broken_links(tmp_path) == ["index.html: sub/page.html#gone (no such anchor)",
                                      "index.html: missing.html (no such file)"]
