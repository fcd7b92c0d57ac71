"""The bed-level model under the impact-speed models: one granular temperature for every
class of a bed, as the collision-rate weighting assumes (bed/propensity.py)."""

import warnings

import numpy as np
import pytest

import agglomtool as at
from agglomtool.bed import Component, bed_propensity
from agglomtool.bed.speed_models import IMPACT_SPEED_MODELS

COND = dict(T=300.0, gas="air", liquid="water", h0=5e-6, U_Umf=3.0)
SAND = Component("silica-sand", 1.0, d=[250e-6, 350e-6, 450e-6], d_fractions=[0.3, 0.4, 0.3])


@pytest.mark.parametrize("model", list(IMPACT_SPEED_MODELS))
def test_every_pair_of_classes_sees_one_speed_law(model):
    """The rates assume one granular temperature for all classes, and the bed model states
    E_ab = E_ba exactly (a pair at beta is the swapped pair at -beta): a speed law that
    followed the size of particle i alone (the collisional balance, Theta ~ d_p**(2/3))
    broke both within a component, where both orders are computed."""
    scene = at.Scene(**COND, d_i=350e-6, speed=model)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        ds = bed_propensity(scene, [SAND], directions=4)
    E = ds["efficiency"].values
    np.testing.assert_allclose(E, E.T, rtol=1e-12, atol=1e-15)


def test_the_bed_temperature_of_the_collisional_balance_is_the_mean_particles():
    """One bed, one granular temperature: that of the bed's mean particle (the Sauter mean
    wet diameter and the mean wet density, as for the bed's U_mf). A one-class bed is the
    scene's own pair."""
    scene = at.Scene(**COND, d_i=350e-6, speed="collisional-balance")
    one = bed_propensity(scene, [Component("silica-sand", 1.0, d=[350e-6])], directions=4)
    pair = at.Scene(**COND, d_i=350e-6, speed="collisional-balance",
                    beta_deg=float(one.beta_deg.values[0])).evaluate()
    assert float(one["sticking_probability"].values[0, 0, 0]) == pytest.approx(
        float(pair["propensity"]), rel=1e-6)
