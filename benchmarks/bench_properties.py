"""Gas-property throughput and accuracy against CoolProp HEOS (prints figures; no asserts).

Run: python benchmarks/bench_properties.py
"""

from __future__ import annotations

import time

import CoolProp.CoolProp as CP
import numpy as np

from agglomtool.properties import gas_properties
from agglomtool.properties._gas_tables import SPECIES_FORMULAS

FLUE = {"N2": 0.75, "CO2": 0.15, "H2O": 0.06, "O2": 0.04}
HEOS_FLUE = "HEOS::Nitrogen[0.75]&CarbonDioxide[0.15]&Water[0.06]&Oxygen[0.04]"


def _states(n, rng):
    T = np.exp(rng.uniform(np.log(400.0), np.log(1900.0), n))
    P = np.exp(rng.uniform(np.log(5e4), np.log(2e6), n))
    return T, P


def _rate(fn, n_states, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return n_states / best


def main():
    rng = np.random.default_rng(0)
    for comp in ("air", FLUE):
        gas_properties(500.0, 1e5, comp)  # build the tables once (reported below)
    n = 1_000_000
    T, P = _states(n, rng)
    k = 2000
    Tk, Pk = T[:k], P[:k]
    print(f"CoolProp {CP.get_global_param_string('version')}; {n} random states, "
          "400-1900 K, 0.5-20 bar")
    for label, comp in (("air (pure, Lemmon)", "air"), ("flue gas (4 species)", FLUE)):
        fast_rate = _rate(lambda c=comp: gas_properties(T, P, c), n)
        ours_heos_rate = _rate(lambda c=comp: gas_properties(Tk, Pk, c, method="heos"), k, 1)
        fast = gas_properties(Tk, Pk, comp)
        ref = gas_properties(Tk, Pk, comp, method="heos")
        e_mu = np.max(np.abs(fast.mu / ref.mu - 1))
        e_rho = np.max(np.abs(fast.rho / ref.rho - 1))
        print(f"{label:24s} table: {fast_rate:10.3g} states/s; per-state HEOS: "
              f"{ours_heos_rate:8.3g} states/s; max rel. error vs HEOS mu {e_mu:.1e}, "
              f"rho {e_rho:.1e}")
    # CoolProp's own HEOS mixture, the slow reference: density and viscosity.
    m = 20
    t0 = time.perf_counter()
    ref_rho = np.array([CP.PropsSI("D", "T", t, "P", p, HEOS_FLUE) for t, p in zip(
        T[:m], P[:m], strict=True)])
    ref_mu = np.array([CP.PropsSI("V", "T", t, "P", p, HEOS_FLUE) for t, p in zip(
        T[:m], P[:m], strict=True)])
    rate = 2 * m / (time.perf_counter() - t0)
    ours = gas_properties(T[:m], P[:m], FLUE)
    print(f"{'CoolProp HEOS mixture':24s} PropsSI: {rate:10.3g} calls/s; ours vs it: rho max "
          f"{np.max(np.abs(ours.rho / ref_rho - 1)):.1e}, mu max "
          f"{np.max(np.abs(ours.mu / ref_mu - 1)):.1e} (CoolProp's mixture viscosity is "
          "a rough estimate)")
    print("table build times are paid once per species (then cached on disk; "
          f"{len(SPECIES_FORMULAS)} species)")


if __name__ == "__main__":
    main()
