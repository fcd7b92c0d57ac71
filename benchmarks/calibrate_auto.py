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


def main():
    from agglomtool.collision.auto import ODE_STEPS, closed_form_indicator_lean
    from agglomtool.collision.ode import ode_batch
    from agglomtool.collision.relative import run_relative

    arrs, factor, scene = measure()
    n = arrs[0].size
    print(f"{scene.max() + 1} scenes with a finite critical speed, {n} collisions")
    truth = ode_batch(*arrs)[0]
    e_rel = run_relative(*arrs)[0]
    g = np.array([closed_form_indicator_lean(*[float(a[q]) for a in arrs])[3]
                  for q in range(n)])
    reb = (e_rel > 0) & np.isfinite(g) & (g > 0)
    ratio = np.abs(e_rel - truth)[reb] / g[reb]
    gr = g[reb]
    print("closed forms: largest |e_w(relative) - e_w(ode)| / g")
    for lo, hi in ((1e-6, 1e-3), (1e-3, 1e-2), (1e-2, 0.05), (0.05, 0.1), (0.1, 1.0)):
        m = (gr >= lo) & (gr < hi)
        if m.any():
            print(f"  g in [{lo:g}, {hi:g}): {ratio[m].max():.3f} ({m.sum()} rebounds)")
    print(f"ode inside auto (steps {ODE_STEPS}): largest |k - k(ode)| / rtol "
          "with k = e_w^2, and largest |e_w - e_w(ode)|")
    k_t = truth * truth
    for rtol in RTOLS:
        e_l, _, _, _, steps = ode_batch(*arrs, rtol=rtol, atol=1e-2 * rtol, **ODE_STEPS)
        dk = np.abs(e_l * e_l - k_t)
        flips = int(np.sum((e_l > 0) != (truth > 0)))
        print(f"  rtol {rtol:g}: {dk.max() / rtol:.3g}; e_w {np.abs(e_l - truth).max():.3g}; "
              f"outcome flips {flips}; mean steps {steps.mean():.1f}")
        e_d, _, _, _, steps_d = ode_batch(*arrs, rtol=rtol, atol=1e-2 * rtol)
        dk_d = np.abs(e_d * e_d - k_t)
        print(f"    (default steps, first 0.01 and no cap: {dk_d.max() / rtol:.3g}; e_w "
              f"{np.abs(e_d - truth).max():.3g}; mean steps {steps_d.mean():.1f})")


if __name__ == "__main__":
    main()
