"""The remembered water states (``agglomtool.properties.water._MEMO``) are bitwise the states
CoolProp evaluates afresh, whatever was evaluated before; a state that is not a liquid is
still refused, remembered neighbours or not."""

from __future__ import annotations

import CoolProp.CoolProp as CP
import numpy as np
import pytest

from agglomtool.properties import water


def _fresh(T, P):
    """Each state from its own new CoolProp state object (no history at all)."""
    mu, rho = np.empty(T.size), np.empty(T.size)
    for k, (t, p) in enumerate(zip(T, P, strict=True)):
        st = CP.AbstractState("HEOS", "Water")
        st.update(CP.PT_INPUTS, float(p), float(t))
        mu[k], rho[k] = st.viscosity(), st.rhomass()
    return mu, rho


def test_memo_is_bitwise_the_fresh_state():
    rng = np.random.default_rng(11)
    T = rng.uniform(275.0, 370.0, 150)
    P = rng.choice([101325.0, 2e5, 1e6], 150)
    ref_mu, ref_rho = _fresh(T, P)
    water._MEMO.clear()
    first = water._liquid_states(T, P)  # evaluated (and remembered) in this order
    assert len(water._MEMO) == 150
    order = rng.permutation(150)
    again = water._liquid_states(T[order], P[order])  # every state from the memo
    for got in (first, (again[0][np.argsort(order)], again[1][np.argsort(order)])):
        np.testing.assert_array_equal(got[0], ref_mu)
        np.testing.assert_array_equal(got[1], ref_rho)
    # The same temperatures at two pressures: two states each (the key is the pair).
    T2 = np.concatenate([T[:10], T[:10]])
    P2 = np.repeat([101325.0, 5e6], 10)
    got = water._liquid_states(T2, P2)
    ref = _fresh(T2, P2)
    np.testing.assert_array_equal(got[0], ref[0])
    np.testing.assert_array_equal(got[1], ref[1])
    assert np.all(got[1][10:] > got[1][:10])  # compressed
    # A grid block: the memo fills the repeated temperatures of a broadcast shape.
    mu, rho = water._liquid_states(T[:20].reshape(1, 20), np.full((3, 1), 101325.0))
    ref = _fresh(T[:20], np.full(20, 101325.0))
    np.testing.assert_array_equal(mu, np.broadcast_to(ref[0], (3, 20)))
    np.testing.assert_array_equal(rho, np.broadcast_to(ref[1], (3, 20)))


def test_boiling_water_is_refused_with_a_full_memo():
    water._liquid_states(np.array([370.0]), np.array([101325.0]))
    with pytest.raises(ValueError, match="is not a liquid"):
        water._liquid_states(np.array([370.0, 380.0]), np.array([101325.0, 101325.0]))
