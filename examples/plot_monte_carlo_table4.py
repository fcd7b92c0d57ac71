"""
Monte Carlo: the paper's uncertainty analyses (Table 4, Figs. 10-11)
====================================================================

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Section 3.4,
Table 4, Figs. 10-11 and S.4-S.6. For water (capillary-limited) and slag (viscous-limited),
at the mean impact speeds giving ``e_w`` about 0.52 and about 0.20, this example

1. runs the reference analysis (nine normal inputs at Table 4's reference standard
   deviations) and one analysis per alternative standard deviation (one input group
   changed, the others at reference: the paper's design), draws the densities of ``e_w``
   like Figs. 10-11, and measures how far each alternative moves the distribution
   (Wasserstein-1 distance to the reference run; every run shares its random numbers, so
   only the changed group differs);
2. ranks the input groups by one-at-a-time spread and by Sobol total index (SALib);
3. checks convergence with N/2, N and 5 N samples (Fig. S.4).

The gallery runs it with N = 1e5 samples per run (set by the environment variable
``AGGLOMTOOL_EXAMPLE_SAMPLES``); the paper's size, N = 1e6 (about a minute)::

    python examples/plot_monte_carlo_table4.py     # PNGs in examples/output/
"""

# %%
# Set-up
# ------
# :func:`agglomtool.uncertainty.table4_case` gives each of the paper's analyses as ready
# inputs of :func:`agglomtool.monte_carlo` (particles, liquid, gas, bed, speed and the
# uncertain inputs with their normal laws, truncated at physical bounds).
import matplotlib.pyplot as plt
import numpy as np
from _output import samples, save

from agglomtool.uncertainty import (
    TABLE4,
    TABLE4_GROUPS,
    TABLE4_U0,
    monte_carlo,
    sobol_indices,
    spread_by_input,
    table4_case,
)

N = samples(1_000_000)  # samples per run; the paper used 1e6
# Sobol base sample, a power of 2: 2**15 at N = 1e6 (4.6e5 model runs per analysis).
N_BASE = 2 ** max(6, round(np.log2(N / 32)))
SEED = 2024
EDGES = np.linspace(0.0, 0.9, 181)  # e_w bins of 0.005 on [0, e]
PANELS = {"d": "a) solid diameters", "ha": "b) asperity heights",
          "h0": "c) coating thicknesses", "mu_l": "d) liquid viscosity",
          "gamma": "e) surface tension", "u0": "f) impact speed u0"}
# How Table 4 states each group's sd: (factor from SI, unit).
SHOWN = {"d": (1e6, "um"), "ha": (1e6, "um"), "h0": (1e6, "um"), "mu_l": (1.0, "Pa s"),
         "gamma": (1.0, "N/m"), "u0": (1.0, "m/s")}
# Section 3.4's reading of Figs. 10-11, strongest first.
PAPER_TIERS = {
    "water": (("u0",), ("mu_l", "gamma"), ("d", "ha", "h0")),
    "slag": (("h0", "ha"), ("mu_l", "u0"), ("gamma", "d")),
}


def wasserstein1(a: np.ndarray, b: np.ndarray) -> float:
    """Wasserstein-1 distance between two equal-size samples [-]."""
    return float(np.mean(np.abs(np.sort(a) - np.sort(b))))


def sds(case: str, target: float, group: str):
    row = TABLE4_U0[case][target] if group == "u0" else TABLE4[case][group]
    return row[1], row[2]


def paper_design(case: str, target: float) -> dict:
    """Reference run plus one run per alternative sd; figure and distances."""
    ref = monte_carlo(**table4_case(case, target), n=N, seed=SEED, bins=EDGES)
    ew_ref = ref["e_w"].values
    print(f"\n=== {case}, e_w at the mean inputs = {float(ref['e_w_nominal']):.4f} "
          f"(paper: about {target}), u0 = {TABLE4_U0[case][target][0]} m/s, n = {N:,}")
    print(f"reference: P(agglomeration) = {float(ref['p_agglomeration']):.4f}, "
          f"mean e_w = {float(ref['e_w_mean']):.4f}, sd = {float(ref['e_w_std']):.4f}, "
          f"5/50/95 % = {np.round(ref['e_w_quantile'].sel(quantile=[0.05, 0.5, 0.95]).values, 4)}"
          f", resampled draws: {ref.attrs['n_resampled_total']}")
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5), sharex=True)
    moved = {}
    print(f"{'group':6s} {'sd':>10s} {'sd(e_w)':>8s} {'P_agg':>7s} {'W1 to ref':>9s}")
    for ax, (group, title) in zip(axes.ravel(), PANELS.items(), strict=True):
        sd_ref, alts = sds(case, target, group)
        x = ref["e_w_bin"].values
        f, unit = SHOWN[group]
        ax.plot(x, ref["e_w_density"].values, "k-", lw=1.5,
                label=f"sd {sd_ref * f:.3g} {unit} (ref), "
                      f"P_agg {float(ref['p_agglomeration']):.3f}")
        dist = []
        for sd_alt in alts:
            ds = monte_carlo(**table4_case(case, target, alternative={group: sd_alt}), n=N,
                             seed=SEED, bins=EDGES)
            w1 = wasserstein1(ds["e_w"].values, ew_ref)
            dist.append(w1)
            ax.plot(x, ds["e_w_density"].values, lw=1.0,
                    label=f"sd {sd_alt * f:.3g} {unit}, "
                          f"P_agg {float(ds['p_agglomeration']):.3f}")
            print(f"{group:6s} {sd_alt:10.3g} {float(ds['e_w_std']):8.4f} "
                  f"{float(ds['p_agglomeration']):7.4f} {w1:9.4f}")
        moved[group] = max(dist)
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7)
        ax.set_ylabel("probability density of rebounding e_w [-]")
    for ax in axes[1]:
        ax.set_xlabel("e_w [-]")
    fig.suptitle(f"{case}: e_w = {float(ref['e_w_nominal']):.2f} at the mean inputs "
                 f"(Table 4, {N:,} samples; P_agg is the point mass at e_w = 0)")
    fig.tight_layout()
    name = f"fig{10 if case == 'water' else 11}_{case}_ew{int(round(100 * target)):03d}.png"
    save(fig, name[:-4], dpi=110)
    print("largest W1 per group (paper's design): "
          + ", ".join(f"{g} {v:.4f}" for g, v in sorted(moved.items(), key=lambda t: -t[1])))
    return moved


def tier_violations(values: dict, tiers) -> list[str]:
    """Pairs (a, b) where the paper puts a in a higher tier than b but a <= b here."""
    bad = []
    for i in range(len(tiers) - 1):
        below = [g for t in tiers[i + 1:] for g in t]
        bad += [f"{a} ({values[a]:.4g}) <= {b} ({values[b]:.4g})"
                for a in tiers[i] for b in below if values[a] <= values[b]]
    return bad


def rankings(case: str, target: float, moved: dict) -> None:
    kw = table4_case(case, target)
    oat = spread_by_input(**kw, groups=TABLE4_GROUPS, n=N // 5, seed=SEED)
    sob = sobol_indices(**kw, groups=TABLE4_GROUPS, n_base=N_BASE, seed=SEED)
    std = dict(zip(oat["factor"].values.tolist(), oat["e_w_std"].values, strict=True))
    print(f"{'group':6s} {'OAT sd(e_w)':>11s} {'S1':>7s} {'+-':>6s} {'ST':>7s} {'+-':>6s}")
    for i, g in enumerate(sob["factor"].values.tolist()):
        print(f"{g:6s} {std[g]:11.4f} {float(sob['S1'][i]):7.3f} "
              f"{float(sob['S1_conf'][i]):6.3f} {float(sob['ST'][i]):7.3f} "
              f"{float(sob['ST_conf'][i]):6.3f}")
    st = dict(zip(sob["factor"].values.tolist(), sob["ST"].values, strict=True))
    print(f"({sob.attrs['n_model_runs']:,} model runs for Sobol; all-uncertain sd(e_w) = "
          f"{float(oat['e_w_std_all']):.4f})")
    for label, vals in (("one-at-a-time sd", std), ("Sobol ST", st),
                        ("paper design W1", moved)):
        order = " > ".join(sorted(vals, key=lambda g: -vals[g]))
        bad = tier_violations(vals, PAPER_TIERS[case])
        ok = "agrees with" if not bad else "differs from (" + "; ".join(bad) + ")"
        print(f"  {label:17s}: {order}   -> {ok} the paper's tiers "
              f"{' > '.join('{' + ', '.join(t) + '}' for t in PAPER_TIERS[case])}")


def convergence(case: str) -> None:
    """Fig. S.4: N/2, N and 5 N samples (independent seeds), reference sds."""
    print(f"\n=== convergence, {case}, e_w about 0.52")
    runs = {}
    for n, seed in ((N // 2, 1), (N, 2), (5 * N, 3)):
        runs[n] = monte_carlo(**table4_case(case, 0.52), n=n, seed=seed, bins=EDGES,
                              keep_samples=False)
    big = runs[5 * N]
    width = np.diff(EDGES)
    peak = float(big["e_w_density"].max())
    fig, ax = plt.subplots(figsize=(6, 4))
    for n, ds in runs.items():
        dens = ds["e_w_density"].values
        tv = 0.5 * (np.sum(np.abs(dens - big["e_w_density"].values) * width)
                    + abs(float(ds["p_agglomeration"] - big["p_agglomeration"])))
        q = ds["e_w_quantile"].sel(quantile=[0.05, 0.5, 0.95]).values
        print(f"n = {n:>9,}: P_agg = {float(ds['p_agglomeration']):.4f} "
              f"+- {float(ds['p_agglomeration_se']):.4f}, mean = {float(ds['e_w_mean']):.4f}, "
              f"sd = {float(ds['e_w_std']):.4f}, 5/50/95 % = {np.round(q, 4)}, "
              f"max|density - density(5 N)|/peak = "
              f"{np.max(np.abs(dens - big['e_w_density'].values)) / peak:.4f}, "
              f"total variation to 5 N = {tv:.4f}")
        ax.plot(ds["e_w_bin"].values, dens, lw=1.0, label=f"n = {n:,}")
    ax.set_xlabel("e_w [-]")
    ax.set_ylabel("probability density of rebounding e_w [-]")
    ax.set_title(f"{case}: sample-size convergence (cf. Fig. S.4)")
    ax.legend()
    fig.tight_layout()
    save(fig, f"figS4_convergence_{case}", dpi=110)


# %%
# Water (case I), e_w about 0.52
# ------------------------------
# Impact speed dominates under capillary-limited conditions.
moved = paper_design("water", 0.52)
rankings("water", 0.52, moved)

# %%
# Water (case I), e_w about 0.20
# ------------------------------
moved = paper_design("water", 0.20)
rankings("water", 0.20, moved)

# %%
# Slag (case II), e_w about 0.52
# ------------------------------
# Coating thickness and asperity height dominate under viscous-limited conditions.
moved = paper_design("slag", 0.52)
rankings("slag", 0.52, moved)

# %%
# Slag (case II), e_w about 0.20
# ------------------------------
moved = paper_design("slag", 0.20)
rankings("slag", 0.20, moved)

# %%
# Convergence with the sample size (Fig. S.4)
# -------------------------------------------
for case in ("water", "slag"):
    convergence(case)
