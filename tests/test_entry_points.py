"""Every public entry point answers an unknown name or a bad value with a ValueError that
names the field, never a KeyError, TypeError or IndexError from inside."""

import pytest

import agglomtool as at

WATER = at.Liquid(mu=8.9e-4, gamma=0.073, rho=997.0, theta_deg=10.0)
AIR = at.Gas(mu=1.8e-5, rho=1.2)
P = at.Particle(d=500e-6, rho=2650.0, h0=5e-6, ha=1e-7)


def _collide(**kw):
    args = dict(liquid=WATER, gas=AIR, u0=0.1)
    args.update(kw)
    return at.collide(P, P, **args)


CASES = [
    ("solid", lambda: at.materials.solid("ilmanite")),
    ("liquid", lambda: at.materials.liquid("watr", T=300.0)),
    ("gas", lambda: at.materials.gas("ari")),
    ("gas", lambda: at.gas_properties(300.0, 1e5, "ari")),
    ("method", lambda: at.umf(500e-6, 2650.0, AIR, "wenyu")),
    ("solid_i", lambda: at.Scene(solid_i="sand")),
    ("liquid", lambda: at.Scene(liquid="water", T=5000.0).evaluate()),
    ("mode", lambda: at.Scene(mode="fast")),
    ("T", lambda: at.Scene(T="hot")),
    ("e", lambda: at.Scene(e=1.2)),
    ("speed", lambda: at.Scene(speed="uniform")),
    ("colour", lambda: at.Scene().replace(colour=1)),
    ("colour", lambda: at.sweep(at.Scene(u0=0.1), colour=[1.0, 2.0])),
    ("solid_j", lambda: at.sweep(at.Scene(u0=0.1), solid_j=["sand"])),
    ("T", lambda: at.sweep(at.Scene(u0=0.1), T=[[1.0, 2.0]])),
    ("mode", lambda: _collide(mode="fast")),
    ("u0", lambda: _collide(u0=float("nan"))),
    ("e", lambda: _collide(e=1.2)),
    ("d", lambda: at.Particle(d=-1.0, rho=2650.0, h0=0.0, ha=0.0)),
    ("mu", lambda: at.Liquid(mu="x", gamma=0.07, rho=1000.0)),
    ("eps", lambda: at.Bed(eps=1.5)),
    ("uncertain", lambda: at.monte_carlo(at.Scene(u0=0.1), uncertain={"hh": at.Normal(1, 1)},
                                         n=10)),
    ("n", lambda: at.monte_carlo(at.Scene(u0=0.1), uncertain={"h0": at.Normal(1e-6, 1e-7)},
                                 n=0)),
    ("var", lambda: __import__("agglomtool.plots", fromlist=["x"]).operating_window(
        at.sweep(at.Scene(u0=0.1), T=[1000.0, 1100.0]), "nothing")),
    ("complevel", lambda: at.write_map(at.sweep(at.Scene(u0=0.1), T=[1000.0]), "x.nc",
                                       complevel=12)),
]


@pytest.mark.parametrize("field,call", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_bad_input_is_a_value_error_naming_the_field(field, call, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError) as info:
        call()
    assert field in str(info.value), str(info.value)
