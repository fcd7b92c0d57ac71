"""Bad input raises ValueError naming the field, the value and the allowed range (issue
item 3): non-positive sizes or densities, negative thickness or asperity height, e outside
[0, 1], theta outside [0, 90), eps outside (0, 1), NaN anywhere, particles not approaching.

The range is checked in the notation the package prints (``(0, inf)``, ``[0, 90)``...);
the speeds ``u0``, ``u0_j`` and the angle ``beta_deg`` have physical ranges too
(``[-1e+12, 1e+12] m/s``, ``[-3600, 3600] deg``).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import agglomtool as at

NAN = math.nan
P = at.Particle(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6)
WATER = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
AIR = at.Gas(mu=18.48e-6, rho=1.168)

GOOD = {
    "Particle": dict(d=1000e-6, rho=2650.0, h0=5e-6, ha=0.1e-6),
    "Liquid": dict(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0),
    "Gas": dict(mu=18.48e-6, rho=1.168),
    "Bed": dict(eps=0.55, U=0.5),
}
RANGES = {  # the physical ranges (absurd magnitudes are refused too: docs/inputs.md)
    ("Particle", "d"): "(0, 1e+10] m or inf",
    ("Particle", "rho"): "(0, 100000] kg/m3 or inf",
    ("Particle", "h0"): "[0, 1e+10] m",
    ("Particle", "ha"): "[0, 1e+10] m",
    ("Liquid", "mu"): "(0, 1e+30] Pa s",
    ("Liquid", "gamma"): "(0, 10] N/m",
    ("Liquid", "rho"): "(0, 100000] kg/m3",
    ("Liquid", "theta_deg"): "[0, 90)",
    ("Gas", "mu"): "(0, 1] Pa s",
    ("Gas", "rho"): "(0, 100000] kg/m3",
    ("Bed", "eps"): "(0, 1)",
    ("Bed", "U"): "[0, 1e+12] m/s",
}
BAD_VALUES = {
    ("Particle", "d"): [0.0, -1e-3, -math.inf],
    ("Particle", "rho"): [0.0, -2650.0],
    ("Particle", "h0"): [-1e-9],
    ("Particle", "ha"): [-1e-9],
    ("Liquid", "mu"): [0.0, -1.0],
    ("Liquid", "gamma"): [0.0, -0.07],
    ("Liquid", "rho"): [0.0, -997.0],
    ("Liquid", "theta_deg"): [-1.0, 90.0, 120.0],
    ("Gas", "mu"): [0.0],
    ("Gas", "rho"): [0.0, -1.0],
    ("Bed", "eps"): [0.0, 1.0, -0.2, 1.5],
    ("Bed", "U"): [-0.1],
}
CLASSES = {"Particle": at.Particle, "Liquid": at.Liquid, "Gas": at.Gas, "Bed": at.Bed}


def _assert_message(exc, field, value, rng):
    msg = str(exc.value)
    assert field in msg, f"field {field!r} not named in: {msg}"
    if isinstance(value, float) and math.isnan(value):
        assert re.search(r"nan", msg, re.IGNORECASE), f"value NaN not named in: {msg}"
    else:
        assert repr(float(value)) in msg, f"value {value!r} not named in: {msg}"
    assert rng in msg, f"allowed range {rng!r} not stated in: {msg}"


CASES = [(cls, name, v) for (cls, name), vals in BAD_VALUES.items() for v in vals]


@pytest.mark.parametrize(("cls", "name", "value"), CASES)
def test_out_of_range_field(cls, name, value):
    kwargs = dict(GOOD[cls], **{name: value})
    with pytest.raises(ValueError) as exc:
        CLASSES[cls](**kwargs)
    _assert_message(exc, f"{cls}.{name}", value, RANGES[(cls, name)])


@pytest.mark.parametrize(("cls", "name"), list(RANGES))
def test_out_of_range_inside_an_array(cls, name):
    """The first offending element of an array input is the one reported."""
    bad = BAD_VALUES[(cls, name)][-1]
    good = GOOD[cls][name]
    kwargs = dict(GOOD[cls], **{name: np.array([good, bad, good])})
    with pytest.raises(ValueError) as exc:
        CLASSES[cls](**kwargs)
    _assert_message(exc, f"{cls}.{name}", bad, RANGES[(cls, name)])


@pytest.mark.parametrize(("cls", "name"), list(RANGES))
def test_nan_field(cls, name):
    """NaN anywhere: the message names the field, says NaN and gives the allowed range."""
    kwargs = dict(GOOD[cls], **{name: NAN})
    with pytest.raises(ValueError) as exc:
        CLASSES[cls](**kwargs)
    _assert_message(exc, f"{cls}.{name}", NAN, RANGES[(cls, name)])


@pytest.mark.parametrize(("cls", "name"), [("Particle", "h0"), ("Liquid", "mu"), ("Bed", "eps")])
def test_nan_inside_an_array(cls, name):
    kwargs = dict(GOOD[cls], **{name: np.array([GOOD[cls][name], NAN])})
    with pytest.raises(ValueError) as exc:
        CLASSES[cls](**kwargs)
    _assert_message(exc, f"{cls}.{name}", NAN, RANGES[(cls, name)])


@pytest.mark.parametrize("e", [-0.1, 1.0000001, 2.0, NAN])
@pytest.mark.parametrize("func", ["collide", "critical_impact_speed"])
def test_restitution_out_of_range(func, e):
    kw = dict(liquid=WATER, gas=AIR, e=e)
    with pytest.raises(ValueError) as exc:
        if func == "collide":
            at.collide(P, P, u0=0.05, **kw)
        else:
            at.critical_impact_speed(P, P, **kw)
    _assert_message(exc, "e", e, "[0, 1]")


def test_restitution_out_of_range_in_array():
    with pytest.raises(ValueError) as exc:
        at.collide(P, P, liquid=WATER, gas=AIR, u0=0.05, e=np.array([0.5, 0.9, -0.5]))
    _assert_message(exc, "e", -0.5, "[0, 1]")


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        (dict(u0=NAN), "u0"),
        (dict(u0=np.array([0.1, NAN])), "u0"),
        (dict(u0=0.1, u0_j=NAN), "u0_j"),
        (dict(u0=0.1, beta_deg=NAN), "beta_deg"),
        (dict(u0=0.1, beta_deg=np.array([0.0, NAN])), "beta_deg"),
    ],
)
def test_nan_in_call_arguments(kwargs, field):
    with pytest.raises(ValueError) as exc:
        at.collide(P, P, liquid=WATER, gas=AIR, **kwargs)
    rng = "[-3600, 3600] deg" if field == "beta_deg" else "[-1e+12, 1e+12] m/s"
    _assert_message(exc, field, NAN, rng)


def test_nan_beta_in_critical_speed():
    with pytest.raises(ValueError) as exc:
        at.critical_impact_speed(P, P, liquid=WATER, gas=AIR, beta_deg=NAN)
    _assert_message(exc, "beta_deg", NAN, "[-3600, 3600] deg")


@pytest.mark.parametrize(
    ("kwargs", "relative"),
    [
        (dict(u0=-1.0, u0_j=0.5), -0.5),
        (dict(u0=0.25, u0_j=-0.5), -0.25),
        (dict(u0=0.0, u0_j=0.0), 0.0),
        (dict(u0=np.array([0.1, 0.2]), u0_j=np.array([0.1, -0.75])), -0.55),
    ],
)
def test_particles_not_approaching(kwargs, relative):
    """u0 + u0_j <= 0: not a rebound but a bad input; the message names the relative speed,
    its value and the range (0, inf)."""
    with pytest.raises(ValueError) as exc:
        at.collide(P, P, liquid=WATER, gas=AIR, **kwargs)
    _assert_message(exc, "u0", relative, "(0, inf)")
    if np.ndim(kwargs["u0"]):  # in a batch, the message says which collision
        assert "at index (1,)" in str(exc.value), str(exc.value)


@pytest.mark.parametrize("mode", ["paper", "relative", "auto"])
def test_a_bad_speed_in_a_grid_is_located(mode):
    """Every tier names the first offending collision of a 2-D batch by its index."""
    u0 = np.full((3, 4), 0.2)
    u0[1, 2] = np.inf
    u0[2, 0] = np.inf
    with pytest.raises(ValueError) as exc:
        at.collide(P, P, liquid=WATER, gas=AIR, u0=u0, mode=mode, details=False)
    msg = str(exc.value)
    assert "u0 = inf" in msg and "at index (1, 2)" in msg, msg


@pytest.mark.parametrize("u0", [0.0, -0.1])
def test_particle_not_approaching_a_plate(u0):
    plate = at.Particle.plate(h0=5e-6, ha=0.1e-6)
    with pytest.raises(ValueError) as exc:
        at.collide(plate, P, liquid=WATER, gas=AIR, u0=u0)
    msg = str(exc.value)
    assert "u0" in msg and "(0, inf)" in msg and repr(u0) in msg, msg


def test_both_plates_rejected():
    plate = at.Particle.plate(h0=5e-6, ha=0.1e-6)
    with pytest.raises(ValueError, match="plate"):
        at.collide(plate, plate, liquid=WATER, gas=AIR, u0=0.1)


def test_plate_must_not_move():
    plate = at.Particle.plate(h0=5e-6, ha=0.1e-6)
    with pytest.raises(ValueError, match="u0_j"):
        at.collide(P, plate, liquid=WATER, gas=AIR, u0=0.1, u0_j=0.1)


def test_finite_particle_with_infinite_density_rejected():
    with pytest.raises(ValueError) as exc:
        at.Particle(d=1e-3, rho=math.inf)
    msg = str(exc.value)
    assert "Particle.rho" in msg and "inf" in msg and "(0, 100000]" in msg, msg


def test_valid_edges_accepted():
    """The closed ends of the ranges are valid: h0 = ha = 0, theta = 0, e = 0 and 1."""
    p = at.Particle(d=1e-3, rho=2650.0, h0=0.0, ha=0.0)
    liq = at.Liquid(mu=1e-3, gamma=0.07, rho=1000.0, theta_deg=0.0)
    r = at.collide(p, P, liquid=liq, gas=AIR, u0=0.1, e=np.array([0.0, 1.0]))
    assert np.all(np.isfinite(r.e_w))
