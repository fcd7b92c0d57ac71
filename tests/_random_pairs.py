"""Random wet pairs for the tests of the u0* search: log-uniform sizes, coatings,
asperities and viscosities over the package's ranges, any angle, partly plates."""

from __future__ import annotations

import numpy as np

import agglomtool as at

AIR = at.Gas(mu=18.48e-6, rho=1.168)


def random_arrays(n: int, seed: int) -> dict:
    """The inputs of ``n`` random pairs as arrays (a test edits them before
    :func:`as_inputs`: plates, missing bridges, ``e = 0``)."""
    rng = np.random.default_rng(seed)

    def lu(lo, hi):
        return 10.0 ** rng.uniform(np.log10(lo), np.log10(hi), n)

    out = {"ha": lu(0.02e-6, 1e-6)}
    out["h0"] = out["ha"] * lu(1.5, 100.0)
    out["d_j"], out["rho_j"] = lu(100e-6, 3e-3), rng.uniform(1000.0, 5000.0, n)
    out["d_i"], out["rho_i"] = lu(100e-6, 3e-3), rng.uniform(1000.0, 5000.0, n)
    out["mu"], out["gamma"] = lu(1e-3, 30.0), rng.uniform(0.02, 0.5, n)
    out["rho_l"], out["theta_deg"] = rng.uniform(800.0, 3000.0, n), rng.uniform(0.0, 80.0, n)
    out["eps"], out["beta_deg"] = rng.uniform(0.4, 0.95, n), rng.uniform(0.0, 360.0, n)
    out["e"] = rng.uniform(0.2, 1.0, n)
    return out


def as_inputs(a: dict) -> dict:
    """:func:`agglomtool.collide`'s keyword arguments of the pairs ``a``; a pair whose
    ``d_j`` is infinite is a plate (its density made infinite too)."""
    rho_j = np.where(np.isinf(a["d_j"]), np.inf, a["rho_j"])
    return dict(
        p_i=at.Particle(d=a["d_i"], rho=a["rho_i"], h0=a["h0"], ha=a["ha"]),
        p_j=at.Particle(d=a["d_j"], rho=rho_j, h0=a["h0"], ha=a["ha"]),
        liquid=at.Liquid(mu=a["mu"], gamma=a["gamma"], rho=a["rho_l"],
                         theta_deg=a["theta_deg"]),
        gas=AIR, bed=at.Bed(eps=a["eps"]), beta_deg=a["beta_deg"], e=a["e"],
    )
