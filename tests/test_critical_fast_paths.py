"""The fast paths of the closed-form u0* (mode "relative"), each against its reference.

1. The check without a second full kernel call.
   :func:`agglomtool.collision.critical_relative.kernel_e_w` evaluates mode "relative"'s
   kernel from its speed-independent numbers (:func:`kernel_constants`), which the
   threshold and both speeds of the check share. It must be the kernel itself, bitwise: its
   ``e_w`` is compared with :func:`agglomtool.collision.relative.relative_kernel`'s on a
   seeded batch spread over the input space (plates, body forces of either sign, coatings
   barely thicker than the asperities to 500 times thicker, viscosities 1e-3..1e6, ``e``
   down to 0), at speeds spread over ten decades and at the two speeds the solver checks
   around each threshold. Any change to the order or form of an operation on either side
   shows up as a differing bit on some element. The batch must reach every stage of the
   kernel (and both forms of the distance function at rupture), so that no branch goes
   unchecked.
2. The Newton iteration's early stop (``early_rtol=EARLY_RTOL``, 1e-10, the default)
   against the iteration without it (``early_rtol=0``): the same status everywhere; the
   threshold never below the full iteration's (to rounding, 1e-12: the stop lands right of
   the crossing, the side the solver's check allows up to ``rtol``) and at most 1e-8 above
   it (4e-10 was the largest difference seen); never more evaluations of ``F``, and fewer
   on a good part of the batch (else the path is not tested).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from agglomtool.collision._codes import (
    APP_EN,
    APP_VIS,
    CONTACT,
    P_BROKEN,
    REBOUND,
    SEP_EN,
    SEP_VIS,
)
from agglomtool.collision.critical_relative import (
    EARLY_RTOL,
    OK,
    kernel_constants,
    kernel_e_w,
    relative_threshold,
)
from agglomtool.collision.records import Pair
from agglomtool.collision.relative import relative_kernel


@njit
def _both(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e, w):
    """``e_w`` of the kernel and of ``kernel_e_w``, the kernel's stage and path, and the
    log1p flag of the rupture gap's distance function, per element."""
    n = w.shape[0]
    ref = np.empty(n)
    got = np.empty(n)
    stage = np.empty(n, dtype=np.int64)
    path = np.empty(n, dtype=np.int64)
    empty = np.empty(0)
    for k in range(n):
        p = Pair(m_i[k], m_j[k], r[k], H0[k], Ha[k], mu_l[k], gamma[k], cos_t[k], theta[k],
                 fn_i[k], fn_j[k], e[k])
        ew, sg, pa, _ = relative_kernel(p, w[k], empty)
        kc = kernel_constants(p)
        ref[k] = ew
        got[k] = kernel_e_w(kc, H0[k], Ha[k], mu_l[k], gamma[k], theta[k], e[k], w[k])
        stage[k] = sg
        path[k] = pa
    return ref, got, stage, path


@njit
def _thresholds(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e):
    n = e.shape[0]
    out = np.full(n, np.nan)
    for k in range(n):
        if e[k] > 0.0:
            w, status = relative_threshold(Pair(m_i[k], m_j[k], r[k], H0[k], Ha[k], mu_l[k],
                                                gamma[k], cos_t[k], theta[k], fn_i[k],
                                                fn_j[k], e[k]), 60)
            if status == OK:
                out[k] = w
    return out


def _batch(n, seed):
    rng = np.random.default_rng(seed)

    def lu(lo, hi, size=n):
        return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), size)

    d_i, d_j = lu(50e-6, 5e-3), lu(50e-6, 5e-3)
    rho_i, rho_j = rng.uniform(900.0, 8000.0, n), rng.uniform(900.0, 8000.0, n)
    k = rng.random(n)
    plate_j, plate_i = k < 0.1, k > 0.95
    d_j = np.where(plate_j, np.inf, d_j)
    d_i = np.where(plate_i, np.inf, d_i)
    vol_i, vol_j = np.pi / 6.0 * d_i**3, np.pi / 6.0 * d_j**3
    m_i = np.where(plate_i, np.inf, rho_i * np.where(plate_i, 1.0, vol_i))
    m_j = np.where(plate_j, np.inf, rho_j * np.where(plate_j, 1.0, vol_j))
    r = 2.0 / (2.0 / d_i + 2.0 / d_j)
    # A few radii far below the gaps (no physical pair): the only way the rupture gap ends
    # up below a/5 or so, where ln f takes its three-log form there.
    r = np.where(rng.random(n) < 0.1, lu(1e-14, 1e-10), r)
    Ha = lu(0.02e-6, 4e-6)
    H0 = Ha * (1.0 + lu(1e-6, 499.0))
    theta = np.deg2rad(rng.uniform(0.0, 85.0, n))
    # Body forces from none to a hundred times the weight, either sign, on either side.
    weight_i = np.where(plate_i, 1.0, m_i) * 9.81
    weight_j = np.where(plate_j, 1.0, m_j) * 9.81
    fn_i = np.where(rng.random(n) < 0.2, 0.0, rng.normal(0.0, 1.0, n) * lu(0.01, 100.0)
                    * weight_i)
    fn_j = np.where(rng.random(n) < 0.2, 0.0, rng.normal(0.0, 1.0, n) * lu(0.01, 100.0)
                    * weight_j)
    e = np.where(rng.random(n) < 0.03, 0.0, rng.uniform(0.05, 1.0, n))
    return (m_i, m_j, r, H0, Ha, lu(1e-3, 1e6), rng.uniform(0.02, 0.6, n), np.cos(theta),
            theta, fn_i, fn_j, e)


def test_kernel_e_w_is_the_kernel_bitwise():
    n = 20_000
    args = _batch(n, 20261122)
    rng = np.random.default_rng(5)
    # Speeds over ten decades, and the solver's two check speeds around each threshold.
    w_star = _thresholds(*args)
    has = np.isfinite(w_star) & (w_star > 0.0)
    assert has.sum() > 0.8 * n
    rtol = 1e-6
    hi = w_star * (1.0 + 1e-3 * rtol)
    speeds = [10.0 ** rng.uniform(-5.0, 5.0, n), np.where(has, hi, 1.0),
              np.where(has, hi * (1.0 - rtol), 1.0), np.where(has, w_star, 1.0),
              np.where(has, w_star * 1.5, 1.0)]
    stages, paths = [], []
    for w in speeds:
        ref, got, stage, path = _both(*args, w)
        bad = np.flatnonzero(ref.view(np.int64) != got.view(np.int64))
        assert bad.size == 0, (bad[:5], ref[bad[:5]], got[bad[:5]])
        stages.append(stage)
        paths.append(path)
    stage, path = np.concatenate(stages), np.concatenate(paths)
    # Every way the kernel ends is exercised.
    for code in (APP_VIS, APP_EN, CONTACT, SEP_VIS, SEP_EN, REBOUND):
        assert np.count_nonzero(stage == code) > 20, code
    broken = (stage == REBOUND) & ((path & P_BROKEN) != 0)
    assert np.count_nonzero(broken) > 20
    assert np.count_nonzero((stage == REBOUND) & ~broken) > 1000
    # Both forms of ln f at the rupture gap (log1p where the gap is large next to a).
    m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e = args
    w = speeds[1]
    a2 = (H0 - Ha) * (H0 + Ha)
    h = (1.0 + 0.5 * theta) * np.cbrt(0.5 * math.pi * r * a2)  # h_rupt at Ca -> 0
    q = a2 / (h + np.sqrt(h * h + a2)) ** 2
    sep = has & (h > Ha) & np.isfinite(w)
    assert np.count_nonzero(sep & (q < 0.5)) > 100
    assert np.count_nonzero(sep & (q >= 0.5)) > 30


@njit
def _thresholds_with(m_i, m_j, r, H0, Ha, mu_l, gamma, cos_t, theta, fn_i, fn_j, e,
                     max_iter, early_rtol):
    n = e.shape[0]
    w = np.full(n, np.nan)
    status = np.full(n, -1)
    for k in range(n):
        if e[k] > 0.0:
            w[k], status[k] = relative_threshold(Pair(m_i[k], m_j[k], r[k], H0[k], Ha[k],
                                                      mu_l[k], gamma[k], cos_t[k], theta[k],
                                                      fn_i[k], fn_j[k], e[k]),
                                                 max_iter, early_rtol)
    return w, status


def test_early_stop_equals_the_full_newton():
    n = 20_000
    args = _batch(n, 20261123)
    w_e, s_e = _thresholds_with(*args, 60, EARLY_RTOL)
    w_r, s_r = _thresholds_with(*args, 60, 0.0)
    np.testing.assert_array_equal(s_e, s_r)
    ok = (s_r == OK) & np.isfinite(w_r) & (w_r > 0.0)
    assert ok.sum() > 0.8 * n
    assert np.array_equal(w_e[~ok], w_r[~ok], equal_nan=True)
    gap = (w_e[ok] - w_r[ok]) / w_r[ok]
    assert gap.min() >= -1e-12, gap.min()
    assert gap.max() <= 1e-8, gap.max()
    # Evaluations of F each variant needs (the fewest max_iter that converges).
    need_e = np.full(n, 99)
    need_r = np.full(n, 99)
    for k in range(12, 0, -1):
        need_e[_thresholds_with(*args, k, EARLY_RTOL)[1] == OK] = k
        need_r[_thresholds_with(*args, k, 0.0)[1] == OK] = k
    counted = ok & (need_r < 99)
    assert counted.sum() > 0.7 * n
    assert np.all(need_e[counted] <= need_r[counted])
    assert np.mean(need_e[counted] < need_r[counted]) > 0.3
