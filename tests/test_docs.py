"""The documentation's promises: the getting-started page's Python code runs, and the API
reference lists every public name (the Sphinx build itself runs in .ci/run)."""

import importlib
import re
from pathlib import Path

import numpy as np
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


def _check_collision(ns, out, folder):
    """One collision: what it prints, and u0* is the speed below which the pair sticks."""
    at, r, u_star = ns["at"], ns["r"], float(ns["u_star"])
    assert 0.0 <= float(r.e_w) <= 0.9 and bool(r.agglomerated) == (float(r.e_w) == 0.0)
    assert f"{r.stage_name}" in out and str(r.e_w) in out
    assert r.explain().strip() and r.explain() in out
    pair = {k: ns[k] for k in ("p_i", "p_j")}
    kw = dict(liquid=ns["water"], gas=ns["air"], bed=ns["bed"], beta_deg=90.0, e=0.9)
    below, above = at.collide(**pair, **kw, u0=[0.99 * u_star, 1.01 * u_star]).agglomerated
    assert below and not above
    assert bool(r.agglomerated) == (0.05 < u_star)


def _check_map(ns, out, folder):
    """The scene describes itself, the map has one propensity per partner, and the file and
    the picture the page promises are written (the file holds the map)."""
    import xarray as xr

    scene, ds = ns["scene"], ns["ds"]
    assert scene.describe() in out and "silica-sand" in scene.describe()
    means = ds.propensity.mean(["U_Umf", "h0"]).values
    assert means.shape == (3,) and np.all((means >= 0) & (means <= 1))
    with xr.open_dataset(folder / "sand_vs_ilmenite.nc") as back:
        np.testing.assert_array_equal(back["propensity"].values, ds["propensity"].values)
    assert (folder / "sand_vs_ilmenite.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _check_warning(ns, out, folder):
    """The 5 m coating is a PlausibilityWarning naming the field, printed; the filter that
    stands for --strict makes the next one an error."""
    at = ns["at"]
    assert issubclass(ns["caught"][0].category, at.PlausibilityWarning)
    assert "h0" in str(ns["caught"][0].message) and str(ns["caught"][0].message) in out
    with pytest.raises(at.PlausibilityWarning):
        at.Scene(liquid="water", T=298.15, h0=5.0)


def _check_store(ns, out, folder):
    """The store reads back lazily and exports to one file, both holding the sweep."""
    import xarray as xr

    ds, lazy = ns["ds"], ns["lazy"]
    np.testing.assert_array_equal(lazy["propensity"].values, ds["propensity"].values)
    with xr.open_dataset(folder / "map.nc") as back:
        np.testing.assert_array_equal(back["propensity"].values, ds["propensity"].values)


#: What each Python block of the getting-started page promises, found by a phrase of its
#: code. A block without an entry here fails the test: a new block needs its check.
PROMISES = {"at.collide(": _check_collision, "at.sweep(scene": _check_map,
            "catch_warnings": _check_warning, 'store="map-store"': _check_store}


@pytest.mark.parametrize("index", range(len(python_blocks(DOCS / "getting_started.md"))))
def test_getting_started_code_runs(index, tmp_path, monkeypatch, capsys):
    """Each block runs as printed, and does what the page says it does."""
    import matplotlib  # a test dependency (the [test] extra): its absence is a failure

    matplotlib.use("Agg")
    import warnings

    monkeypatch.chdir(tmp_path)
    code = python_blocks(DOCS / "getting_started.md")[index]
    checks = [check for phrase, check in PROMISES.items() if phrase in code]
    assert len(checks) == 1, f"block {index}: no check (or several) for what it promises"
    namespace = {}
    with warnings.catch_warnings():  # a block may set a filter: keep it inside the test
        exec(compile(code, f"getting_started.md block {index}", "exec"), namespace)
        checks[0](namespace, capsys.readouterr().out, tmp_path)


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
