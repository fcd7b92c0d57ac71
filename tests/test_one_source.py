"""One source for each piece of pair physics.

The Wen-Yu ``U_mf``, Gidaspow's drag, the wet mass and the paper's ``U_e = 1.1 U_mf`` are
each written once, as compiled scalar functions of :mod:`agglomtool.collision.physics`, and
both the numpy reference (:func:`agglomtool.pair.prepare_pair`, :mod:`agglomtool.properties`)
and the fused kernels (:mod:`agglomtool.collision.fused`) call them. Two checks:

- behaviour: the reference and the fused preparation give bitwise the same masses and
  body forces, with the emulsion velocity derived (``Bed.U`` None) and given, on wide
  random inputs (two copies of a formula written with different powers, ``d**3`` against
  ``d * d * d``, or numpy's ``power`` against the C library's, differ in the last place);
- source: the correlations' own numbers (Wen and Yu's 33.7, Schiller-Naumann's 0.687,
  Wen and Yu's voidage exponent 1.65, Ergun's 150 and 1.75) appear in no other module of
  the package.
"""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import agglomtool as at
from agglomtool.api import _fused_inputs, _lab_speeds
from agglomtool.collision import fused
from agglomtool.pair import prepare_pair

PACKAGE = Path(__file__).resolve().parent.parent / "agglomtool"
HOME = PACKAGE / "collision" / "physics.py"


def _lu(rng, lo, hi, n):
    return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), n)


def _scene(rng, n):
    d_i = _lu(rng, 10e-6, 10e-3, n)
    d_j = d_i * _lu(rng, 1e-2, 1e2, n)
    d_j[: n // 8] = np.inf  # plates in slot j
    p_i = at.Particle(d=d_i, rho=rng.uniform(500.0, 10000.0, n), h0=_lu(rng, 1e-8, 5e-4, n),
                      ha=1e-7)
    p_j = at.Particle(d=d_j, rho=np.where(np.isinf(d_j), np.inf, rng.uniform(500, 1e4, n)),
                      h0=_lu(rng, 1e-8, 5e-4, n), ha=1e-7)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=rng.uniform(500, 3000, n), theta_deg=20.0)
    gas = at.Gas(mu=rng.uniform(15e-6, 50e-6, n), rho=rng.uniform(0.2, 1.5, n))
    eps = rng.uniform(0.3, 0.99, n)  # both sides of Gidaspow's switch
    beta = rng.uniform(-180.0, 540.0, n)
    u0 = _lu(rng, 1e-4, 10.0, n)
    return p_i, p_j, liq, gas, eps, beta, u0


@pytest.mark.parametrize("slip", ["emulsion", "particle"])
@pytest.mark.parametrize("given_U", [False, True])
def test_reference_and_fused_preparation_are_the_same_arithmetic(slip, given_U):
    rng = np.random.default_rng(25)
    n = 4000
    p_i, p_j, liq, gas, eps, beta, u0 = _scene(rng, n)
    bed = at.Bed(eps=eps, U=rng.uniform(0.0, 2.0, n) if given_U else None)
    u_i, u_j, _ = _lab_speeds(p_i, p_j, u0, None)
    state = prepare_pair(p_i, p_j, liq, gas, bed, beta, 0.9, True, slip, u_i=u_i, u_j=u_j)
    _, ins, steps, n = _fused_inputs(p_i, p_j, liq, gas, bed, beta, 0.9, u0, None)
    k = fused.prepare_flat(ins, steps, n, True, slip == "particle")
    for q, name in ((0, "m_i"), (1, "m_j"), (10, "fn_i"), (11, "fn_j")):
        np.testing.assert_array_equal(k[q], np.broadcast_to(getattr(state, name), (n,)),
                                      err_msg=name)


#: Numbers that belong to one correlation each: where else they appear, it is a copy.
CORRELATION_NUMBERS = {33.7: "Wen-Yu C1", 0.687: "Schiller-Naumann exponent",
                       1.65: "Wen-Yu voidage exponent", 150.0: "Ergun viscous term",
                       1.75: "Ergun inertial term"}


def test_the_correlations_numbers_are_written_once():
    where = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Constant) and type(node.value) is float
                    and node.value in CORRELATION_NUMBERS):
                where.setdefault(node.value, set()).add(path.relative_to(PACKAGE).as_posix())
    copies = {CORRELATION_NUMBERS[v]: sorted(files) for v, files in where.items()
              if files != {HOME.relative_to(PACKAGE).as_posix()}}
    assert not copies, f"written outside collision/physics.py: {copies}"
