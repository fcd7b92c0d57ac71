"""Shared cases and independent checks for the robustness tests.

Two checks are written here from the paper's equations alone, not from the package's code:

``reference_e_w``
    The closed form of Eqs. 3, 25-30, 72-105, 94 for a pair WITHOUT body forces (or whose body
    forces have no component along the collision axis). Without body forces the running
    energy of each particle is ``[(P - c Delta)^2 / 2 - m_r L_cap] / m_k`` (P = m_r w, the
    common CM momentum; the share of particle k is m_r / m_k), so both particles stop at the
    same gap, no special path is taken, and the whole flow chart collapses to the relative
    motion with the reduced mass ``m_r``::

        approach:   E_app = m_r w^2 / 2 - L_cap(H0 -> Ha) - c Da (w - c Da / (2 m_r))
                    sticks if c Da >= m_r w or E_app <= 0
        contact:    w_c = sqrt(2 E_app / m_r), w_s = e w_c; sticks if w_s = 0
        separation: h_rupt from Eq. 94 with Ca = mu w_s / gamma; nothing lost if h_rupt <= Ha
                    E_fin = m_r w_s^2 / 2 - L_cap(Ha -> h_rupt) - c Ds (w_s - c Ds / (2 m_r))
                    sticks if c Ds >= m_r w_s or E_fin <= 0
        e_w = sqrt(2 E_fin / m_r) / w

    It holds for identical particles, any size ratio and a plate: without body forces both
    particles carry the same CM momentum, so their running energies per unit CM speed are
    equal and neither stops before the other; a plate, the limit of an infinitely heavy
    partner, takes the same path with share 1 (see
    ``test_stability.test_plate_is_the_heavy_partner_limit_in_every_tier``).

``energy_terms`` / ``assert_energy_bound``
    An upper bound that the paper's bookkeeping guarantees for every collision it calls a
    rebound, body forces included. Viscous losses are >= 0 wherever the kernel uses them
    (it checks ``c Delta < m v`` first); a particle that stops first is stopped where its
    running energy reaches zero, so nothing is created there; restitution keeps
    ``e^2 m_r w_c^2 / 2 <= e^2 (K_app,i + K_app,j)`` (the energy of the relative motion is
    the smallest over frames); and ``m_r v_rel^2 / 2 <= K_fin,i + K_fin,j`` for the same
    reason. The body-force work on a stage is at most ``max(|F_i|, |F_j|)`` times the gap
    change because the distance shares add up to one. Hence::

        m_r (e_w w)^2 / 2 <= e^2 max(0, K0 + G_app + F (H0 - Ha))
                             - L_cap(Ha -> h_rupt) + F max(0, h_rupt - Ha)

    with ``G_app = 2 pi gamma r cos(theta) (g(H0) - g(Ha)) >= 0`` the capillary work gained
    on the approach. Note that this is NOT ``e_w <= e``: capillary work gained on the approach
    is not paid back when the bridge ruptures below ``H0`` (``h_rupt < H0``, thick films on
    small particles, or a bridge already broken at contact), and body forces do work of
    either sign. ``e_w <= e`` follows only where ``F = 0`` (or the body work is a net loss)
    and ``h_rupt >= H0``.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import agglomtool as at
from agglomtool.pair import prepare_pair


# --------------------------------------------------------------------------------------
# The paper's Table 2 cases (I: water, II: hypothetical slag)
# --------------------------------------------------------------------------------------
def case_water():
    p = at.Particle(d=1000e-6, rho=2650.0, h0=5.00e-6, ha=0.10e-6)
    liquid = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
    gas = at.Gas(mu=18.48e-6, rho=1.168)
    return p, liquid, gas


def case_slag():
    p = at.Particle(d=1000e-6, rho=2650.0, h0=0.15e-6, ha=0.10e-6)
    liquid = at.Liquid(mu=10.0, gamma=0.400, rho=2500.0, theta_deg=10.0)
    gas = at.Gas(mu=45.48e-6, rho=0.324)
    return p, liquid, gas


# --------------------------------------------------------------------------------------
# Independent formulas (Eqs. 3, 28-30, 76, 100-105), written so that nothing cancels
# --------------------------------------------------------------------------------------
def _ln_f(D, a2):
    """ln f(D) accurate in both regimes: for D >> a through log1p, else directly."""
    D = np.asarray(D, dtype=float)
    a2 = np.asarray(a2, dtype=float)
    s = np.sqrt(D * D + a2)
    q = a2 / (s + D) ** 2  # (s - D) / (s + D), in [0, 1)
    far = q * q < 0.25
    with np.errstate(divide="ignore", invalid="ignore"):
        direct = np.log(D) + np.log(s) - 2.0 * np.log(D + s)
        series = -math.log(4.0) + np.log1p(-q * q)
    return np.where(far, series, direct)


def _g(D, a2):
    """Capillary potential g(D) = D - sqrt(D^2 + a^2), as -a^2 / (D + s)."""
    return -a2 / (D + np.sqrt(D * D + a2))


def wet_mass(d, rho, h0, rho_l):
    """(4/3) pi (rho r^3 + rho_l ((r + h0)^3 - r^3)) [kg]; inf for a plate."""
    d = np.asarray(d, dtype=float)
    plate = np.isinf(d)
    r = np.where(plate, 1.0, 0.5 * d)
    m = (4.0 / 3.0) * np.pi * (rho * r**3 + rho_l * ((r + h0) ** 3 - r**3))
    return np.where(plate, np.inf, m)


def reduced_mass(m_i, m_j):
    m_i, m_j = np.broadcast_arrays(np.asarray(m_i, float), np.asarray(m_j, float))
    with np.errstate(invalid="ignore"):
        mr = m_i * m_j / (m_i + m_j)
    return np.where(np.isinf(m_j), m_i, np.where(np.isinf(m_i), m_j, mr))


def reference_e_w(p_i, p_j, liquid, w, e):
    """e_w of the closed form in this module's docstring (no body forces) and the energy
    tolerance [J] of a comparison with it (see ``_reference_one``)."""
    d_i, d_j = np.asarray(p_i.d, float), np.asarray(p_j.d, float)
    m_i = wet_mass(d_i, p_i.rho, p_i.h0, liquid.rho)
    m_j = wet_mass(d_j, p_j.rho, p_j.h0, liquid.rho)
    m_r = reduced_mass(m_i, m_j)
    with np.errstate(divide="ignore"):
        r = 2.0 / (2.0 / d_i + 2.0 / d_j)
    H0 = p_i.h0 + p_j.h0
    Ha = p_i.ha + p_j.ha
    theta = np.deg2rad(liquid.theta_deg)
    mu, gamma = liquid.mu, liquid.gamma
    arrs = np.broadcast_arrays(m_r, r, H0, Ha, mu, gamma, theta, np.asarray(w, float),
                               np.asarray(e, float))
    m_r, r, H0, Ha, mu, gamma, theta, w, e = (a.astype(float).ravel() for a in arrs)
    n = w.size
    out = np.zeros(n)
    scale = np.zeros(n)
    for k in range(n):
        out[k], scale[k] = _reference_one(
            m_r[k], r[k], H0[k], Ha[k], mu[k], gamma[k], theta[k], w[k], e[k]
        )
    shape = arrs[0].shape
    return out.reshape(shape), scale.reshape(shape)


# Absolute rounding of a ln f value evaluated as docs/model.md prescribes it (ln D + ln s
# - 2 ln(D + s)): four logs of magnitude up to ~40, an ulp each, so <= ~2e-14; 1e-13 is an
# a-priori bound. A Delta of two such values carries twice that, and a viscous loss c Delta v
# carries c v times it: when a << D the true Delta is far smaller (a^4 / (16 D^4)) and is
# lost in that rounding, which is harmless for e_w only because the loss is then negligible.
LNF_ABS_ERR = 1e-13
#: Relative rounding allowed on the energies that add up to the result.
ENERGY_RTOL = 1e-9


def _after_stage(k_start, v_start, m_r, c, delta, loss_cap):
    """Energy left after one liquid stage (0 = sticks), Fig. 3 without body forces."""
    if not c * delta < m_r * v_start:  # steps 1 / 7
        return 0.0
    k_end = k_start - loss_cap - c * delta * (v_start - c * delta / (2.0 * m_r))
    if not k_end > 0.0:  # steps 3 / 8, "both <= 0"
        return 0.0
    return k_end


def _reference_one(m_r, r, H0, Ha, mu, gamma, theta, w, e):
    """(e_w, tolerance [J]) for one collision; the tolerance is ENERGY_RTOL times the sum of
    the energies involved plus the viscous loss that the rounding of ln f can shift."""
    k0 = 0.5 * m_r * w * w
    if not H0 > Ha:
        return (e if e > 0.0 else 0.0), ENERGY_RTOL * k0
    a2 = (H0 - Ha) * (H0 + Ha)
    c = 1.5 * math.pi * mu * r * r
    kcap = 2.0 * math.pi * gamma * r * math.cos(theta)
    da = float(_ln_f(H0, a2) - _ln_f(Ha, a2))
    gain = kcap * float(_g(H0, a2) - _g(Ha, a2))  # capillary work gained on approach
    tol = ENERGY_RTOL * (k0 + abs(gain) + c * da * w) + 2.0 * LNF_ABS_ERR * c * w
    e_app = _after_stage(k0, w, m_r, c, da, -gain)
    if not e_app > 0.0:
        return 0.0, tol
    w_s = e * math.sqrt(2.0 * e_app / m_r)
    if not w_s > 0.0:
        return 0.0, tol
    ca = mu * w_s / gamma
    h = (1.0 + 0.5 * theta) * (1.0 + math.sqrt(ca)) * (0.5 * math.pi * r * a2) ** (1.0 / 3.0)
    e_s = 0.5 * m_r * w_s * w_s
    if not h > Ha:
        return w_s / w, tol
    ds = float(_ln_f(h, a2) - _ln_f(Ha, a2))
    loss_cap = kcap * float(_g(h, a2) - _g(Ha, a2))
    tol += ENERGY_RTOL * (abs(loss_cap) + c * ds * w_s) + 2.0 * LNF_ABS_ERR * c * w_s
    e_fin = _after_stage(e_s, w_s, m_r, c, ds, loss_cap)
    if not e_fin > 0.0:
        return 0.0, tol
    return math.sqrt(2.0 * e_fin / m_r) / w, tol


def assert_energy_close(e_w, e_ref, m_r, w, tol, label=""):
    """Compare two e_w through the final energy m_r (e_w w)^2 / 2, to ``tol`` [J].

    Near the threshold e_w is the square root of a small difference of large energies, so
    the comparison is made where rounding lives: in energy, against the size of the terms
    that make it (the callers build ``tol`` as ENERGY_RTOL times those terms)."""
    e_w, e_ref, m_r, w, tol = np.broadcast_arrays(
        np.asarray(e_w, float), np.asarray(e_ref, float), np.asarray(m_r, float),
        np.asarray(w, float), np.asarray(tol, float),
    )
    k_got = 0.5 * m_r * (e_w * w) ** 2
    k_ref = 0.5 * m_r * (e_ref * w) ** 2
    bad = ~(np.abs(k_got - k_ref) <= tol)
    if bad.any():
        i = tuple(int(x) for x in np.argwhere(bad)[0])
        raise AssertionError(
            f"{label}: {int(bad.sum())} of {bad.size} differ; first at {i}: "
            f"e_w = {e_w[i]!r}, expected {e_ref[i]!r} (energy {k_got[i]!r} vs {k_ref[i]!r}, "
            f"tolerance {tol[i]!r})"
        )


def energy_terms(p_i, p_j, liquid, gas, bed, beta_deg, e, result, body_forces=True):
    """The energy bound of the module docstring, term by term, for the elements of
    ``result`` (a :class:`CollisionResult` with details, drag slip "emulsion").

    Returns ``(lhs, bound, scale, m_r)``: the final energy ``m_r (e_w w)^2 / 2`` [J], its
    bound [J], the size of the terms of the bound [J] and the reduced mass [kg]."""
    bed = at.Bed() if bed is None else bed
    s = prepare_pair(p_i, p_j, liquid, gas, bed, beta_deg, e, body_forces, "emulsion")
    shape = result.e_w.shape
    b = lambda a: np.broadcast_to(np.asarray(a, dtype=float), shape)  # noqa: E731
    m_r = b(reduced_mass(s.m_i, s.m_j))
    H0, Ha = b(s.H0), b(s.Ha)
    ee = b(s.e)
    F = b(np.maximum(np.abs(s.fn_i), np.abs(s.fn_j)))
    kcap = b(2.0 * np.pi * s.gamma * s.r * s.cos_t)
    w = result.w
    k0 = 0.5 * m_r * w * w
    bridge = H0 > Ha
    a2 = np.where(bridge, (H0 - Ha) * (H0 + Ha), 1.0)
    dist_app = np.where(bridge, H0 - Ha, 0.0)
    gain = np.where(bridge, kcap * (_g(H0, a2) - _g(Ha, a2)), 0.0)
    h = result.details["h_rupt"]
    reb = result.e_w > 0.0
    if np.any(reb & bridge & ~np.isfinite(h)):
        raise AssertionError("a rebound with a bridge reports no finite h_rupt")
    sep_on = bridge & np.isfinite(h) & (h > Ha)
    h_safe = np.where(sep_on, h, 1.0)
    dist_sep = np.where(sep_on, h_safe - Ha, 0.0)
    loss_sep = np.where(sep_on, kcap * (_g(h_safe, a2) - _g(Ha, a2)), 0.0)
    bound = ee * ee * np.maximum(0.0, k0 + gain + F * dist_app) - loss_sep + F * dist_sep
    scale = k0 + np.abs(gain) + F * dist_app + np.abs(loss_sep) + F * dist_sep
    lhs = 0.5 * m_r * (result.e_w * w) ** 2
    return lhs, bound, scale, m_r


def assert_energy_bound(*args, rtol=ENERGY_RTOL, **kwargs):
    """Every rebound of ``result`` obeys the energy bound (see :func:`energy_terms`)."""
    result = args[7]
    lhs, bound, scale, _ = energy_terms(*args, **kwargs)
    bad = (result.e_w > 0.0) & ~(lhs <= bound + rtol * scale)
    if bad.any():
        i = tuple(int(x) for x in np.argwhere(bad)[0])
        raise AssertionError(
            f"{int(bad.sum())} rebounds exceed the energy bound; first at {i}: "
            f"e_w = {result.e_w[i]!r}, final energy {lhs[i]!r} J > bound {bound[i]!r} J "
            f"(scale {scale[i]!r} J), stage {result.stage[i]}, path {result.path[i]}"
        )


def swap_path(path):
    """Path flags seen from the other side: i <-> j."""
    p = np.asarray(path).astype(np.int64)
    i_j = int(at.Path.APPROACH_I_STOPS), int(at.Path.APPROACH_J_STOPS)
    s_ij = int(at.Path.SEPARATION_I_STOPS), int(at.Path.SEPARATION_J_STOPS)
    keep = p & ~(i_j[0] | i_j[1] | s_ij[0] | s_ij[1])
    out = keep.copy()
    out |= np.where(p & i_j[0], i_j[1], 0)
    out |= np.where(p & i_j[1], i_j[0], 0)
    out |= np.where(p & s_ij[0], s_ij[1], 0)
    out |= np.where(p & s_ij[1], s_ij[0], 0)
    return out


#: Dvoretzky-Kiefer-Wolfowitz: P(sup|F_n - F| > eps) <= 2 exp(-2 n eps^2). At
#: ``DKW_ALPHA = 1e-6`` a correct sampler fails the bound once in a million runs
#: (``tests/test_uncertainty.py`` and ``tests/test_uncertainty_sampling.py`` use it).
DKW_ALPHA = 1e-6


def dkw_eps(n: int) -> float:
    """The DKW bound on the sup distance of ``n`` samples' empirical CDF at ``DKW_ALPHA``."""
    return math.sqrt(math.log(2.0 / DKW_ALPHA) / (2.0 * n))


def ks_sup(x: np.ndarray, cdf) -> float:
    """Kolmogorov-Smirnov distance of the samples ``x`` from the law with CDF ``cdf``."""
    x = np.sort(x)
    f = cdf(x)
    n = x.size
    return float(max(np.max(np.arange(1, n + 1) / n - f), np.max(f - np.arange(n) / n)))


#: The closed-form tiers whose invariants ``test_invariants.py`` and ``test_stability.py``
#: assert: the published model and the default, frame-consistent tier. Those modules run
#: every test once per tier (``pytestmark = pytest.mark.usefixtures("closed_form_tier")``)
#: and collide through :func:`tier_collide`.
CLOSED_FORM_TIERS = ("paper", "relative")
_TIER_UNDER_TEST = {"mode": None}


@pytest.fixture(scope="module", params=CLOSED_FORM_TIERS)
def closed_form_tier(request):
    """The tier a module's tests run in (module-scoped, so hypothesis sees no
    function-scoped fixture)."""
    _TIER_UNDER_TEST["mode"] = request.param
    yield request.param
    _TIER_UNDER_TEST["mode"] = None


def tier_collide(*args, **kwargs):
    """``agglomtool.collide`` in the tier under test; an explicit ``mode=`` wins."""
    if _TIER_UNDER_TEST["mode"] is None:
        raise RuntimeError("tier_collide needs the closed_form_tier fixture")
    kwargs.setdefault("mode", _TIER_UNDER_TEST["mode"])
    return at.collide(*args, **kwargs)


@pytest.fixture(scope="session")
def checks():
    """The helpers of this module, for the test files (no import of conftest needed)."""
    return SimpleNamespace(
        case_water=case_water,
        case_slag=case_slag,
        reference_e_w=reference_e_w,
        assert_energy_close=assert_energy_close,
        energy_terms=energy_terms,
        assert_energy_bound=assert_energy_bound,
        swap_path=swap_path,
        wet_mass=wet_mass,
        reduced_mass=reduced_mass,
        ln_f=_ln_f,
        ENERGY_RTOL=ENERGY_RTOL,
    )
