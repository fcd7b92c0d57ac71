"""The map says which quantity decides it where no finite u0* exists."""

import numpy as np

import agglomtool as at
from agglomtool.maps.regime import deciding_regime

MELT = at.Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T=1123.15,
                solid_i="silica-sand", d_i=300e-6)


def test_a_melt_map_of_no_bridge_and_sticks_everywhere_names_the_coating():
    # 0.05 um is below the sand's 0.1 um asperities (no bridge); 1 um above (the melt,
    # 1e6-1e7 Pa s here, holds every bridge up to the ceiling)
    ds = at.sweep(MELT, T=[1073.15, 1223.15], h0=[0.05e-6, 1e-6], U_Umf=[2.0, 8.0])
    flags = set(np.unique(ds.u_star_flag.values))
    assert flags == {1, 2}
    text = deciding_regime(ds)
    assert text.startswith("Every point of this map either forms no bridge (50 %)")
    assert "coating thickness h0 against the asperity heights" in text
    assert "10 m/s" in text and "mu_l" in text


def test_one_regime_alone_and_a_capillary_map():
    none = at.sweep(MELT, h0=[0.02e-6, 0.05e-6])
    assert deciding_regime(none).startswith("No bridge forms anywhere")
    stick = at.sweep(MELT, h0=[1e-6, 2e-6])
    assert deciding_regime(stick).startswith("The pair sticks at every impact speed up to "
                                             "the ceiling of 10 m/s everywhere")
    water = at.sweep(at.Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6),
                     U_Umf=[2.0, 4.0])
    assert (water.u_star_flag == 0).any() and deciding_regime(water) == ""
