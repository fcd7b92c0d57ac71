"""The propensity evaluates its speed nodes only where probability lies above u0* (issue
12): the same numbers, bit for bit, as evaluating every node everywhere."""

import numpy as np

from agglomtool.bed.speeds import sticking_probability
from agglomtool.scene import Resolved, Scene


def test_masked_nodes_equal_the_full_evaluation():
    s = Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
    values = {**s.values(), "U_Umf": np.linspace(1.2, 8.0, 12).reshape(12, 1, 1),
              "h0": np.geomspace(1e-6, 30e-6, 9).reshape(1, 9, 1),
              "beta_deg": np.array([-60.0, 0.0, 45.0]).reshape(1, 1, 3)}
    r = Resolved(values)
    u_star = r.u_star
    shape = np.broadcast_shapes(np.shape(u_star), np.shape(r.U))
    full = sticking_probability(r.speeds, u_star, r.collide, nodes=16, shape=shape)
    masked = sticking_probability(r.speeds, u_star, r.collide, nodes=16, shape=shape,
                                  collide_on=r.collide_on)
    np.testing.assert_array_equal(masked, full)
    assert 0.0 < float(np.mean(full < 1.0)) < 1.0  # both kinds of points in the block


def test_speed_law_at_a_mask_equals_the_full_law_there():
    """The nodes' quantiles are taken on the open elements only (SpeedModel.at): the same
    numbers, bit for bit, as the full-size quantile cut to them, for every family, with
    parameters that vary over the grid and ones that do not."""
    from agglomtool.bed.speeds import SpeedModel

    rng = np.random.default_rng(3)
    shape = (7, 5, 3)
    mask = rng.random(shape) < 0.4
    q = rng.uniform(0.0, 0.999, shape)
    laws = [SpeedModel("lognormal", u0=rng.uniform(0.05, 2.0, (7, 1, 1)),
                       sigma_ln=rng.uniform(0.1, 1.0, (1, 5, 3))),
            SpeedModel("lognormal", u0=0.3, sigma_ln=0.5),
            SpeedModel("maxwellian", granular_temperature=rng.uniform(1e-3, 1.0, shape)),
            SpeedModel("fixed", u0=rng.uniform(0.1, 1.0, (1, 1, 3)))]
    for law in laws:
        full = np.broadcast_to(law.quantile(q), shape)[mask]
        part = np.broadcast_to(law.at(mask, shape).quantile(q[mask]), full.shape)
        np.testing.assert_array_equal(part, full)
    # and the cdf the propensity starts from, at the same elements
    law = laws[0]
    np.testing.assert_array_equal(law.at(mask, shape).cdf(q[mask]),
                                  np.broadcast_to(law.cdf(q), shape)[mask])
