"""Built-in examples: the paper's reference cases, ready to evaluate.

Shabanian et al. (2024), Heliyon 10:e29397, doi:10.1016/j.heliyon.2024.e29397, Table 2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .api import collide, critical_impact_speed
from .inputs import Bed, Gas, Liquid, Particle

__all__ = ["ReferenceCase", "reference_cases"]


@dataclass(frozen=True)
class ReferenceCase:
    """One of the paper's Table 2 cases: identical particles, head-on."""

    name: str
    particle: Particle
    liquid: Liquid
    gas: Gas
    bed: Bed
    e: float
    published_u_star: float  # Section 3.1 [m/s]

    def critical_impact_speed(self, beta_deg=0.0, mode="paper"):
        """u0* [m/s] at ``beta_deg``."""
        return critical_impact_speed(
            self.particle, self.particle, liquid=self.liquid, gas=self.gas, bed=self.bed,
            beta_deg=beta_deg, e=self.e, mode=mode,
        )

    def collide(self, u0, beta_deg=0.0, mode="paper", **kwargs):
        """:func:`agglomtool.collide` for this case."""
        return collide(
            self.particle, self.particle, liquid=self.liquid, gas=self.gas, bed=self.bed,
            u0=u0, beta_deg=beta_deg, e=self.e, mode=mode, **kwargs,
        )

    def report(self, beta_deg=(0.0, 45.0, 90.0), mode="paper") -> str:
        """A text table: u0* per angle, and e_w at multiples of u0*."""
        beta = np.atleast_1d(np.asarray(beta_deg, dtype=float))
        u_star = np.atleast_1d(self.critical_impact_speed(beta, mode))
        factors = np.array([0.9, 1.1, 1.5, 2.0, 5.0])
        lines = [
            f"{self.name}: mu_l = {float(self.liquid.mu):g} Pa s, "
            f"gamma = {float(self.liquid.gamma):g} N/m, h0 = {float(self.particle.h0) * 1e6:g} um"
            f" (mode {mode}; paper: u0* = {self.published_u_star} m/s at beta = 0)",
            "  beta [deg]   u0* [m/s]   Ca(u0*)   e_w at u0 = "
            + "  ".join(f"{f:g}u0*" for f in factors),
        ]
        for b, us in zip(beta, u_star, strict=True):
            ca = float(self.liquid.mu) * 2.0 * us / float(self.liquid.gamma)
            r = self.collide(us * factors, beta_deg=b, mode=mode, details=False)
            ew = "  ".join(f"{x:6.3f}" for x in r.e_w)
            lines.append(f"  {b:10.1f}   {us:9.5f}   {ca:7.3g}   {ew}")
        return "\n".join(lines)


def reference_cases() -> list[ReferenceCase]:
    """Table 2's case I (water) and case II (hypothetical slag)."""
    bed = Bed(eps=0.55, U=None)  # U = 1.1 x Wen-Yu Umf (Section 3.1)
    water = ReferenceCase(
        name="Case I, water, 25 C",
        particle=Particle(d=1000e-6, rho=2650.0, h0=5.00e-6, ha=0.10e-6),
        liquid=Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0, name="water"),
        gas=Gas(mu=18.48e-6, rho=1.168, name="air, 25 C, 1 bar"),
        bed=bed, e=0.9, published_u_star=0.034,
    )
    slag = ReferenceCase(
        name="Case II, hypothetical slag, 800 C",
        particle=Particle(d=1000e-6, rho=2650.0, h0=0.15e-6, ha=0.10e-6),
        liquid=Liquid(mu=10.0, gamma=0.400, rho=2500.0, theta_deg=10.0, name="slag"),
        gas=Gas(mu=45.48e-6, rho=0.324, name="air, 800 C, 1 bar"),
        bed=bed, e=0.9, published_u_star=0.638,
    )
    return [water, slag]
