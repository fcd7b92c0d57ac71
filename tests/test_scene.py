"""Scene: properties derived once, the paper's case II reproduced, speeds and propensity."""

import numpy as np
import pytest

from agglomtool import critical_impact_speed
from agglomtool.bed.speeds import SpeedModel, sticking_probability
from agglomtool.examples import reference_cases
from agglomtool.scene import Scene


def test_case_two_u_star_matches_reference_case():
    # Case II through the scene (CoolProp air at 800 C instead of Table 2's typed gas
    # properties, which CoolProp's air matches within 0.5 %). The gas drops out of u0* for
    # identical particles head-on (test_properties_case2.py), so the scene's u0* equals the
    # reference case's to all digits (measured): 1e-12, the bound for a reordered
    # arithmetic. What differs is the path: the scene's database solid and liquid.
    s = Scene(T=1073.15, liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6, u0=0.5)
    case = reference_cases()[1]
    ref = float(case.critical_impact_speed())
    assert float(s.evaluate()["u_star"]) == pytest.approx(ref, rel=1e-12)


def test_scene_errors_name_the_field():
    with pytest.raises(ValueError, match="liquid"):
        Scene(liquid="no-such-melt")
    with pytest.raises(ValueError, match="eps"):
        Scene(eps=1.5)
    with pytest.raises(ValueError, match="u0"):
        Scene(speed="lognormal")
    with pytest.raises(ValueError, match="U_mf"):
        Scene(U=1e-4).evaluate()


def test_fixed_speed_propensity_is_the_outcome():
    s = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
    us = float(s.evaluate()["u_star"])
    low = Scene(**{**s.values(), "u0": 0.5 * us, "speed": "fixed"}).evaluate()
    high = Scene(**{**s.values(), "u0": 3.0 * us, "speed": "fixed"}).evaluate()
    assert float(low["propensity"]) == 1.0 and bool(low["agglomerated"])
    assert float(high["propensity"]) == 0.0 and not bool(high["agglomerated"])


@pytest.mark.parametrize("family,kw", [("lognormal", {"u0": 0.3, "sigma_ln": 0.6}),
                                        ("maxwellian", {"granular_temperature": 0.05})])
def test_quantile_inverts_cdf(family, kw):
    m = SpeedModel(family, **kw)
    q = np.linspace(0.01, 0.99, 50)
    np.testing.assert_allclose(m.cdf(m.quantile(q)), q, rtol=1e-10)
    np.testing.assert_allclose(m.cdf(m.median()), 0.5, rtol=1e-12)


def test_propensity_monotonic_equals_cdf_at_u_star():
    # Where e_w(u0) is monotonic (case II at beta = 0), P = F(u0*) whatever the nodes.
    case = reference_cases()[1]
    us = float(case.critical_impact_speed())
    m = SpeedModel("lognormal", u0=np.array([0.3, 0.6, 1.2]), sigma_ln=0.5)
    p = sticking_probability(m, us, lambda u: case.collide(u, details=False), nodes=8)
    np.testing.assert_allclose(p, m.cdf(us), rtol=0, atol=1e-12)


def test_propensity_counts_sticking_above_u_star():
    # A collide() that sticks in a window above u0* must raise P above F(u0*) by about the
    # window's probability (nodes resolve it to (1 - F)/(2N)).
    class R:
        def __init__(self, stuck):
            self.agglomerated = stuck

    m = SpeedModel("maxwellian", granular_temperature=0.04)
    us, lo, hi = 0.05, 0.2, 0.3
    p = sticking_probability(m, us, lambda u: R((u > lo) & (u < hi)), nodes=400)
    expected = m.cdf(us) + m.cdf(hi) - m.cdf(lo)
    assert float(p) == pytest.approx(float(expected), abs=1.0 / 400)


def test_u_star_of_grid_does_not_depend_on_speed_fields():
    s = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
    a = s.evaluate()["u_star"]
    b = Scene(**{**s.values(), "U_Umf": 6.0}).evaluate()["u_star"]
    assert float(a) == float(b)
    r = Scene(**{**s.values(), "beta_deg": 90.0})
    p = r.evaluate()
    from agglomtool.scene import Resolved

    res = Resolved(r.values())
    p_i, p_j = res.particles
    direct = critical_impact_speed(p_i, p_j, liquid=res.liquid, gas=res.gas, bed=res.bed,
                                   beta_deg=90.0, e=res.e)
    assert float(p["u_star"]) == float(direct)
