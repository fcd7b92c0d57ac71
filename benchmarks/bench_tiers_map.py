"""What the default tier costs on operating maps: one map per tier, best and median of 5.

The tool's default tier is "auto" unless it is more than 3x slower than "relative" on maps,
in which case "relative" (agglomtool._fields.DEFAULT_MODE says which, and why). Two maps:
water on 300 um sand (U/Umf x h0 x beta, 1e5 points) and the viscous K-silicate melt
(T x h0 x U/Umf, 3e4 points).

    python3 benchmarks/bench_tiers_map.py
"""

import time, numpy as np, os, agglomtool as at
s = at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
grid = dict(U_Umf=np.linspace(1.2, 8, 100), h0=np.geomspace(1e-6, 30e-6, 100), beta_deg=np.linspace(-90, 90, 10))
for mode in ["relative", "auto", "paper"]:
    at.sweep(s.replace(mode=mode), U_Umf=[2.0, 3.0], h0=[5e-6])  # compile
res = {}
for _ in range(5):
    for mode in ["relative", "auto", "paper"]:
        t = time.perf_counter(); ds = at.sweep(s.replace(mode=mode), **grid); res.setdefault(mode, []).append(time.perf_counter() - t)
print("load", round(os.getloadavg()[0],2), {k: (round(min(v),3), round(sorted(v)[2],3)) for k, v in res.items()})
s2 = at.Scene(liquid="k-silicate-ash-melt", gas="biomass-flue-gas", h0=0.2e-6)
grid2 = dict(T=np.linspace(1073.15, 1673.15, 100), h0=np.geomspace(0.05e-6, 2e-6, 100), U_Umf=[2.0, 4.0, 8.0])
res = {}
for _ in range(3):
    for mode in ["relative", "auto", "paper"]:
        t = time.perf_counter(); ds = at.sweep(s2.replace(mode=mode), **grid2); res.setdefault(mode, []).append(time.perf_counter() - t)
print("melt map load", round(os.getloadavg()[0],2), {k: (round(min(v),3), round(sorted(v)[1],3)) for k, v in res.items()})
