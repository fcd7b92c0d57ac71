"""The piecewise closed forms inside mode "auto" (agglomtool.collision.auto).

Each liquid stage cut into ``n`` pieces of equal ``ln f``, the closed forms of mode
"relative" applied on each from the speed the previous piece left. With one piece they are
mode "relative"; as ``n`` grows they approach the integrated truth (mode "ode" at its
default rtol 1e-10), and their error stays within ``PIECEWISE_BOUND * g`` wherever their
pieces are clear.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import agglomtool as at
from agglomtool.api import _fused_inputs
from agglomtool.collision import fused
from agglomtool.collision.auto import (
    G_MAX,
    PIECES,
    PIECEWISE_BOUND,
    TIER_ODE,
    TIER_RELATIVE,
    auto_batch,
    auto_fused,
    closed_form_indicator,
    piecewise_batch,
    piecewise_kernel,
)
from agglomtool.collision.ode import ode_batch
from agglomtool.collision.outcome import DETAIL_NAMES
from agglomtool.collision.records import Pair
from agglomtool.collision.relative import relative_kernel
from agglomtool.pair import prepare_pair

KERNEL_NAMES = ("m_i", "m_j", "r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta")
WATER = dict(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
SLAG = dict(mu=10.0, gamma=0.4, rho=2500.0, theta_deg=10.0)
AIR = dict(mu=18.48e-6, rho=1.168)
HOT = dict(mu=45.48e-6, rho=0.324)


def mixed_scenes(n, seed):
    """Water and slag pairs as in the collision benchmark (diameters 0.3-1.5 mm, sand or
    ilmenite, water films 1-9 um or slag films 0.11-0.3 um, angles 0-360 deg), a tenth of
    them on a plate."""
    rng = np.random.default_rng(seed)
    slag = rng.random(n) < 0.5

    def pick(a, b):
        return np.where(slag, b, a)

    lo, hi = pick(1e-6, 0.11e-6), pick(9e-6, 0.3e-6)

    def particle(plate=None):
        d = rng.uniform(300e-6, 1500e-6, n)
        rho = rng.choice([2650.0, 4330.0], n)
        if plate is not None:
            d, rho = np.where(plate, np.inf, d), np.where(plate, np.inf, rho)
        return at.Particle(d=d, rho=rho, h0=lo + (hi - lo) * rng.random(n), ha=0.1e-6)

    return dict(p_i=particle(), p_j=particle(rng.random(n) < 0.1),
                liquid=at.Liquid(**{k: pick(WATER[k], SLAG[k]) for k in WATER}),
                gas=at.Gas(**{k: pick(AIR[k], HOT[k]) for k in AIR}), bed=at.Bed(eps=0.55),
                beta_deg=rng.uniform(0.0, 360.0, n))


def kernel_inputs(kw, factors, mode="ode"):
    """Flat kernel inputs of every scene at ``factors`` times its critical speed."""
    n = np.size(kw["beta_deg"])
    u_star = at.critical_impact_speed(**kw, mode=mode)
    stt = prepare_pair(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                       kw["beta_deg"], 0.9, True, "emulsion")

    def rep(a):
        return np.repeat(np.broadcast_to(np.ravel(a), (n,)), factors.size)

    u = (np.ravel(u_star)[:, None] * factors[None, :]).ravel()
    arrs = [rep(getattr(stt, k)) for k in KERNEL_NAMES]
    arrs.append(u * rep(stt.w_per_u0))
    arrs += [rep(getattr(stt, k)) for k in ("fn_i", "fn_j", "e")]
    ok = np.isfinite(arrs[9])
    return [np.ascontiguousarray(a[ok], dtype=float) for a in arrs]


@pytest.fixture(scope="module")
def spread():
    """Mixed scenes from 0.6 to 4 times their critical speed, with the truth."""
    args = kernel_inputs(mixed_scenes(200, 17), np.geomspace(0.6, 4.0, 24))
    return args, ode_batch(args)[0]


def test_one_piece_is_mode_relative_bitwise(spread):
    """``n = 1``: outcome and indicator of the whole-stage closed forms, and the details of
    mode "relative", bitwise (NaN where either has none)."""
    args, _ = spread
    det_p = np.empty(len(DETAIL_NAMES))
    det_r = np.empty(len(DETAIL_NAMES))
    stages = set()
    for q in range(0, args[0].size, 7):
        x = [float(a[q]) for a in args]
        pair, w = Pair(*x[:9], *x[10:]), x[9]  # the tier order has w after theta
        ew, sg, pa, g, _ = piecewise_kernel(pair, w, 1, det_p)
        assert (ew, sg, pa, g) == closed_form_indicator(pair, w, det_r), q
        relative_kernel(pair, w, det_r)
        np.testing.assert_array_equal(det_p, det_r)
        stages.add(sg)
    assert len(stages) >= 3  # rebounds and sticks at several stages


def test_pieces_converge_to_ode_where_whole_stages_err(spread):
    """Where the whole-stage closed forms err by more than 0.005 (about 370 collisions,
    water pairs) and the pieces are clear, the pieces approach the truth: every collision
    errs at 4 and at 16 pieces by less than a tenth of the whole stages' error, and the
    largest error falls from 1 to 2 to 4 pieces and from 16 to 64 to 256.

    Between 4 and 16 pieces it does not fall: the error has a part of one sign that falls
    about as 1/n^2 (+1.8e-2, +4.7e-3, +3.5e-4 at 1, 2, 4 pieces on a typical case) and a
    smaller part of the other sign that falls slowly (-7.7e-4, -3.5e-4, -1.2e-4 at 16, 64,
    256), so near 4 pieces the two cancel (measured largest errors 1.5e-3 at both 4 and
    16 pieces, 2.9e-2 for the whole stages)."""
    args, truth = spread
    err = {n: np.abs(piecewise_batch(args, n)[0] - truth) for n in (1, 2, 4, 16, 64, 256)}
    clear = piecewise_batch(args, 4)[4] & piecewise_batch(args, 16)[4]
    hard = (err[1] > 0.005) & clear & (truth > 0)
    assert hard.sum() >= 100
    for n in (4, 16):
        assert np.all(err[n][hard] < 0.1 * err[1][hard]), n
    top = {n: e[hard].max() for n, e in err.items()}
    assert top[1] > top[2] > top[4]
    assert top[16] > top[64] > top[256]
    assert top[256] < 0.01 * top[1]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), lo=st.floats(0.6, 1.5), span=st.floats(1.0, 8.0))
def test_pieces_stay_within_their_calibrated_bound(seed, lo, span):
    """Clear rebounds with ``g <= G_MAX`` at every piece count of the ladder: the error
    against the truth is at most ``PIECEWISE_BOUND * g``."""
    args = kernel_inputs(mixed_scenes(6, seed), np.geomspace(lo, lo * span, 8))
    truth = ode_batch(args)[0]
    for n in PIECES:
        e, _, _, g, clear = piecewise_batch(args, n)
        ok = (e > 0) & clear & (g <= G_MAX)
        assert np.all(np.abs(e - truth)[ok] <= PIECEWISE_BOUND * g[ok]), n


@pytest.mark.parametrize("tol", [0.01, 0.002])
def test_auto_uses_every_form_and_stays_within_tol(spread, tol):
    """Mode "auto" on the spread: whole stages, each piece count and "ode" all used, error
    within ``tol`` and within the bound reported, no outcome flipped where the truth is
    clear of ``tol``; the fused path chooses the same forms."""
    args, truth = spread
    e_w, _, _, _, tier, bound, pieces = auto_batch(args, tol=tol, return_pieces=True)
    err = np.abs(e_w - truth)
    assert err.max() <= tol
    assert np.all(err <= bound + 1e-15)
    assert not np.any((truth > tol) & (e_w == 0.0))
    assert not np.any((e_w > tol) & (truth == 0.0))
    assert set(np.unique(pieces).tolist()) == {0, 1, *PIECES}
    np.testing.assert_array_equal(tier, np.where(pieces == 0, TIER_ODE, TIER_RELATIVE))


@pytest.mark.parametrize("size", [3000, 700])
def test_fused_auto_chooses_as_auto_batch(size):
    """The fused path (preparation and choice in one loop) takes the same form per
    collision as ``auto_batch`` on the prepared arrays, and the same outcome, bitwise;
    above and below ``SERIAL_BELOW`` (the parallel and the serial loop)."""
    kw = mixed_scenes(size, 23)
    rng = np.random.default_rng(4)
    u_star = at.critical_impact_speed(**kw)
    u0 = u_star * rng.uniform(0.5, 3.0, u_star.shape)
    _, ins, steps, n = _fused_inputs(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"],
                                     kw["bed"], kw["beta_deg"], 0.9, u0, None)
    e_f, st_f, pa_f, _, pc_f = auto_fused(ins, steps, n, body=True, particle_slip=False,
                                              return_pieces=True)
    k = fused.prepare_flat(ins, steps, n, True, False)
    e_b, st_b, pa_b, _, _, _, pc_b = auto_batch(k[:13], return_pieces=True)
    np.testing.assert_array_equal(pc_f, pc_b)
    np.testing.assert_array_equal(e_f, e_b)
    np.testing.assert_array_equal(st_f, st_b)
    np.testing.assert_array_equal(pa_f, pa_b)
    assert set(np.unique(pc_f).tolist()) >= {1, *PIECES}


def test_details_of_the_pieces_balance(spread):
    """``details=True``: the rows of collisions taken by pieces carry the summed stage
    losses, and the energies balance (``K_fin = K_ini - losses``, ``e_w^2 = K_fin /
    K_ini``)."""
    args, _ = spread
    e_w, _, _, det, _, _, pieces = auto_batch(args, details=True, return_pieces=True)
    col = {name: det[:, k] for k, name in enumerate(DETAIL_NAMES)}
    rows = (pieces > 1) & (e_w > 0) & np.isfinite(col["L_vis_sep"])
    assert rows.sum() >= 20
    k_ini = col["K_ini_i"] + col["K_ini_j"]
    k_app = col["K_app_i"] + col["K_app_j"]
    k_fin = col["K_fin_i"] + col["K_fin_j"]
    lost_app = col["L_cap_app"] + col["L_vis_app"] + col["L_bdw_app_i"] + col["L_bdw_app_j"]
    np.testing.assert_allclose((k_ini - lost_app)[rows], k_app[rows], rtol=1e-9,
                               atol=1e-12 * k_ini[rows].max())
    np.testing.assert_allclose(np.sqrt(k_fin / k_ini)[rows], e_w[rows], rtol=1e-12)
    assert math.isfinite(float(col["h_rupt"][rows].max()))
