"""Fidelity of every model tier against the integrated truth (mode "ode"), and its cost.

Run ``python benchmarks/fidelity.py``. Writes under ``benchmarks/results/``:

- ``fidelity.csv``: per tier, time per collision and errors in ``e_w`` (max, RMS, max in the
  band 0.8-1.25 u0*) and in ``u0*`` against "ode";
- ``fidelity_scenes.csv``: per scene, ``u0*`` of every tier and the work fractions of the
  optional terms at ``u0*``;
- ``fidelity.png``: time per collision against error, per tier;
- ``fidelity.md``: the tables as Markdown, with the convergence check of "ode".

Scenes (``benchmarks/scenes.py``): the paper's cases I and II at beta = 0, 45, 90 deg; the
Table 3 variations at beta = 0 and 90 deg; a 1.74 mm glass sphere on a plate under 20-100 um
water films; melts of 1e3-1e6 Pa s. Each at 120 head-on speeds from 0.5 to 10 times its
"ode" critical speed (geometric). Times are kernel times on the flat arrays of the whole
suite repeated 20 times (best of 3 runs, both cores), without the API's input preparation;
the machine may be shared, so compare the tiers' times with each other.
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import numpy as np

import agglomtool as at
from agglomtool.collision.auto import TIER_ODE, auto_batch, ode_options, ode_rtol
from agglomtool.collision.ode import ode_batch
from agglomtool.collision.outcome import DETAIL_NAMES
from agglomtool.collision.tiers import TIERS

sys.path.insert(0, str(Path(__file__).parent))
from scenes import all_scenes  # noqa: E402

RESULTS = Path(__file__).parent / "results"
FACTORS = np.geomspace(0.5, 10.0, 120)
BAND = (0.8, 1.25)
TIERS_COMPARED = ("stokes", "paper", "relative", "ode_selfconsistent", "auto")
TOL = 0.01


TIME_REPEAT = 20


def best_time(fn, repeats=3):
    fn()  # compile / warm up
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return best


def build_suite(scenes):
    u_star = np.array([float(at.critical_impact_speed(**s.kwargs(), mode="ode"))
                       for s in scenes])
    parts = [s.kernel_inputs(u * FACTORS) for s, u in zip(scenes, u_star, strict=True)]
    arrays = [np.ascontiguousarray(np.concatenate([p[k] for p in parts])) for k in range(13)]
    factor = np.tile(FACTORS, len(scenes))
    scene_id = np.repeat(np.arange(len(scenes)), FACTORS.size)
    return arrays, factor, scene_id, u_star


def convergence(scenes):
    """Largest change of e_w when both tolerances are halved, on the paper's cases."""
    out = {}
    paper = [s for s in scenes if s.group == "paper cases"]
    for rtol in (1e-6, 1e-8, 1e-10):
        diffs = []
        for s in paper:
            u = float(at.critical_impact_speed(**s.kwargs(), mode="ode"))
            args = s.kernel_inputs(u * FACTORS)
            e1 = ode_batch(args, rtol=rtol, atol=1e-2 * rtol)[0]
            e2 = ode_batch(args, rtol=rtol / 2, atol=0.5e-2 * rtol)[0]
            diffs.append(np.abs(e1 - e2).max())
        out[rtol] = max(diffs)
    return out


def main():
    RESULTS.mkdir(exist_ok=True)
    scenes = all_scenes()
    arrays, factor, scene_id, u_star_ode = build_suite(scenes)
    n = arrays[0].size
    big = [np.ascontiguousarray(np.tile(a, TIME_REPEAT)) for a in arrays]
    n_big = big[0].size
    e_ode, _, _, det_ode, steps = ode_batch(arrays, details=True)
    t_ode = best_time(lambda: ode_batch(big)) / n_big
    band = (factor >= BAND[0]) & (factor <= BAND[1])

    rows = [dict(tier="ode", time_us=t_ode * 1e6, speedup_vs_ode=1.0, max_err=0.0,
                 rms_err=0.0, band_max_err=0.0, u0_max_rel_err=0.0, u0_rms_rel_err=0.0,
                 ode_fraction=1.0)]
    u_stars = {"ode": u_star_ode}
    for name in TIERS_COMPARED:
        tier = TIERS[name]
        e_w = tier(arrays)[0]
        t = best_time(lambda tier=tier: tier(big)) / n_big
        err = np.abs(e_w - e_ode)
        u_t = np.array([float(at.critical_impact_speed(**s.kwargs(), mode=name))
                        for s in scenes])
        u_stars[name] = u_t
        rel = u_t / u_star_ode - 1.0
        frac = np.nan
        if name == "auto":
            tier_used = auto_batch(arrays, tol=TOL)[4]
            frac = float(np.mean(tier_used == TIER_ODE))
        rows.append(dict(tier=name, time_us=t * 1e6, speedup_vs_ode=t_ode / t,
                         max_err=err.max(), rms_err=np.sqrt(np.mean(err**2)),
                         band_max_err=err[band].max(), u0_max_rel_err=np.abs(rel).max(),
                         u0_rms_rel_err=np.sqrt(np.mean(rel**2)), ode_fraction=frac))
    # Auto against ode at the integration tolerance and steps auto itself uses inside.
    rtol_in = ode_rtol(TOL)
    t_ode_loose = best_time(lambda: ode_batch(big, **ode_options(rtol_in))) / n_big

    with open(RESULTS / "fidelity.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})

    # Per scene: u0* of every tier; work fractions of the optional terms at 1.0 u0*.
    k_body = DETAIL_NAMES.index("W_body_frac")
    k_vol = DETAIL_NAMES.index("W_volcorr_frac")
    at_star = np.argmin(np.abs(np.log(FACTORS)))
    scene_rows = []
    for q, s in enumerate(scenes):
        row = dict(scene=s.name, group=s.group)
        for name, u in u_stars.items():
            row[f"u0_{name}"] = f"{u[q]:.6g}"
        for name in u_stars:
            if name != "ode":
                row[f"err_{name}_pct"] = f"{100 * (u_stars[name][q] / u_star_ode[q] - 1):.3g}"
        i = q * FACTORS.size + at_star
        row["body_work_frac"] = f"{det_ode[i, k_body]:.3g}"
        row["volcorr_work_frac"] = f"{det_ode[i, k_vol]:.3g}"
        scene_rows.append(row)
    with open(RESULTS / "fidelity_scenes.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(scene_rows[0]))
        wr.writeheader()
        wr.writerows(scene_rows)

    conv = convergence(scenes)
    plot(rows)
    write_markdown(rows, scene_rows, conv, n, steps, t_ode_loose, scenes, u_stars)
    for r in rows:
        print({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()})
    print("convergence (halving rtol, atol):", conv)
    print(f"ode at rtol {ode_rtol(TOL):g}, auto's settings: {t_ode_loose * 1e6:.3g} us per "
          "collision")


def plot(rows):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    floor = 1e-9
    for r in rows:
        x = r["time_us"]
        ax.scatter(x, max(r["max_err"], floor), marker="o", color="C0")
        ax.scatter(x, max(r["rms_err"], floor), marker="s", color="C1")
        ax.annotate(r["tier"], (x, max(r["max_err"], floor)), textcoords="offset points",
                    xytext=(4, 4), fontsize=8)
    ax.axhline(TOL, color="grey", ls=":", lw=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("kernel time per collision [us] (2 cores)")
    ax.set_ylabel("|e_w - e_w(ode)| (circles: max, squares: RMS)")
    ax.set_title("Model tiers: cost against error (ode at the floor 1e-9)")
    fig.tight_layout()
    fig.savefig(RESULTS / "fidelity.png", dpi=120)


def write_markdown(rows, scene_rows, conv, n, steps, t_ode_loose, scenes, u_stars):
    lines = [
        "# Fidelity of the model tiers against the integrated truth",
        "",
        f"{len(scenes)} scenes x {FACTORS.size} speeds (0.5-10 u0*, geometric) = {n} "
        f"collisions. Errors in e_w against mode \"ode\" (rtol 1e-10); band = "
        f"{BAND[0]}-{BAND[1]} u0*; u0* errors relative, over the scenes. Produced by "
        "`benchmarks/fidelity.py`.",
        "",
        "| tier | time/collision [us] | max err | RMS err | band max err | "
        "u0* max rel err | u0* RMS rel err | share sent to ode |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['tier']} | {r['time_us']:.3g} | {r['max_err']:.3g} | {r['rms_err']:.3g} | "
            f"{r['band_max_err']:.3g} | {r['u0_max_rel_err']:.3g} | "
            f"{r['u0_rms_rel_err']:.3g} | "
            f"{'' if np.isnan(r['ode_fraction']) else format(r['ode_fraction'], '.3f')} |"
        )
    auto = next(r for r in rows if r["tier"] == "auto")
    ode = rows[0]
    lines += [
        "",
        f"auto (tol = {TOL}) costs {auto['time_us'] / ode['time_us']:.1%} of ode everywhere "
        f"(rtol 1e-10), {auto['time_us'] / (t_ode_loose * 1e6):.1%} of ode everywhere at "
        f"rtol {ode_rtol(TOL):g} with the settings auto uses inside (steps and stick stop).",
        "",
        f"ode steps per collision: median {np.median(steps):.0f}, max {steps.max()}.",
        "Convergence of ode (largest change of e_w on the paper's cases when rtol and atol "
        "are halved): " + ", ".join(f"rtol {k:g}: {v:.2g}" for k, v in conv.items()) + ".",
        "",
        "## Critical impact speed per scene",
        "",
        "| scene | u0* ode [m/s] | " + " | ".join(f"{k} err %" for k in u_stars if k != "ode")
        + " | body work / K0 | vol.-corr. work / K0 |",
        "|---|---|" + "---|" * (len(u_stars) - 1) + "---|---|",
    ]
    for r in scene_rows:
        lines.append(
            f"| {r['scene']} | {r['u0_ode']} | "
            + " | ".join(r[f"err_{k}_pct"] for k in u_stars if k != "ode")
            + f" | {r['body_work_frac']} | {r['volcorr_work_frac']} |"
        )
    (RESULTS / "fidelity.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
