"""The laws' map passes (agglomtool.bed.hydrodynamics: ``_bubble_block``,
``_collisional_block``) compute a row's elements in loops the compiler turns into vector
instructions: no branch, no call and no checked division inside the loop (a division that
Python's error model checks for zero can raise, which keeps a loop scalar). The test
compiles each block afresh with its own options for the arguments a map gives it and
looks in its LLVM IR for the vector form of the row's costly step: the bubble's square
root (its rise velocity, in the chain) or the collisional balance's division; the numbers
are checked bit for bit against the plain path in test_speed_law_passes.py.
"""

import re

import numba
import numpy as np
import pytest

from agglomtool.bed import hydrodynamics as hd

SHAPE = (6, 8, 300)  # a map's block: U over the grid, U_mf along the first two axes


def _map_args(block):
    rng = np.random.default_rng(7)
    Umf = rng.uniform(0.2, 0.4, SHAPE[:-1] + (1,))
    U = Umf * rng.uniform(1.5, 4.0, SHAPE)
    theta = np.empty(SHAPE).reshape(-1)
    code = np.zeros(SHAPE, np.int8).reshape(-1)
    if block == "bubble":
        P = (U - Umf) ** 0.4
        ins, st, shp = hd._map_inputs((U, Umf, P, 0.0, 0.0, 0.2, 0.3, 0.55, 0.25), SHAPE)
        plan, blocks = hd._plan(shp)
        return (ins, st, shp, plan, False, theta, code, np.empty((blocks, 8)), 0)
    ins, st, shp = hd._map_inputs((U, Umf, 0.9998, 1e-3, 2.0), SHAPE)
    plan, blocks = hd._plan(shp)
    return (ins, st, shp, plan, theta, code, np.empty((blocks, 2)), 0)


@pytest.mark.parametrize("block, step", [
    ("bubble", r"call <\d+ x double> @llvm\.sqrt\.v\d+f64"),
    ("collisional", r"fdiv[^\n]*<\d+ x double>"),
])
def test_a_map_row_is_computed_in_vector_instructions(block, step):
    kernel = hd._bubble_block if block == "bubble" else hd._collisional_block
    args = _map_args(block)
    options = {k: v for k, v in kernel.targetoptions.items() if k != "cache"}
    fresh = numba.njit(**options)(kernel.py_func)
    sig = tuple(numba.typeof(a) for a in args)
    fresh.compile(sig)
    ir = fresh.inspect_llvm(sig)
    assert re.search(step, ir), (
        f"_{block}_block's row loop runs one element at a time (no {step!r} in its IR)")
    fresh(*args)  # and it runs on a map's arguments
