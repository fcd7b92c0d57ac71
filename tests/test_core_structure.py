"""The collision core's functions take named records, not long positional lists.

Every function of ``agglomtool/collision/`` (nested ones and ``@overload`` implementations
included) is read with :mod:`ast`; its positional parameters are those that can be passed
by position (``posonlyargs`` and ``args``, with or without a default; ``*args`` and
keyword-only parameters are not counted). More than :data:`LIMIT` of them is a function
that should take a record of :mod:`agglomtool.collision.records` (or of its own module)
instead. No file of the core holds one.
"""

from __future__ import annotations

import ast
from pathlib import Path

CORE = Path(__file__).resolve().parent.parent / "agglomtool" / "collision"

#: Most positional parameters a function of the core may take.
LIMIT = 8

#: Python-level entry points whose flags must be keyword-only (the tier functions and
#: their batch variants): a bare ``False`` in a call says nothing.
TIER_FILES = ("auto.py", "ode.py", "paper.py", "relative.py", "stokes.py", "tiers.py")


def _functions(path: Path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node


def _positional(node) -> int:
    return len(node.args.posonlyargs) + len(node.args.args)


def over_limit(path: Path) -> list[tuple[str, int]]:
    """``(name, positional parameters)`` of each function of ``path`` over the limit."""
    return [(f.name, _positional(f)) for f in _functions(path) if _positional(f) > LIMIT]


def _compiled(node) -> bool:
    """Decorated with ``njit`` / ``overload`` (Numba takes no keyword-only parameters)."""
    for dec in node.decorator_list:
        target = dec.func if isinstance(dec, ast.Call) else dec
        name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
        if name in ("njit", "jit", "overload", "generated_jit"):
            return True
    return False


def test_the_counter_counts_positional_parameters(tmp_path):
    """The counter sees a long list, nested functions included, and ignores what cannot be
    passed by position."""
    src = tmp_path / "m.py"
    src.write_text(
        "def a(p1, p2, p3, p4, p5, p6, p7, p8, p9=0):\n"
        "    def inner(q1, q2, q3, q4, q5, q6, q7, q8, q9, /):\n"
        "        pass\n"
        "def b(p1, p2, p3, p4, p5, p6, p7, p8, *rest, k1=0, k2=0):\n"
        "    pass\n"
    )
    assert over_limit(src) == [("a", 9), ("inner", 9)]


def test_no_long_positional_lists_in_the_core():
    files = sorted(CORE.glob("*.py"))
    assert {p.name for p in files} >= set(TIER_FILES) | {"records.py", "fused.py",
                                                         "sticking.py", "critical.py",
                                                         "critical_relative.py"}
    bad = {p.name: over_limit(p) for p in files if over_limit(p)}
    assert not bad, f"functions over {LIMIT} positional parameters (take a record): {bad}"


def test_tier_flags_are_keywords():
    """In the tier files, a Python function's parameter with a ``True``/``False`` default
    (``details``, ``return_pieces``, ``check``, ...) is keyword-only."""
    bad = []
    for name in TIER_FILES:
        for f in _functions(CORE / name):
            if _compiled(f):
                continue
            args = f.args.posonlyargs + f.args.args
            for arg, default in zip(args[len(args) - len(f.args.defaults):], f.args.defaults,
                                    strict=True):
                if isinstance(default, ast.Constant) and isinstance(default.value, bool):
                    bad.append(f"{name}:{f.name}({arg.arg})")
    assert not bad, f"flags to make keyword-only: {bad}"
