"""Minimum fluidization velocity and the paper's drag law."""

import numpy as np
import pytest
from fluids.packed_bed import Ergun

from agglomtool.inputs import Gas
from agglomtool.properties import (
    UMF_C1_C2,
    drag_force_gidaspow,
    gas_properties,
    umf,
    umf_ergun,
    umf_wen_yu,
)
from agglomtool.properties.fluidization import GRAVITY


@pytest.mark.parametrize(("T", "target"), [(298.15, 0.559), (1073.15, 0.335)])
def test_umf_wen_yu_sand_in_air(T, target):
    # The paper's Table 2 setting, by hand: 1000 um, 2650 kg/m3 sand in air at 1 bar,
    # Wen & Yu (1966): 0.559 m/s (25 C), 0.335 m/s (800 C), with CoolProp's air. Tolerance
    # half a unit of the third digit, the targets' rounding (obtained 0.55882 and 0.33516).
    gas = gas_properties(T, 1e5, "air")
    assert umf(1000e-6, 2650.0, gas) == pytest.approx(target, abs=0.0005, rel=0)


#: Re_mf = sqrt(C1^2 + C2 Ar) - C1 and the six published (C1, C2) pairs, typed from their
#: sources as tabulated by Kunii and Levenspiel (1991, Fluidization Engineering, 2nd ed.,
#: ch. 3, Table 4); some tabulations round Saxena-Vogel's C1 to 25.28 and Babu's to 25.3.
PUBLISHED_C1_C2 = {"wen-yu": (33.7, 0.0408), "richardson": (25.7, 0.0365),
                   "saxena-vogel": (25.3, 0.0571), "babu": (25.25, 0.0651),
                   "grace": (27.2, 0.0408), "chitester": (28.7, 0.0494)}


def test_umf_every_published_pair():
    """Each method is the generalized Wen-Yu form with its own published pair, computed here
    directly (Ar, then Re_mf, then U_mf; standard gravity typed in): 1e-12, the same formula
    in another order (the package's form avoids cancellation; at Ar = 8.9e4 the direct form
    here loses about one bit). For this sand in air Wen-Yu gives the lowest U_mf of the six
    and Babu et al. the highest: 0.559 to 0.869 m/s."""
    mu, rho, d, rho_p = 18.448e-6, 1.1688, 1000e-6, 2650.0
    gas = Gas(mu=mu, rho=rho)
    ar = d**3 * rho * (rho_p - rho) * 9.80665 / mu**2
    assert ar == pytest.approx(8.92e4, rel=1e-3)
    assert set(UMF_C1_C2) == set(PUBLISHED_C1_C2)
    values = {}
    for method, (c1, c2) in PUBLISHED_C1_C2.items():
        values[method] = float(umf(d, rho_p, gas, method=method))
        direct = (np.sqrt(c1 * c1 + c2 * ar) - c1) * mu / (rho * d)
        assert values[method] == pytest.approx(direct, rel=1e-12), method
    assert min(values, key=values.get) == "wen-yu" and max(values, key=values.get) == "babu"
    assert values["wen-yu"] == pytest.approx(0.559, abs=0.0005)  # by hand, 3 digits
    with pytest.raises(ValueError, match="not one of"):
        umf(1000e-6, 2650.0, gas, method="nonsense")


@pytest.mark.parametrize(("eps_mf", "target"), [(0.40, 0.583), (0.45, 0.766)])
def test_umf_ergun_sand_in_air(eps_mf, target):
    # Ergun (1952) solved by hand, eps_mf 0.40 / 0.45: 0.583 / 0.766 m/s at 25 C for the
    # sand above; half a unit of the third digit for their rounding (obtained 0.58283 and
    # 0.76624); the check below against the fluids library's Ergun is the tight one.
    gas = Gas(mu=18.448e-6, rho=1.1688)
    u = umf(1000e-6, 2650.0, gas, method="ergun", eps_mf=eps_mf)
    assert u == pytest.approx(target, abs=0.0005, rel=0)
    # At Umf the fluids Ergun pressure gradient carries the buoyant bed weight exactly.
    dp = Ergun(dp=1000e-6, voidage=eps_mf, vs=float(u), rho=1.1688, mu=18.448e-6, L=1.0)
    assert dp == pytest.approx((1 - eps_mf) * (2650.0 - 1.1688) * GRAVITY, rel=1e-10)


def test_umf_ergun_needs_eps_and_checks_inputs():
    gas = Gas(mu=18e-6, rho=1.2)
    with pytest.raises(ValueError, match="eps_mf"):
        umf(1e-3, 2650.0, gas, method="ergun")
    with pytest.raises(ValueError, match="eps_mf = 1.2"):
        umf_ergun(1e-3, 2650.0, 18e-6, 1.2, eps_mf=1.2)
    with pytest.raises(ValueError, match="d = -0.001"):
        umf(-1e-3, 2650.0, gas)


def test_umf_wen_yu_fine_particle_limit():
    # For small Ar, Re_mf -> C2 Ar / (2 C1): the Stokes limit. No cancellation error.
    d, rho_p, mu, rho = 20e-6, 2500.0, 1.8e-5, 1.2
    ar = d**3 * rho * (rho_p - rho) * GRAVITY / mu**2
    stokes = 0.0408 * ar / (2 * 33.7) * mu / (rho * d)
    assert umf_wen_yu(d, rho_p, mu, rho) == pytest.approx(stokes, rel=1e-5)


def test_drag_both_branches():
    # The paper's Eq. 18 (Shabanian et al. 2024, after Gidaspow 1994). Ergun branch, linear
    # regime: 150 (1-eps) mu / (eps d^2) V slip when rho_g -> 0.
    d, mu = 1e-3, 4.5e-5
    v = np.pi / 6 * d**3
    f = drag_force_gidaspow(0.01, d, v, 0.55, mu, 1e-12)
    assert f == pytest.approx(150 * 0.45 * mu / (0.55 * d * d) * v * 0.01, rel=1e-9)
    # Wen-Yu branch at eps >= 0.8, Re << 1: Stokes drag 3 pi mu d slip times eps^-1.65 eps.
    f = drag_force_gidaspow(1e-4, d, v, 0.9, mu, 0.3)
    re = 0.3 * 0.9 * d * 1e-4 / mu
    stokes = 3 * np.pi * mu * d * 1e-4 / 0.9 * (1 + 0.15 * re**0.687) * 0.9**-1.65
    assert f == pytest.approx(stokes, rel=1e-9)
    # Odd in slip, zero at zero slip.
    assert drag_force_gidaspow(-0.3, d, v, 0.9, mu, 0.3) == -drag_force_gidaspow(
        0.3, d, v, 0.9, mu, 0.3)
    assert drag_force_gidaspow(0.0, d, v, 0.55, mu, 0.3) == 0.0
