"""The rearranged Dormand-Prince step of mode "ode" against the textbook form.

:func:`agglomtool.collision.ode._dp_step` takes its stage gaps from fewer exponentials and
adds each stage's viscous term last (a shorter dependency chain); these tests check it
against a plain evaluation of the Butcher tableau (gaps ``exp(y + c h)``, the right-hand
side written out), to rounding, and the early-stop helpers against the bridge functions they
replace.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from agglomtool.collision.bridge import g_diff, ln_f
from agglomtool.collision.ode import _cannot_rebound, _dp_step, _must_stick, volume_correction
from agglomtool.collision.records import OdeForces, RuptureEnd

# Dormand-Prince 5(4): nodes, stage weights, 5th-order weights, 4th-order weights.
_C = [0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0]
_A = [
    [],
    [1 / 5],
    [3 / 40, 9 / 40],
    [44 / 45, -56 / 15, 32 / 9],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656],
    [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
]
_B5 = [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0]
_B4 = [5179 / 57600, 0.0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40]


def _rhs(y, k, sigma, a2, kc, fb, vis, volcorr):
    d = math.exp(y)
    x = a2 / (math.sqrt(d * d + a2) * (math.sqrt(d * d + a2) + d)) if volcorr else 1.0
    return -d * (kc * x + fb) + sigma * vis * x * x * math.sqrt(max(k, 0.0))


def _textbook_step(y, k, h, f1, sigma, a2, kc, fb, vis, volcorr):
    f = [f1]
    for i in range(1, 7):
        ki = k + h * sum(a * fj for a, fj in zip(_A[i], f, strict=True))
        f.append(_rhs(y + _C[i] * h, ki, sigma, a2, kc, fb, vis, volcorr))
    k5 = k + h * sum(b * fj for b, fj in zip(_B5, f, strict=True))
    k4 = k + h * sum(b * fj for b, fj in zip(_B4, f, strict=True))
    return k5, k5 - k4, f[6], [abs(fj) for fj in f]


@pytest.mark.parametrize("volcorr", [True, False])
@pytest.mark.parametrize("sigma", [1.0, -1.0])
def test_dp_step_is_the_textbook_step(volcorr, sigma):
    rng = np.random.default_rng(7)
    worst_k = worst_err = 0.0
    for _ in range(400):
        a = 10.0 ** rng.uniform(-6, -3)
        a2 = a * a
        y = math.log(a * 10.0 ** rng.uniform(-2, 1))
        h = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-4, 0)
        k = 10.0 ** rng.uniform(-3, 0)
        kc = 10.0 ** rng.uniform(0, 5)
        fb = rng.uniform(-1, 1) * 10.0 ** rng.uniform(-2, 3)
        vis = 10.0 ** rng.uniform(-2, 1)
        f1 = _rhs(y, k, sigma, a2, kc, fb, vis, volcorr)
        k5, err, f7, d_new, s_new, x_new, sk5 = _dp_step(
            y, math.exp(y), k, h, f1, sigma, OdeForces(a2, kc, fb, vis, volcorr))
        r5, rerr, rf7, mags = _textbook_step(y, k, h, f1, sigma, a2, kc, fb, vis, volcorr)
        # rounding of the stage sums: relative to the terms summed, not to their sum
        scale = abs(k) + abs(h) * max(mags)
        worst_k = max(worst_k, abs(k5 - r5) / scale)
        worst_err = max(worst_err, abs(err - rerr) / scale)
        assert d_new == math.exp(y + h)
        assert sk5 == math.sqrt(max(k5, 0.0))
        if volcorr:
            assert s_new == math.sqrt(d_new * d_new + a2)
            assert x_new == volume_correction(d_new, a2)
        else:
            assert x_new == 1.0
        assert abs(f7 - rf7) <= 1e-12 * max(mags) + 1e-12 * abs(rf7)
    assert worst_k < 1e-13
    assert worst_err < 1e-13


def test_early_stop_helpers_match_the_bridge_functions():
    """The helpers take the step's square roots; the decisions are those of the bridge
    functions' forms (the same operations)."""
    rng = np.random.default_rng(3)
    for _ in range(2000):
        a = 10.0 ** rng.uniform(-6, -3)
        a2 = a * a
        d = a * 10.0 ** rng.uniform(-2, 1)
        h_end = d * 10.0 ** rng.uniform(0, 2)
        kc = 10.0 ** rng.uniform(0, 5)
        fb = rng.uniform(-1, 1) * 10.0 ** rng.uniform(-2, 3)
        vis = 10.0 ** rng.uniform(-2, 1)
        k = 10.0 ** rng.uniform(-6, 0)
        s = math.sqrt(d * d + a2)
        s_end = math.sqrt(h_end * h_end + a2)
        lnf_end = ln_f(h_end, a2)
        for pulls in (False, True):
            w_rest = kc * g_diff(d, h_end, a2) + fb * (h_end - d)
            if k <= w_rest:
                want = True
            elif pulls:
                v = math.sqrt(k)
                want = v - 0.5 * w_rest / v - 0.5 * vis * (lnf_end - ln_f(d, a2)) <= 0.0
            else:
                want = False
            assert _must_stick(d, s, k, OdeForces(a2, kc, fb, vis, True),
                               RuptureEnd(h_end, s_end, lnf_end, pulls)) == want
        x = volume_correction(d, a2)
        e2 = rng.uniform(0.01, 1.0)
        need = 10.0 ** rng.uniform(-6, 0)
        m = max(math.sqrt(k), d * (kc * x + max(fb, 0.0)) / (vis * x * x))
        assert _cannot_rebound(d, x, math.sqrt(k), kc, fb, vis, e2, need) == (e2 * m * m <= need)
