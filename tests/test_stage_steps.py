"""The steps of a collision that several tiers take alike are written once, in
``agglomtool/collision/stages.py`` (with the masses in ``physics.py`` and the bridge
geometry in ``bridge.py``), and the tier files hold no copy of their arithmetic: changing
one step's physics is a change to one function.

Each test parses the tier files with :mod:`ast` (code only: docstrings and comments do not
count) and looks for the arithmetic of one shared step written out again. What a tier does
differently on purpose is named where it is allowed (the paper's per-particle stages take
the viscous loss of each particle themselves). The equality of the outputs before and
after the steps were shared is the tiers' own tests' business (``test_tiers_models``,
``test_auto_piecewise``, ``test_fused_equality``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

CORE = Path(__file__).resolve().parent.parent / "agglomtool" / "collision"
#: The tier files: the kernels that take the shared steps.
TIERS = ("paper.py", "relative.py", "ode.py", "auto.py", "stokes.py")
#: The kernels that fill a details row (each clears it through stages.fresh_details).
KERNELS = {"paper.py": ["paper_kernel"], "relative.py": ["relative_kernel"],
           "ode.py": ["ode_kernel"], "auto.py": ["piecewise_kernel", "_piecewise"],
           "stokes.py": ["stokes_kernel"]}
#: The shared steps, each defined once in the core.
SHARED = {
    "stages.py": ("viscous_loss", "bridge_constants", "fresh_details", "no_bridge",
                  "dry_contact", "contact_details", "contact_speed", "relative_contact",
                  "rupture_at", "separation_start", "split_details", "stage_details",
                  "rupture_details", "stage_losses", "stage_energy", "term_work_fractions",
                  "work_details", "tier_outputs"),
    "physics.py": ("reduced_mass", "relative_body_force"),
    "bridge.py": ("rupture_gap", "ln_f_change", "g_change", "viscous_constant",
                  "capillary_constant"),
}


def _tree(name: str, root: Path = CORE) -> ast.Module:
    return ast.parse((root / name).read_text())


def _text(node: ast.AST) -> str:
    return ast.unparse(node)


def _binops(tree: ast.AST):
    return [n for n in ast.walk(tree) if isinstance(n, ast.BinOp)]


def _offences(name: str, pred) -> list[str]:
    return [f"{name}:{n.lineno}: {_text(n)}" for n in ast.walk(_tree(name)) if pred(n)]


def _is_name(node: ast.AST, ident: str) -> bool:
    return (isinstance(node, ast.Name) and node.id == ident) or (
        isinstance(node, ast.Attribute) and node.attr == ident)


def test_each_shared_step_is_defined_once():
    """Every shared step has exactly one definition among the core's files."""
    defs: dict[str, list[str]] = {}
    for path in sorted(CORE.glob("*.py")):
        for node in ast.walk(_tree(path.name)):
            if isinstance(node, ast.FunctionDef):
                defs.setdefault(node.name, []).append(path.name)
    for home, names in SHARED.items():
        for name in names:
            assert defs.get(name) == [home], (name, defs.get(name))


@pytest.mark.parametrize("name", TIERS)
def test_details_row_cleared_by_the_shared_step(name):
    """No tier clears a details row in its own loop (``stages.fresh_details`` does), and each
    kernel that fills one calls it."""
    loops = _offences(name, lambda n: isinstance(n, ast.For) and any(
        isinstance(a, ast.Assign) and isinstance(a.targets[0], ast.Subscript)
        and (_is_name(a.value, "nan")) for a in n.body))
    assert loops == []
    funcs = {n.name: n for n in ast.walk(_tree(name)) if isinstance(n, ast.FunctionDef)}
    for kernel in KERNELS[name]:
        calls = [n for n in ast.walk(funcs[kernel]) if isinstance(n, ast.Call)
                 and _is_name(n.func, "fresh_details")]
        assert calls, f"{name}: {kernel} does not call stages.fresh_details"


@pytest.mark.parametrize("name", TIERS)
def test_dry_collision_and_contact_written_once(name):
    """The dry outcome (its path flag ``P_NO_BRIDGE``) and the contact's loss column ``L_C``
    appear only in ``stages.py``."""
    assert _offences(name, lambda n: _is_name(n, "P_NO_BRIDGE")) == []
    assert _offences(name, lambda n: isinstance(n, ast.Subscript)
                     and _is_name(n.slice, "L_C")) == []


@pytest.mark.parametrize("name", TIERS)
def test_constants_masses_and_rupture_gap_written_once(name):
    """No tier forms the bridge's constants (a product with ``pi``), the mass fractions
    (``m_i + m_j``) or Eq. 94's angle factor (``0.5 * theta``) itself."""
    bad = [f"{name}:{n.lineno}: {_text(n)}" for n in _binops(_tree(name))
           if "math.pi" in _text(n) or _text(n) in ("m_i + m_j", "0.5 * theta")]
    assert bad == []


@pytest.mark.parametrize("name", TIERS)
def test_ln_f_change_written_once(name):
    """No tier forms a difference of ``ln f`` from the gaps' parts (``... * _LN4``) itself:
    ``bridge.ln_f_change`` and ``ln_f_diff_from`` do."""
    bad = [f"{name}:{n.lineno}: {_text(n)}" for n in _binops(_tree(name))
           if isinstance(n.op, ast.Mult) and (_is_name(n.left, "_LN4")
                                              or _is_name(n.right, "_LN4"))]
    assert bad == []


@pytest.mark.parametrize("name", [t for t in TIERS if t != "paper.py"])
def test_relative_stage_written_once(name):
    """The relative-motion tiers take a liquid stage's viscous loss only through
    ``stages.stage_energy`` (the paper's per-particle stages, in ``paper.py``, take each
    particle's loss themselves: another frame)."""
    assert _offences(name, lambda n: isinstance(n, ast.Call)
                     and (_is_name(n.func, "viscous_loss")
                          or _is_name(n.func, "_viscous_loss"))) == []
