"""User materials files: names normalised at load, clashes refused, unreadable files named;
a mistyped name answered with the closest known one."""

import re

import pytest

import agglomtool as at
from agglomtool import materials

SOLID = """
density = {density}
asperity_height = 1e-6
restitution_dry = 0.8
size_range = [2e-4, 6e-4]
source = "my lab"
confidence = "measured once"
"""


def _dir(tmp_path, text, name="user.toml"):
    d = tmp_path / "m"
    d.mkdir(exist_ok=True)
    (d / name).write_text(text) if isinstance(text, str) else (d / name).write_bytes(text)
    return d


def test_mixed_case_and_underscore_names_are_normalised_and_usable(tmp_path):
    d = _dir(tmp_path, "[solid.My_Sand]" + SOLID.format(density=1500.0))
    assert "my-sand" in materials.names("solid", extra_dirs=d)
    assert "My_Sand" not in materials.names("solid", extra_dirs=d)
    for spelling in ("My_Sand", "my-sand", "MY SAND"):
        entry = materials.solid(spelling, extra_dirs=d)
        assert entry.density == 1500.0 and entry.name == "my-sand"


def test_user_entry_that_normalises_to_a_builtin_is_refused(tmp_path):
    d = _dir(tmp_path, "[solid.silica_sand]" + SOLID.format(density=1500.0))
    with pytest.raises(materials.MaterialsError, match="built-in") as info:
        materials.names("solid", extra_dirs=d)
    msg = str(info.value)
    assert "silica_sand" in msg and "user.toml" in msg and "solids.toml" in msg


def test_two_spellings_of_one_name_in_a_file_are_refused(tmp_path):
    d = _dir(tmp_path, "[solid.my-sand]" + SOLID.format(density=1500.0)
             + "[solid.My_Sand]" + SOLID.format(density=1600.0))
    with pytest.raises(materials.MaterialsError, match="both named 'my-sand'"):
        materials.load(extra_dirs=d)


def test_name_with_forbidden_characters_is_refused(tmp_path):
    d = _dir(tmp_path, '[solid."sand/2"]' + SOLID.format(density=1500.0))
    with pytest.raises(materials.MaterialsError, match=r"sand/2.*letters, digits"):
        materials.load(extra_dirs=d)


def test_non_utf8_file_names_the_file(tmp_path):
    text = ("[solid.sable]" + SOLID.format(density=1500.0)).replace("my lab", "labo \xe9t\xe9")
    d = _dir(tmp_path, text.encode("latin-1"), name="latin.toml")
    with pytest.raises(materials.MaterialsError, match="latin.toml: is not UTF-8"):
        materials.load(extra_dirs=d)


def test_deeply_nested_file_names_the_file(tmp_path):
    d = _dir(tmp_path, "x = " + "[" * 100_000 + "]" * 100_000 + "\n", name="deep.toml")
    with pytest.raises(materials.MaterialsError, match="deep.toml: .*nested too deeply"):
        materials.load(extra_dirs=d)


def test_fingerprint_follows_the_file_contents(tmp_path):
    d = _dir(tmp_path, "[solid.my-sand]" + SOLID.format(density=1500.0))
    used = {"solid": ["my-sand", "silica-sand"]}
    before = materials.fingerprint(used, extra_dirs=d)
    assert before["solid silica-sand"].startswith("agglomtool:solids.toml ")
    assert str((d / "user.toml").resolve()) in before["solid my-sand"]
    (d / "user.toml").write_text("[solid.my-sand]" + SOLID.format(density=2650.0))
    after = materials.fingerprint(used, extra_dirs=d)
    assert after["solid silica-sand"] == before["solid silica-sand"]
    assert after["solid my-sand"] != before["solid my-sand"]


def test_an_edited_file_is_read_again(tmp_path):
    d = _dir(tmp_path, "[solid.my-sand]" + SOLID.format(density=1500.0))
    assert materials.solid("my-sand", extra_dirs=d).density == 1500.0
    (d / "user.toml").write_text("[solid.my-sand]" + SOLID.format(density=2650.0) + "\n")
    assert materials.solid("my-sand", extra_dirs=d).density == 2650.0


@pytest.mark.parametrize("make, needle", [
    (lambda: at.Scene(liquid="k-silicate"), "did you mean 'k-silicate-ash-melt'?"),
    (lambda: at.Scene(solid_i="silica_snad"), "did you mean 'silica-sand'?"),
    (lambda: at.Scene(speed="darton"), "did you mean 'bubble-darton'?"),
    (lambda: materials.liquid("hypothetical slag "), None),  # normalised: found
    (lambda: materials.liquid("hypotetical-slag"), "did you mean 'hypothetical-slag'?"),
])
def test_a_mistyped_name_is_answered_with_the_closest_known(make, needle):
    if needle is None:
        make()
        return
    with pytest.raises(ValueError, match=re.escape(needle)):
        make()


def test_a_name_near_nothing_gets_the_list_only():
    with pytest.raises(ValueError, match=r"'honey' is not in the materials database; known "
                                         r"liquids: .*water") as err:
        at.Scene(liquid="honey")
    assert "did you mean" not in str(err.value)


def test_a_mistyped_key_of_a_config_is_answered_with_the_closest_field():
    import tomllib

    from agglomtool.bed.config import parse_bed_config
    from agglomtool.maps.config import ConfigError, parse_config

    with pytest.raises(ConfigError, match=re.escape("[scene] h_0: not a Scene field (did you "
                                                    "mean 'h0'?); fields: T, P")):
        parse_config(tomllib.loads('[scene]\nh_0 = "5 um"\n[grid]\nT = [300.0]\n'))
    with pytest.raises(ConfigError, match=re.escape("[grid] U_mf: not a Scene field (did you "
                                                    "mean 'U_Umf'?)")):
        parse_config(tomllib.loads('[grid]\nU_mf = [2.0, 3.0]\n'))
    text = ('[scene]\nliquid = "water"\n[[component]]\nsolid = "silica-sand"\nfraction = 1.0\n'
            'd_50 = "1 mm"\n')
    with pytest.raises(ConfigError, match=re.escape("d_50: unknown (did you mean 'd50'?); "
                                                    "allowed: solid")):
        parse_bed_config(tomllib.loads(text))
    with pytest.raises(ValueError, match=re.escape("'h_0' is not a Scene field (did you mean "
                                                   "'h0'?)")):
        at.Scene().replace(h_0=1e-6)
