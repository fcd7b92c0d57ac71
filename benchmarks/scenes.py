"""Scenes of the fidelity benchmark and of the calibration of mode "auto".

Each scene is one pair of particles, a liquid, a gas and a bed at one collision angle; the
kernels' inputs come from :func:`agglomtool.pair.prepare_pair` (the same path as the API).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import agglomtool as at
from agglomtool.pair import prepare_pair

#: Kernel input names in tier order (w between theta and fn_i).
STATE_NAMES = ("m_i", "m_j", "r", "H0", "Ha", "mu_l", "gamma", "cos_t", "theta")
FORCE_NAMES = ("fn_i", "fn_j", "e")

WATER = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0, name="water 25 C")
AIR_25C = at.Gas(mu=18.48e-6, rho=1.168, name="air 25 C, 1 bar (Table 2)")
AIR_800C = at.Gas(mu=45.48e-6, rho=0.324, name="air 800 C, 1 bar (Table 2)")


def slag(mu=10.0):
    """The paper's slag (Table 2) with viscosity ``mu`` [Pa s]."""
    return at.Liquid(mu=mu, gamma=0.4, rho=2500.0, theta_deg=10.0, name=f"slag {mu:g} Pa s")


def silica(h0, ha=0.1e-6, d=1000e-6, rho=2650.0):
    return at.Particle(d=d, rho=rho, h0=h0, ha=ha)


@dataclass
class Scene:
    """One collision geometry: ``kwargs`` for :func:`agglomtool.collide`."""

    name: str
    group: str
    p_i: at.Particle
    p_j: at.Particle
    liquid: at.Liquid
    gas: at.Gas
    beta_deg: float
    bed: at.Bed | None = None
    e: float = 0.9

    def kwargs(self):
        return dict(p_i=self.p_i, p_j=self.p_j, liquid=self.liquid, gas=self.gas,
                    bed=self.bed, beta_deg=self.beta_deg, e=self.e)

    def kernel_inputs(self, u0):
        """Flat kernel inputs (13 arrays, tier order) at head-on speeds ``u0`` [m/s]."""
        u0 = np.asarray(u0, dtype=float).ravel()
        st = prepare_pair(self.p_i, self.p_j, self.liquid, self.gas,
                          self.bed or at.Bed(), self.beta_deg, self.e, True, "emulsion")
        n = u0.size
        out = [np.full(n, float(np.ravel(getattr(st, k))[0])) for k in STATE_NAMES]
        out.append(u0 * float(np.ravel(st.w_per_u0)[0]))
        out += [np.full(n, float(np.ravel(getattr(st, k))[0])) for k in FORCE_NAMES]
        return out


def paper_cases():
    """Cases I (water) and II (slag) of Table 2 at beta = 0, 45, 90 deg."""
    out = []
    for beta in (0.0, 45.0, 90.0):
        p = silica(5e-6)
        out.append(Scene(f"I water b{beta:g}", "paper cases", p, p, WATER, AIR_25C, beta))
        p = silica(0.15e-6)
        out.append(Scene(f"II slag b{beta:g}", "paper cases", p, p, slag(), AIR_800C, beta))
    return out


def table3_variations():
    """Table 3 of the paper: smaller or denser partner, asperities, coatings (i / j), for both
    cases, at beta = 0 and 90 deg."""
    out = []
    for beta in (0.0, 90.0):
        for case, h0, liq, gas in (("I", 5e-6, WATER, AIR_25C),
                                   ("II", 0.15e-6, slag(), AIR_800C)):
            pi = silica(h0)
            var = {
                "size A": (pi, silica(h0, d=600e-6)),
                "density A": (pi, silica(h0, rho=4330.0)),
                "asperity A": (silica(h0, ha=0.08e-6), silica(h0, ha=0.12e-6)),
                "asperity B": (silica(h0, ha=0.08e-6), silica(h0, ha=0.08e-6)),
            }
            if case == "I":
                var["coating A"] = (silica(3e-6), silica(7e-6))
                var["coating B"] = (silica(7.5e-6), silica(7.5e-6))
            else:
                var["coating A"] = (silica(0.12e-6), silica(0.18e-6))
                var["coating B"] = (silica(0.20e-6), silica(0.20e-6))
            for name, (a, b) in var.items():
                out.append(Scene(f"{case} {name} b{beta:g}", "Table 3", a, b, liq, gas, beta))
    return out


def glass_on_plate():
    """A 1.74 mm glass sphere (2500 kg/m3, dry) dropped on a plate under a thick water film,
    in still air (no drag): films of 20, 50 and 100 um, asperities 0.1 um each."""
    out = []
    ball = at.Particle(d=1.74e-3, rho=2500.0, h0=0.0, ha=0.1e-6)
    for film in (20e-6, 50e-6, 100e-6):
        plate = at.Particle.plate(h0=film, ha=0.1e-6)
        out.append(Scene(f"glass on plate {film * 1e6:g} um", "glass on plate", plate, ball,
                         WATER, AIR_25C, 90.0, bed=at.Bed(eps=0.99, U=0.0)))
    return out


def viscous_melts():
    """Case II geometry with melts of 1e3 to 1e6 Pa s, at beta = 90 deg."""
    p = silica(0.15e-6)
    return [Scene(f"melt {mu:.0e} Pa s", "viscous melts", p, p, slag(mu), AIR_800C, 90.0)
            for mu in (1e3, 1e4, 1e5, 1e6)]


def all_scenes():
    return paper_cases() + table3_variations() + glass_on_plate() + viscous_melts()
