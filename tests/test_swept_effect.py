"""A swept field that nothing the map or bed computes reads is refused, naming the field and
the speeds that read it (a flat axis is not an answer); one that is read is accepted and
moves the result. A [scene] whose speed law needs a value the [grid] sweeps is complete."""

import contextlib
import tomllib
import warnings

import numpy as np
import pytest

import agglomtool as at
from agglomtool.bed.config import parse_bed_config
from agglomtool.maps.config import ConfigError, parse_config

WATER = dict(liquid="water", T=298.15, d_i=500e-6, h0=5e-6, U_Umf=3.0)

#: Fields only the bubble models read, two values each inside the default bed (0.3 m deep,
#: 0.3 m wide).
GEOMETRY = {"bed_height": [0.2, 1.0], "column_diameter": [0.2, 1.0],
            "orifice_area": [0.0, 1e-4], "height": [0.05, 0.1], "wake_fraction": [0.15, 0.4]}

#: The speed laws' own parameters and the speeds that read them.
LAW_FIELDS = {"u0": [0.05, 0.1], "sigma_ln": [0.3, 1.0], "granular_temperature": [1e-3, 1e-2],
              "fluctuation_ratio": [0.5, 2.0]}


@contextlib.contextmanager
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        yield


@pytest.mark.parametrize("field", sorted(GEOMETRY))
@pytest.mark.parametrize("scene_kw", [dict(speed="excess-gas"),
                                      dict(speed="collisional-balance"),
                                      dict(speed="fixed", u0=0.1), dict()])
def test_map_refuses_a_geometry_axis_its_speed_ignores(field, scene_kw):
    scene = at.Scene(**WATER, **scene_kw)
    with pytest.raises(ValueError, match=rf"grid {field} has no effect with speed = "
                                         rf"'{scene.speed}'.*bubble-darton"):
        at.sweep(scene, **{field: GEOMETRY[field]})


@pytest.mark.parametrize("field", sorted(GEOMETRY))
@pytest.mark.parametrize("speed", ["bubble-darton", "bubble-mori-wen"])
def test_map_over_a_geometry_axis_its_model_reads_moves(field, speed):
    with _quiet():
        ds = at.sweep(at.Scene(**WATER, speed=speed), **{field: GEOMETRY[field]})
    u = ds.u_typical.values
    assert u.shape == (2,) and np.all(np.isfinite(u)) and u[0] != u[1]


@pytest.mark.parametrize("field", sorted(LAW_FIELDS))
def test_map_refuses_a_law_parameter_its_speed_ignores(field):
    scene = at.Scene(**WATER, speed="bubble-darton")
    with pytest.raises(ValueError, match=rf"grid {field} has no effect with speed = "
                                         "'bubble-darton'"):
        at.sweep(scene, **{field: LAW_FIELDS[field]})


def test_bed_height_is_refused_where_the_height_of_interest_is_given():
    scene = at.Scene(**WATER, speed="bubble-darton", height=0.1)
    with pytest.raises(ValueError, match=r"grid bed_height has no effect.*height = 0.1"):
        at.sweep(scene, bed_height=[0.2, 1.0])


def test_a_speed_axis_makes_the_fields_of_each_speed_count():
    with _quiet():
        ds = at.sweep(at.Scene(**WATER), speed=["excess-gas", "bubble-darton"],
                      wake_fraction=[0.15, 0.4])
    u = ds.u_typical.sel(speed="bubble-darton").values
    assert u[0] != u[1]
    with pytest.raises(ValueError, match="grid wake_fraction has no effect"):
        at.sweep(at.Scene(**WATER), speed=["excess-gas", "collisional-balance"],
                 wake_fraction=[0.15, 0.4])


BED = [at.Component("silica-sand", 1.0, d50=500e-6)]


@pytest.mark.parametrize("field", ["u0", "wake_fraction", "bed_height"])
def test_bed_sweep_refuses_an_axis_its_speed_ignores(field):
    values = {**LAW_FIELDS, **GEOMETRY}[field]
    with pytest.raises(ValueError, match=rf"grid {field} has no effect with speed = "
                                         "'excess-gas'"):
        at.bed_sweep(at.Scene(**WATER), BED, **{field: values})


def test_bed_sweep_over_an_axis_its_speed_reads_moves():
    with _quiet():
        ds = at.bed_sweep(at.Scene(**WATER, speed="fixed", u0=0.1), BED, u0=[0.02, 0.2])
    p = ds.propensity.values
    assert np.all(np.isfinite(p)) and p[0] > p[1]


BED_TOML = """
[scene]
liquid = "water"
T = "25 degC"
h0 = "5 um"
U_Umf = 3
speed = "collisional-balance"
[[component]]
solid = "silica-sand"
fraction = 1
d50 = "500 um"
[grid]
bed_height = [0.2, 1.0]
"""


def test_bed_config_names_the_key_of_an_axis_without_effect():
    with pytest.raises(ConfigError, match=r"\[grid\] bed_height: grid bed_height has no "
                                          "effect with speed = 'collisional-balance'"):
        parse_bed_config(tomllib.loads(BED_TOML))


def test_robust_map_accepts_an_axis_a_drawn_model_reads():
    # speed not named: uncertain="assumed" draws the model, bubble-darton among them
    with _quiet():
        ds = at.sweep(at.Scene(**WATER), uncertain="assumed", samples=16, seed=1,
                      wake_fraction=[0.15, 0.4])
    assert ds.propensity_mean.shape == (2,)
    with pytest.raises(ValueError, match="grid wake_fraction has no effect"):
        at.sweep(at.Scene(**WATER, speed="excess-gas"), uncertain="assumed", samples=16,
                 seed=1, wake_fraction=[0.15, 0.4])


MAP_TOML = """
[scene]
liquid = "water"
T = "25 degC"
d_i = "500 um"
h0 = "5 um"
{scene}
[grid]
{grid}
"""


@pytest.mark.parametrize("speed, grid", [
    ("lognormal", "u0 = [0.05, 0.1]"), ("fixed", "u0 = [0.05, 0.1]"),
    ("maxwellian", "granular_temperature = [1e-3, 1e-2]")])
def test_config_scene_takes_the_swept_value_its_speed_needs(speed, grid):
    cfg = parse_config(tomllib.loads(MAP_TOML.format(scene=f'speed = "{speed}"', grid=grid)))
    name = grid.split()[0]
    ds = at.sweep(cfg.scene, **cfg.grid)
    for value in cfg.grid[name]:
        one = at.Scene(**WATER, speed=speed, **{name: value}).evaluate()
        assert float(ds.propensity.sel({name: value})) == pytest.approx(
            float(one["propensity"]), rel=1e-12)


def test_config_without_speed_and_a_swept_u0_says_the_fix():
    text = MAP_TOML.format(scene="", grid="u0 = [0.05, 0.1]")
    with pytest.raises(ConfigError, match=r"\[grid\] u0: grid u0 has no effect with speed = "
                                          r"'excess-gas': set the scene's speed to one of "
                                          r"\['fixed', 'lognormal'\]"):
        parse_config(tomllib.loads(text))


def test_python_refusal_of_a_swept_u0_says_the_fix_that_works():
    with pytest.raises(ValueError, match=r"at\.Scene\(\.\.\., speed='fixed', u0=0\.05\)"):
        at.sweep(at.Scene(**WATER), u0=[0.05, 0.1])
    # the fix it names works
    scene = at.Scene(**WATER, speed="fixed", u0=0.05)
    assert at.sweep(scene, u0=[0.05, 0.1]).propensity.shape == (2,)


def test_compare_refuses_options_of_a_field_its_speed_ignores():
    # "no difference in 100 % of plausible inputs" would be read as "it does not matter"
    scene = at.Scene(**WATER, speed="excess-gas")
    with pytest.raises(ValueError, match=r"compare wake_fraction: wake_fraction has no "
                                         "effect with speed = 'excess-gas'.*bubble-darton"):
        at.compare(scene, uncertain="assumed", n=16, wake_fraction=[0.1, 0.4])
    with pytest.raises(ValueError, match=r"compare u0: u0 has no effect"):
        at.compare(scene, uncertain="assumed", n=16, u0=["0.05 m/s", "0.1 m/s"])
    # where the speed model is drawn, a bubble model among them reads the bed's height
    with _quiet():
        ds = at.compare(at.Scene(**WATER), uncertain="assumed", n=16, bed_height=[0.2, 1.0])
    assert ds.propensity_mean.shape == (2,)


def test_a_U_Umf_axis_is_refused_where_U_is_given_or_swept():
    # U = U_Umf x U_mf only where U is not given: the axis would be flat
    given = at.Scene(**WATER, U=0.5)
    with pytest.raises(ValueError, match=r"grid U_Umf has no effect: the scene gives U = 0.5 "
                                         "m/s"):
        at.sweep(given, U_Umf=[1.5, 3.0])
    with pytest.raises(ValueError, match=r"grid U_Umf has no effect: the grid sweeps U"):
        at.sweep(at.Scene(**WATER), U=[0.4, 0.6], U_Umf=[1.5, 3.0])
    with pytest.raises(ValueError, match=r"grid U_Umf has no effect: the scene gives U"):
        at.bed_sweep(given, BED, U_Umf=[1.5, 3.0])
    with pytest.raises(ValueError, match=r"compare U_Umf: U_Umf has no effect"):
        at.compare(given, uncertain="assumed", n=16, U_Umf=[1.5, 3.0])
    # a U axis replaces the scene's U_Umf as any axis replaces the scene's value
    ds = at.sweep(at.Scene(**WATER), U=[0.4, 0.6])
    assert ds.propensity.values[0] > ds.propensity.values[1]


@pytest.mark.parametrize("options", [dict(U_Umf=[2, 2.0]), dict(h0=["1 um", 1e-6]),
                                     dict(solid_j=["silica-sand", "Silica_Sand"])])
def test_compare_refuses_an_option_given_twice_in_two_spellings(options):
    # the same option twice would be 'no difference in 100 %': an answer to nothing
    with pytest.raises(ValueError, match=r"compare \w+: options repeat"):
        at.compare(at.Scene(**WATER), uncertain="assumed", n=16, **options)


@pytest.mark.parametrize("names", [["silica-sand", "silica_sand"], ["ilmenite", "Ilmenite"]])
def test_a_material_axis_refuses_one_material_in_two_spellings(names):
    # two columns of the same material under two labels would read as a comparison
    with pytest.raises(ValueError, match=r"grid solid_j .*repeats"):
        at.sweep(at.Scene(**WATER), solid_j=names)


def test_a_material_axis_holds_the_names_the_database_spells():
    with _quiet():
        ds = at.sweep(at.Scene(**WATER), solid_j=["Silica_Sand", "ILMENITE"])
        plain = at.sweep(at.Scene(**WATER), solid_j=["ilmenite", "olivine"])
    assert list(ds.solid_j.values) == ["silica-sand", "ilmenite"]
    assert float(ds.propensity.sel(solid_j="ilmenite")) == float(
        plain.propensity.sel(solid_j="ilmenite"))


#: Laws of fields that only some impact-speed models read.
UNREAD_LAWS = {"wake_fraction": at.Uniform(0.15, 0.4),
               "granular_temperature": at.Uniform(1e-3, 1e-2),
               "bed_height": at.Uniform(0.2, 1.0)}


@pytest.mark.parametrize("field", sorted(UNREAD_LAWS))
def test_an_uncertain_field_its_speed_ignores_is_refused(field):
    # every draw would be alike: 'spread 0', 'decided in 100 %', for an input never read
    scene = at.Scene(**WATER, speed="excess-gas")
    law = {field: UNREAD_LAWS[field]}
    match = rf"uncertain {field} has no effect with speed = 'excess-gas'"
    with pytest.raises(ValueError, match=match):
        at.monte_carlo(scene, uncertain=law, n=16, seed=0)
    with pytest.raises(ValueError, match=match):
        at.compare(scene.replace(solid_i="silica-sand"), uncertain=law, n=16,
                   solid_j=["silica-sand", "ilmenite"])
    with pytest.raises(ValueError, match=match):
        at.sweep(scene, uncertain=law, samples=4, h0=[2e-6, 8e-6])
    # with the database's assumptions drawn too, a speed the scene names is not drawn
    with pytest.raises(ValueError, match=match):
        at.monte_carlo(scene, uncertain={**law, "assumed": True}, n=16, seed=0)


def test_an_uncertain_field_a_speed_reads_is_drawn_and_spreads():
    law = {"wake_fraction": UNREAD_LAWS["wake_fraction"]}
    with _quiet():
        mc = at.monte_carlo(at.Scene(**WATER, speed="bubble-darton"), uncertain=law, n=64,
                            seed=0)
        # compared over speeds, the law counts where one option reads it
        ds = at.compare(at.Scene(**WATER), uncertain=law, n=16,
                        speed=["excess-gas", "bubble-darton"])
        robust = at.sweep(at.Scene(**WATER), uncertain=law, samples=8,
                          speed=["excess-gas", "bubble-darton"], h0=[2e-6, 8e-6])
    assert float(mc.propensity_quantile[0]) < float(mc.propensity_quantile[-1])
    assert np.ptp(ds.propensity_quantile.sel(option="bubble-darton").values) > 0
    assert robust.propensity_mean.shape == (2, 2)
    # the scene's U leaves U_Umf unread
    with pytest.raises(ValueError, match="uncertain U_Umf has no effect: the scene gives U"):
        at.monte_carlo(at.Scene(**WATER, U=0.5), uncertain={"U_Umf": at.Uniform(1.5, 3.0)},
                       n=16, seed=0)


_SCENE_TOML = """
[scene]
liquid = "water"
T = "25 degC"
d_i = "500 um"
h0 = "5 um"
{extra}
"""


def _map_file(extra, tail='[grid]\nU_Umf = [1.5, 3.0]\n'):
    return tomllib.loads(_SCENE_TOML.format(extra=extra) + tail)


@pytest.mark.parametrize("extra", ['wake_fraction = 0.3', 'bed_height = 1.0',
                                   'speed = "excess-gas"\ngranular_temperature = 0.01',
                                   'speed = "collisional-balance"\nwake_fraction = 0.3'])
def test_a_scene_field_its_speed_ignores_is_refused_in_a_file(extra):
    """[scene] bed_height = 1.0 beside the default excess-gas speed changed nothing, unsaid
    (exit 0): refused in map, bed and compare files, naming the speeds that read it."""
    field = extra.splitlines()[-1].split(" =")[0]
    match = rf"\[scene\] {field}: {field} has no effect with speed = '[a-z-]+': set"
    with pytest.raises(ConfigError, match=match):
        parse_config(_map_file(extra), "m.toml")
    bed = ('[[component]]\nsolid = "silica-sand"\nfraction = 1.0\nd50 = "500 um"\n')
    with pytest.raises(ConfigError, match=match):
        parse_bed_config(tomllib.loads(_SCENE_TOML.format(extra=extra + "\nU_Umf = 3.0")
                                       + bed), "b.toml")
    from agglomtool.uncertainty.config import parse_compare_config

    cmp = '[compare]\nsolid_j = ["silica-sand", "ilmenite"]\n[uncertain]\nh0 = ' \
          '{ law = "normal", mean = "5 um", sd = "1 um" }\n'
    with pytest.raises(ConfigError, match=match):
        parse_compare_config(tomllib.loads(_SCENE_TOML.format(extra=extra + "\nU_Umf = 3.0")
                                           .replace('h0 = "5 um"\n', "") + cmp), "c.toml")


def test_a_scene_field_a_computing_speed_reads_is_taken():
    with _quiet():
        parse_config(_map_file('speed = "bubble-darton"\nwake_fraction = 0.3'), "m.toml")
        # a speed axis with a bubble model, the models drawn with the assumed values
        parse_config(_map_file('wake_fraction = 0.3', '[grid]\nspeed = ["excess-gas", '
                               '"bubble-darton"]\n'), "m.toml")
        parse_config(_map_file('bed_height = 1.0', '[grid]\nU_Umf = [1.5, 3.0]\n'
                               '[uncertain]\nassumed = true\n'), "m.toml")


def test_a_robust_map_refuses_an_unread_law_before_its_nominal_map(monkeypatch):
    # the refusal of robust_sweep came after the nominal map had been computed
    import agglomtool.maps.plan as plan

    def no_work(*args, **kwargs):
        raise AssertionError("the nominal map was computed before the refusal")

    monkeypatch.setattr(plan.SweepPlan, "evaluate", no_work)
    scene = at.Scene(**WATER, speed="excess-gas")
    with pytest.raises(ValueError, match="uncertain wake_fraction has no effect"):
        at.sweep(scene, uncertain={"wake_fraction": UNREAD_LAWS["wake_fraction"]},
                 samples=4, h0=[2e-6, 8e-6])
