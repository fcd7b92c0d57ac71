"""Measure the error of the closed-form tiers against mode "ode" on random scenes.

The error bounds of mode "auto" (:mod:`agglomtool.collision.auto`) come from this script:
``python benchmarks/calibrate_auto.py`` draws random collisions (seeded), evaluates them with
every tier, and prints the envelope of the errors against the indicators "auto" uses. The
random set is independent of the fidelity suite (``benchmarks/fidelity.py``), on which the
result is then checked.
"""

from __future__ import annotations

import numpy as np

import agglomtool as at
from agglomtool.pair import prepare_pair

N_SCENES = 400
SPEEDS = np.geomspace(0.3, 30.0, 60)  # multiples of the ode critical speed


def random_scenes(n, seed=20240611):
    """Random pairs, liquids, gases, beds and angles (arrays of length ``n``)."""
    rng = np.random.default_rng(seed)
    lu = lambda lo, hi: np.exp(rng.uniform(np.log(lo), np.log(hi), n))  # noqa: E731
    d_i, d_j = lu(200e-6, 3e-3), lu(200e-6, 3e-3)
    plate = rng.random(n) < 0.15
    d_j = np.where(plate, np.inf, d_j)
    rho_i, rho_j = rng.uniform(1000, 5000, n), np.where(plate, np.inf, rng.uniform(1000, 5000, n))
    ha_i, ha_j = lu(0.01e-6, 1e-6), lu(0.01e-6, 1e-6)
    h0_tot = (ha_i + ha_j) * lu(1.2, 500.0)
    split = rng.uniform(0.0, 1.0, n)
    hot = rng.random(n) < 0.5
    kw = dict(
        p_i=at.Particle(d=d_i, rho=rho_i, h0=split * h0_tot, ha=ha_i),
        p_j=at.Particle(d=d_j, rho=rho_j, h0=(1 - split) * h0_tot, ha=ha_j),
        liquid=at.Liquid(mu=lu(1e-3, 1e6), gamma=rng.uniform(0.02, 0.5, n),
                         rho=rng.uniform(800, 3000, n), theta_deg=rng.uniform(0, 60, n)),
        gas=at.Gas(mu=np.where(hot, 45.48e-6, 18.48e-6), rho=np.where(hot, 0.324, 1.168)),
        bed=at.Bed(eps=rng.uniform(0.4, 0.9, n)),
        beta_deg=rng.uniform(0, 90, n),
        e=rng.uniform(0.3, 1.0, n),
    )
    return kw


def kernel_arrays(kw, factors, u_star):
    """Flat kernel inputs for every scene at ``factors * u_star`` (scene-major)."""
    st = prepare_pair(kw["p_i"], kw["p_j"], kw["liquid"], kw["gas"], kw["bed"],
                      kw["beta_deg"], kw["e"], True, "emulsion")
    rep = lambda a: np.repeat(np.ravel(a), factors.size)  # noqa: E731
    u = (u_star[:, None] * factors[None, :]).ravel()
    names = ("m_i", "m_j", "r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta")
    arrs = [rep(getattr(st, k)) for k in names]
    arrs.append(u * rep(st.w_per_u0))
    arrs += [rep(getattr(st, k)) for k in ("fn_i", "fn_j", "e")]
    return [np.ascontiguousarray(a, dtype=float) for a in arrs]


def measure(n=N_SCENES):
    kw = random_scenes(n)
    u_star = at.critical_impact_speed(**kw, mode="ode")
    ok = np.isfinite(u_star) & (u_star > 0) & (u_star < 1e5)
    kw = {k: _take(v, ok) for k, v in kw.items()}
    u_star = u_star[ok]
    arrs = kernel_arrays(kw, SPEEDS, u_star)
    return arrs, np.tile(SPEEDS, u_star.size), np.repeat(np.arange(u_star.size), SPEEDS.size)


def _take(v, mask):
    if isinstance(v, np.ndarray):
        return v[mask]
    if hasattr(v, "__dataclass_fields__"):
        kw = {k: (np.broadcast_to(x, mask.shape)[mask] if isinstance(x, np.ndarray) and
                  x.ndim else x) for k, x in v.__dict__.items()}
        return type(v)(**kw)
    return v


RTOLS = (1e-7, 1e-6, 1e-5, 1e-4)
G_BINS = ((1e-6, 1e-3), (1e-3, 1e-2), (1e-2, 0.05), (0.05, 0.1), (0.1, 1.0))
PIECE_COUNTS = (2, 3, 4, 6, 8, 16, 32)
U_STAR_PIECES = (1, 4, 8, 16, 32)


def piecewise_envelope(arrs, truth):
    """Largest ``|e_w(pieces) - e_w(ode)| / g`` per band of ``g`` for each piece count,
    over the rebounds whose pieces are clear (the others are never trusted)."""
    from agglomtool.collision.auto import piecewise_batch

    print("piecewise closed forms: largest |e_w(n pieces) - e_w(ode)| / g over the clear "
          "rebounds")
    for n in PIECE_COUNTS:
        e, _, _, g, clear = piecewise_batch(arrs, n)
        reb = (e > 0) & np.isfinite(g) & (g > 0)
        ok = reb & clear
        ratio = np.abs(e - truth)[ok] / g[ok]
        parts = []
        for lo, hi in G_BINS:
            m = (g[ok] >= lo) & (g[ok] < hi)
            if m.any():
                parts.append(f"[{lo:g}, {hi:g}) {ratio[m].max():.3f} ({m.sum()})")
        print(f"  n = {n}: " + "; ".join(parts) + f"; not clear {int((reb & ~clear).sum())}")


def piecewise_critical_ratios(arrs, factor):
    """Per scene the critical speed of the piecewise closed forms over that of "ode"
    (bisection in the speed; the scenes' speeds are multiples of the "ode" one), the
    largest over all scenes and over those whose threshold is not a viscous stop in the
    separation while the body force pulls the pair apart (such sticks are never trusted,
    module docstring of agglomtool.collision.auto)."""
    from agglomtool.collision._codes import SEP_VIS
    from agglomtool.collision.auto import piecewise_batch
    from agglomtool.collision.relative import relative_body_force

    one = factor == factor[0]
    base = [a[one].copy() for a in arrs]
    base[9] = base[9] / factor[0]  # each scene at its "ode" critical speed
    f_b = np.array([relative_body_force(*(float(base[k][q]) for k in (0, 1, 10, 11)))
                    for q in range(base[0].size)])
    print("critical speeds: largest u*(n pieces) / u*(ode) over all scenes, and over those "
          "not at an assisted viscous stop")
    for n in U_STAR_PIECES:
        def run(f, n=n):
            b = list(base)
            b[9] = base[9] * f
            return piecewise_batch(b, n)

        lo = np.full(base[0].size, SPEEDS[0])
        hi = np.full(base[0].size, SPEEDS[-1])
        ok = (run(lo)[0] == 0) & (run(hi)[0] > 0)
        for _ in range(60):
            mid = np.sqrt(lo * hi)
            reb = run(mid)[0] > 0
            hi = np.where(reb, mid, hi)
            lo = np.where(reb, lo, mid)
        assisted = (run(lo)[1] == SEP_VIS) & (f_b < 0)
        print(f"  n = {n}: {hi[ok].max():.4f}, {hi[ok & ~assisted].max():.4f} "
              f"({int(ok.sum())} scenes, {int((ok & assisted).sum())} assisted)")


def main():
    from agglomtool.collision.auto import ODE_STEPS, closed_form_indicator_lean, ode_options
    from agglomtool.collision.ode import ode_batch
    from agglomtool.collision.records import TierInputs, pair_at
    from agglomtool.collision.relative import run_relative

    arrs, factor, scene = measure()
    n = arrs[0].size
    print(f"{scene.max() + 1} scenes with a finite critical speed, {n} collisions")
    truth = ode_batch(arrs)[0]
    e_rel = run_relative(arrs)[0]
    ins = TierInputs(*arrs)
    g = np.array([closed_form_indicator_lean(pair_at.py_func(ins, q), float(ins.w[q]))[3]
                  for q in range(n)])
    reb = (e_rel > 0) & np.isfinite(g) & (g > 0)
    ratio = np.abs(e_rel - truth)[reb] / g[reb]
    gr = g[reb]
    print("closed forms: largest |e_w(relative) - e_w(ode)| / g")
    for lo, hi in G_BINS:
        m = (gr >= lo) & (gr < hi)
        if m.any():
            print(f"  g in [{lo:g}, {hi:g}): {ratio[m].max():.3f} ({m.sum()} rebounds)")
    piecewise_envelope(arrs, truth)
    piecewise_critical_ratios(arrs, factor)
    print(f"ode inside auto (steps {ODE_STEPS}, stick stop): largest |k - k(ode)| / rtol "
          "with k = e_w^2, and largest |e_w - e_w(ode)|")
    k_t = truth * truth
    for rtol in RTOLS:
        e_l, _, _, _, steps = ode_batch(arrs, **ode_options(rtol))
        dk = np.abs(e_l * e_l - k_t)
        flips = int(np.sum((e_l > 0) != (truth > 0)))
        print(f"  rtol {rtol:g}: {dk.max() / rtol:.3g}; e_w {np.abs(e_l - truth).max():.3g}; "
              f"outcome flips {flips}; mean steps {steps.mean():.1f}")
        e_d, _, _, _, steps_d = ode_batch(arrs, rtol=rtol, atol=1e-2 * rtol)
        dk_d = np.abs(e_d * e_d - k_t)
        print(f"    (default steps, first 0.01 and no cap: {dk_d.max() / rtol:.3g}; e_w "
              f"{np.abs(e_d - truth).max():.3g}; mean steps {steps_d.mean():.1f})")


if __name__ == "__main__":
    main()
