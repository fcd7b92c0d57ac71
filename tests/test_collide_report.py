"""The readable account of one collision (``CollisionResult.explain`` and ``agglomtool
collide``) says nothing its own lines contradict."""

import re

import numpy as np

import agglomtool as at
from agglomtool.cli import main

WATER = at.Liquid(mu=8.9e-4, gamma=0.072, rho=997.0, theta_deg=0.0)
AIR = at.Gas(mu=1.8e-5, rho=1.2)


def _decided(text):
    return next(line for line in text.splitlines() if line.startswith("decided at:"))


def test_no_bridge_is_the_decision_not_a_ruptured_bridge():
    # coating (0.2 um) thinner than the asperities (1 um): no bridge, a dry rebound with e
    p = at.Particle(d=300e-6, rho=4330.0, h0=0.2e-6, ha=1e-6)
    res = at.collide(p, p, liquid=WATER, gas=AIR, u0=0.2, e=0.85, details=True)
    assert res.path[()] & at.Path.NO_BRIDGE
    text = res.explain()
    decided = _decided(text)
    assert "no bridge" in decided
    assert "ruptured" not in decided and "bridge ruptured" not in text
    # and when the dry collision leaves nothing (e = 0): still no bridge, no "contact" story
    # of a bridge
    zero = at.collide(p, p, liquid=WATER, gas=AIR, u0=0.2, e=0.0, details=True).explain()
    assert "no bridge" in _decided(zero)


def test_cli_report_of_a_bridgeless_ilmenite_pair_is_consistent(capsys):
    # the slag default (0.2 um) on ilmenite (asperities 1 um): no bridge forms
    assert main(["collide", "--solid-i", "ilmenite", "--d-i", "300e-6"]) == 0
    out = capsys.readouterr().out
    assert "special paths: no_bridge" in out
    assert "no bridge" in _decided(out) and "ruptured" not in _decided(out)


def _frac_lines(text):
    return [line for line in text.splitlines() if re.match(r"\s+W_\w+_frac\b", line)]


def test_work_fractions_are_fractions_or_say_why_not():
    # A viscous melt (1e6 Pa s): the approach's Stokes number is ~1e-8, the bound on the
    # volume correction's work (the viscous work at the impact speed over the whole gap)
    # is ~1/St times the initial kinetic energy: not a fraction of anything.
    melt = at.Liquid(mu=1e6, gamma=0.3, rho=2500.0, theta_deg=0.0)
    p = at.Particle(d=300e-6, rho=4330.0, h0=5e-6, ha=1e-6)
    res = at.collide(p, p, liquid=melt, gas=AIR, u0=0.2, details=True, mode="relative")
    raw = float(res.details["W_volcorr_frac"][()])
    assert raw > 1.0  # the kernel's bound, as computed
    lines = _frac_lines(res.explain())
    assert len(lines) == 2
    for line in lines:
        numbers = [float(x) for x in re.findall(r"=\s*([-+0-9.eE]+)", line)]
        assert all(0.0 <= x <= 1.0 for x in numbers), line
    vol = next(line for line in lines if "W_volcorr_frac" in line)
    assert "> 1" in vol and "not negligible" in vol
    # an ordinary water collision keeps its small fraction as a number
    q = at.Particle(d=500e-6, rho=2650.0, h0=5e-6, ha=1e-7)
    small = at.collide(q, q, liquid=WATER, gas=AIR, u0=0.5, details=True, mode="relative")
    expected = float(small.details["W_volcorr_frac"][()])
    assert 0.0 < expected < 1.0
    vol = next(line for line in _frac_lines(small.explain()) if "W_volcorr_frac" in line)
    assert np.isclose(float(re.search(r"=\s*([0-9.eE+-]+)", vol).group(1)), expected,
                      rtol=1e-5)


def test_the_report_lists_the_assumed_values_with_their_ranges(capsys):
    from agglomtool.cli import main

    assert main(["collide", "--liquid", "water", "--T", "25 degC", "--h0", "5 um",
                 "--solid-j", "ilmenite", "--d-i", "300 um"]) == 0
    out = capsys.readouterr().out
    assert "ilmenite asperity_height = 1 um (lognormal, 5-95 % 0.1-10 um)" in out
    assert "ilmenite restitution_dry = 0.85 (uniform on 0.7-0.95)" in out
    assert "water theta_deg = 0 deg (uniform on 0-30 deg)" in out
    assert "excess-gas fluctuation_ratio = 1 (lognormal, 5-95 % 0.3-3)" in out
    # a value the user sets is not an assumption of the database
    assert main(["collide", "--liquid", "water", "--T", "25 degC", "--h0", "5 um",
                 "--ha-i", "0.3 um", "--ha-j", "0.3 um", "--theta-deg", "5", "--e", "0.9",
                 "--fluctuation-ratio", "1.5"]) == 0
    assert "assumed values used" not in capsys.readouterr().out
