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
