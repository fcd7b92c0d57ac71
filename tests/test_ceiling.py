"""The u0* ceiling: no bed speed like 1e4 m/s is ever reported (it once was, for melts)."""

import numpy as np
import pytest

import agglomtool as at
from agglomtool.scene import U_CEILING, U_STAR_FLAGS, Scene

MELT = Scene(liquid="k-silicate-ash-melt", gas="biomass-flue-gas", T=1173.15, h0=1e-6)


def test_viscous_melt_sticks_up_to_the_ceiling():
    # GRD puts this melt at ~1e6 Pa s at 900 C: the search finds u0* ~ 1e4-1e7 m/s
    (p_i, p_j), kw = _pair(MELT)
    raw = float(at.critical_impact_speed(p_i, p_j, **kw))
    assert raw > 1e3  # the extrapolated number the ceiling exists for
    out = MELT.evaluate()
    assert np.isinf(out["u_star"])
    assert int(out["u_star_flag"]) == 2
    assert float(out["propensity"]) == 1.0


def _pair(scene):
    from agglomtool.scene import Resolved

    r = Resolved(scene.values())
    p_i, p_j = r.particles
    return (p_i, p_j), dict(liquid=r.liquid, gas=r.gas, bed=r.bed, e=r.e)


def test_map_never_reports_a_speed_above_the_ceiling():
    ds = at.sweep(MELT, T=[1173.15, 1473.15, 1673.15], h0=[0.05e-6, 0.5e-6, 2e-6])
    us = ds.u_star.values
    assert np.all((us <= U_CEILING) | np.isinf(us))
    flag = ds.u_star_flag.values
    assert set(np.unique(flag)) <= set(U_STAR_FLAGS)
    np.testing.assert_array_equal(np.isinf(us), flag == 2)
    np.testing.assert_array_equal(us == 0.0, flag == 1)
    assert (flag == 1).any() and (flag == 2).any()  # 0.05 um < 0.1 um asperities; hot melt
    attrs = ds.u_star_flag.attrs
    assert list(attrs["flag_values"]) == [0, 1, 2]
    assert "sticks_up_to_ceiling" in attrs["flag_meanings"]


def test_ceiling_is_configurable():
    low = MELT.replace(T=1673.15, h0=0.11e-6)  # u0* ~ 1.8 m/s
    us = float(low.evaluate()["u_star"])
    assert np.isfinite(us) and us > 0.0
    capped = low.replace(u_ceiling=0.5 * us).evaluate()
    assert np.isinf(capped["u_star"]) and int(capped["u_star_flag"]) == 2
    with pytest.raises(ValueError, match="u_ceiling"):
        Scene(u_ceiling=-1.0)
