"""The package's import graph keeps its layers: no import cycle, a self-contained collision
core, and every import pointing down the layers listed on the maintainers' page.

Every module of ``agglomtool`` is parsed with :mod:`ast`, and every import statement is an
edge: at the top of a module or inside a function (an import deferred to first use is still
an import, so a cycle hidden in a function is still a cycle), relative or absolute, and
``importlib.import_module`` with a name the parser can read. ``from package import name``
is an edge to the submodule ``name`` where there is one; a name a package serves from its
``_LAZY`` table (PEP 562) is an edge to the module the table names. Importing a module also
runs the ``__init__`` of each package above it that the importer is not itself inside, so
those are edges too.

The layers are the table of ``docs/maintainers.md`` ("The layering"), read from the page:
the page and this test cannot drift apart. A module may import modules of its own row, and
of any row of a lower layer; rows of one layer are siblings that do not import each other.
"""

from __future__ import annotations

import ast
import re
from collections import defaultdict
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "agglomtool"
MAINTAINERS = ROOT / "docs" / "maintainers.md"

#: What the collision core may import from the rest of the package: the bottom modules.
CORE = "agglomtool.collision"
CORE_MAY_IMPORT = {"agglomtool.constants", "agglomtool._jit"}


# --- the modules and their imports -----------------------------------------------------------


def module_files(package: Path = PACKAGE) -> dict[str, Path]:
    """``{dotted module name: file}`` of every module of the package (packages by their
    ``__init__``)."""
    out = {}
    for path in sorted(package.rglob("*.py")):
        parts = list(path.relative_to(package.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _is_package(name: str, files: dict[str, Path]) -> bool:
    return files[name].name == "__init__.py"


def _lazy_table(name: str, files: dict[str, Path]) -> dict[str, str]:
    """The ``_LAZY`` table of package ``name``: public name -> the module that defines it."""
    if name not in files or not _is_package(name, files):
        return {}
    for node in ast.parse(files[name].read_text()).body:
        if (isinstance(node, ast.Assign) and len(node.targets) == 1
                and isinstance(node.targets[0], ast.Name) and node.targets[0].id == "_LAZY"
                and isinstance(node.value, ast.Dict)):
            table = {}
            for key, value in zip(node.value.keys, node.value.values, strict=True):
                if isinstance(key, ast.Constant) and isinstance(value, ast.Constant):
                    table[key.value] = f"{name}.{value.value.lstrip('.')}"
            return table
    return {}


def _resolve_relative(importer: str, files: dict[str, Path], level: int, module: str | None
                      ) -> str:
    base = importer.split(".")
    if not _is_package(importer, files):
        base = base[:-1]
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([module] if module else []))


def _literal_name(node: ast.expr, importer: str) -> str | None:
    """The string ``node`` stands for: a constant, or an f-string of constants and
    ``__name__`` (the importer's name)."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.JoinedStr):
        parts = []
        for value in node.values:
            if isinstance(value, ast.Constant):
                parts.append(str(value.value))
            elif (isinstance(value, ast.FormattedValue) and isinstance(value.value, ast.Name)
                  and value.value.id == "__name__"):
                parts.append(importer)
            else:
                return None
        return "".join(parts)
    return None


def _targets(importer: str, node: ast.AST, files: dict[str, Path]) -> list[str]:
    """The modules one import statement (or ``import_module`` call) names."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if isinstance(node, ast.ImportFrom):
        base = (_resolve_relative(importer, files, node.level, node.module) if node.level
                else node.module)
        lazy = _lazy_table(base, files)
        out = []
        for alias in node.names:
            sub = f"{base}.{alias.name}"
            out.append(sub if sub in files else lazy.get(alias.name, base))
        return out
    if (isinstance(node, ast.Call) and node.args
            and ((isinstance(node.func, ast.Name) and node.func.id == "import_module")
                 or (isinstance(node.func, ast.Attribute) and node.func.attr == "import_module"))):
        name = _literal_name(node.args[0], importer)
        if name is None:
            return []  # a name known only at run time (a _LAZY look-up): read from the table
        if name.startswith("."):
            level = len(name) - len(name.lstrip("."))
            return [_resolve_relative(importer, files, level, name.lstrip(".") or None)]
        return [name]
    return []


def _with_parents(target: str, importer: str, files: dict[str, Path]) -> list[str]:
    """``target`` and the packages above it whose ``__init__`` importing it runs (those the
    importer is not itself inside: they ran before it)."""
    parts = target.split(".")
    out = [target]
    for k in range(1, len(parts)):
        parent = ".".join(parts[:k])
        if parent in files and not (importer == parent or importer.startswith(parent + ".")):
            out.append(parent)
    return out


def import_graph(package: Path = PACKAGE) -> dict[str, dict[str, int]]:
    """``{module: {imported module of the package: first line}}``."""
    files = module_files(package)
    root = package.name
    graph: dict[str, dict[str, int]] = {}
    for name, path in files.items():
        edges: dict[str, int] = {}
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            for target in _targets(name, node, files):
                if target != root and not target.startswith(root + "."):
                    continue
                if target not in files:
                    raise AssertionError(f"{path}:{node.lineno} imports {target}, which is "
                                         "not a module of the package")
                for t in _with_parents(target, name, files):
                    if t != name:
                        edges[t] = min(edges.get(t, node.lineno), node.lineno)
        graph[name] = edges
    return graph


def find_cycles(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """One cycle ``[a, b, ..., a]`` through every strongly connected set of modules (Tarjan)."""
    index, low, stack, on_stack, sccs = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, {})):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            scc = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                scc.append(w)
                if w == v:
                    break
            if len(scc) > 1 or v in graph.get(v, {}):
                sccs.append(set(scc))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    cycles = []
    for scc in sccs:  # a shortest way back to the first module, inside the set
        start = min(scc)
        prev, queue = {start: None}, [start]
        while queue:
            v = queue.pop(0)
            nxt = [w for w in sorted(graph[v]) if w in scc]
            if start in nxt:
                path = [v]
                while prev[path[-1]] is not None:
                    path.append(prev[path[-1]])
                cycles.append([*reversed(path), start])
                break
            for w in nxt:
                if w not in prev:
                    prev[w] = v
                    queue.append(w)
    return cycles


def _describe(path: list[str], graph) -> str:
    """``a:12 -> b:30 -> a``: each module with the line of its import of the next."""
    return " -> ".join(f"{a}:{graph[a][b]}" for a, b in zip(path, path[1:], strict=False)
                       ) + f" -> {path[-1]}"


# --- the layers, from the maintainers' page ---------------------------------------------------


def documented_layers(page: Path = MAINTAINERS) -> list[tuple[int, tuple[str, ...]]]:
    """``[(layer, (path, ...)), ...]``: the rows of the layering table of the page, each a
    layer number and the repository paths (in backquotes) of its modules and folders."""
    text = page.read_text()
    section = text.split("## The layering", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        if m := re.match(r"\|\s*(\d+)\s*\|([^|]*)\|", line):
            paths = tuple(re.findall(r"`(agglomtool/[^`]*)`", m[2]))
            rows.append((int(m[1]), paths))
    return rows


def _module_of(path: str) -> tuple[str, bool]:
    """A table path as ``(dotted name, is a folder)``."""
    if path.endswith("/"):
        return path.rstrip("/").replace("/", "."), True
    name = path.removesuffix(".py").replace("/", ".")
    return name.removesuffix(".__init__"), False


def layer_of(module: str, rows) -> tuple[int, int] | None:
    """``(layer, row)`` of ``module``: the row naming its file, else the row of the deepest
    folder holding it; None where no row places it."""
    best = None
    for k, (layer, paths) in enumerate(rows):
        for path in paths:
            name, folder = _module_of(path)
            if not folder and module == name:
                return layer, k
            if folder and (module == name or module.startswith(name + ".")):
                depth = name.count(".")
                if best is None or depth > best[0]:
                    best = (depth, (layer, k))
    return best[1] if best else None


# --- the tests --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def graph():
    return import_graph()


@pytest.fixture(scope="module")
def rows():
    return documented_layers()


def test_the_parser_sees_every_kind_of_import(tmp_path):
    """The graph holds top-level, function-level, relative, absolute, ``import_module`` and
    ``_LAZY`` imports, and the ``__init__`` of a package entered from outside it; and a cycle
    hidden in a function is found."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text(
        "from importlib import import_module\n_LAZY = {'thing': '.deep'}\n"
        "def __getattr__(name):\n    return import_module(f'{__name__}.other')\n")
    (pkg / "sub" / "deep.py").write_text("thing = 1\n")
    (pkg / "sub" / "other.py").write_text("import pkg.low\n")
    (pkg / "low.py").write_text("def f():\n    from .high import g\n")
    (pkg / "high.py").write_text("from .sub import thing\nfrom . import low\n")
    g = import_graph(pkg)
    assert g["pkg.high"] == {"pkg.sub.deep": 1, "pkg.sub": 1, "pkg.low": 2}
    assert g["pkg.low"] == {"pkg.high": 2}
    assert g["pkg.sub"] == {"pkg.sub.other": 4}
    assert g["pkg.sub.other"] == {"pkg.low": 1}
    assert find_cycles(g) == [["pkg.high", "pkg.low", "pkg.high"]]


def test_no_import_cycles(graph):
    cycles = find_cycles(graph)
    assert not cycles, "import cycles:\n" + "\n".join(_describe(c, graph) for c in cycles)


def test_collision_core_imports_only_itself_and_the_bottom_modules(graph):
    bad = [f"{m} imports {t} (line {line})"
           for m, edges in sorted(graph.items()) if m == CORE or m.startswith(CORE + ".")
           for t, line in sorted(edges.items())
           if not (t == CORE or t.startswith(CORE + ".") or t in CORE_MAY_IMPORT)]
    assert not bad, "the collision core reaches outside itself:\n" + "\n".join(bad)


def test_the_page_places_every_module_once(graph, rows):
    assert rows, f"no layering table found in {MAINTAINERS}"
    for _, paths in rows:
        for path in paths:
            assert (ROOT / path).exists(), f"{MAINTAINERS.name} names {path}, which is missing"
    unplaced = [m for m in sorted(graph) if layer_of(m, rows) is None]
    assert not unplaced, (f"modules in no row of the layering table of {MAINTAINERS.name} "
                          f"(add them): {unplaced}")


def test_imports_point_down_the_layers(graph, rows):
    bad = []
    for module, edges in sorted(graph.items()):
        if layer_of(module, rows) is None:
            continue  # test_the_page_places_every_module_once names it
        layer, row = layer_of(module, rows)
        for target, line in sorted(edges.items()):
            if layer_of(target, rows) is None:
                continue
            t_layer, t_row = layer_of(target, rows)
            if t_layer > layer or (t_layer == layer and t_row != row):
                bad.append(f"{module} (layer {layer}) imports {target} (layer {t_layer}, "
                           f"{'above' if t_layer > layer else 'a sibling'}) at line {line}")
    assert not bad, "imports against the layering:\n" + "\n".join(bad)


def test_every_row_places_a_module(graph, rows):
    """The table holds no stale row: every row places at least one module."""
    used = defaultdict(int)
    for module in graph:
        if (placed := layer_of(module, rows)) is not None:
            used[placed[1]] += 1
    empty = [rows[k][1] for k in range(len(rows)) if not used[k]]
    assert not empty, f"rows of the layering table that place no module: {empty}"
