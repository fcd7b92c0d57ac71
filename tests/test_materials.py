"""The materials database: every entry loads and validates; broken files fail clearly."""

import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

from agglomtool import materials
from agglomtool.inputs import Gas, Liquid, Particle
from agglomtool.properties import gas_properties

T_FOR = {"water": 298.15}


@pytest.mark.parametrize("kind", materials.KINDS)
def test_every_entry_loads(kind):
    names = materials.names(kind)
    assert len(names) >= 5
    for name in names:
        if kind == "solid":
            s = materials.solid(name)
            assert isinstance(s.particle(np.mean(s.size_range)), Particle)
            entry = s
        elif kind == "liquid":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # calibration warnings are tested elsewhere
                liq = materials.liquid(name, T=T_FOR.get(name, 1273.15))
            assert isinstance(liq, Liquid) and np.all(np.isfinite(liq.mu))
            entry = materials.liquid_entry(name)
        else:
            entry = materials.gas(name)
            assert isinstance(gas_properties(1073.15, 1e5, name), Gas)
        assert entry.source.strip() and entry.confidence.strip()


def test_required_entries_and_name_forms():
    for name in ("silica sand", "Ilmenite", "olivine", "dense_alumina", "glass-beads"):
        materials.solid(name)
    assert materials.solid("silica sand").density == 2650.0
    for name in ("water", "hypothetical slag", "blast furnace slag"):
        materials.liquid_entry(name)
    for name in ("air", "nitrogen", "carbon dioxide", "steam", "biomass flue gas"):
        materials.gas(name)
    with pytest.raises(ValueError, match="solid = 'sand castle' is not in the materials"):
        materials.solid("sand castle")
    with pytest.raises(ValueError, match="pass T"):
        materials.liquid("water")


def _write(tmp_path, text, name="mine.toml"):
    d = tmp_path / "mats"
    d.mkdir(exist_ok=True)
    (d / name).write_text(text)
    return d


def test_user_directory_argument_and_environment(tmp_path, monkeypatch):
    d = _write(tmp_path, """
[solid.my-sand]
density = 2600.0
asperity_height = 2e-6
restitution_dry = 0.8
size_range = [2e-4, 6e-4]
source = "my lab"
confidence = "measured once"
""")
    assert materials.solid("my sand", extra_dirs=d).density == 2600.0
    monkeypatch.setenv(materials.ENV_VAR, str(d))
    assert "my-sand" in materials.names("solid")
    assert "silica-sand" in materials.names("solid")


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[solid.bad]\ndensity = 'heavy'\n", r"\[solid.bad\] field 'density': must be a number"),
        ("[solid.bad]\ndensity = -3.0\n", r"field 'density': -3.0 is outside"),
        ("[solid.bad]\ndensity = 2600.0\nasperity_height = 1e-6\nrestitution_dry = 0.8\n"
         "size_range = [6e-4, 2e-4]\nsource = 'x'\nconfidence = 'y'\n", "field 'size_range'"),
        ("[solid.bad]\ndensity = 2600.0\ncolour = 'red'\n", "field 'colour': is not a known"),
        ("[liquid.bad]\nmodel = 'fixed'\ntheta_deg = 0.0\nmu = 1.0\ngamma = 0.1\n"
         "source = 's'\nconfidence = 'c'\n", "field 'rho': is missing"),
        ("[liquid.bad]\nmodel = 'melt'\ntheta_deg = 0.0\ncomposition_wt = {SiO2 = 60.0, "
         "Kryptonite = 40.0}\nsource = 's'\nconfidence = 'c'\n",
         "field 'composition_wt.Kryptonite': unknown oxide"),
        ("[liquid.bad]\nmodel = 'melt'\ntheta_deg = 0.0\ncomposition_wt = {SiO2 = 60.0}\n"
         "source = 's'\nconfidence = 'c'\n", "field 'composition_wt': amounts sum to 60"),
        ("[gas.bad]\ncomposition = {N2 = 0.5}\nsource = 's'\nconfidence = 'c'\n",
         r"\[gas.bad\] field 'composition': amounts sum to 0.5"),
        ("[gas.bad]\ncomposition = {N2 = 1.0}\nconfidence = 'c'\n", "field 'source': is missing"),
        ("[mineral.bad]\ndensity = 1.0\n", r"top-level table \[mineral\]"),
        ("[solid.bad\ndensity = 1.0\n", "not valid TOML"),
    ],
)
def test_broken_files_name_file_entry_and_field(tmp_path, text, match):
    d = _write(tmp_path, text, name="broken.toml")
    with pytest.raises(materials.MaterialsError, match=match) as info:
        materials.load(extra_dirs=d)
    assert "broken.toml" in str(info.value)


def test_duplicate_name_is_an_error(tmp_path):
    d = _write(tmp_path, "[gas.air]\ncomposition = {N2 = 1.0}\nsource = 's'\n"
                         "confidence = 'c'\n")
    with pytest.raises(materials.MaterialsError, match=r"\[gas.air\] is already defined"):
        materials.load(extra_dirs=d)


def test_missing_user_directory(tmp_path):
    with pytest.raises(materials.MaterialsError, match="does not exist"):
        materials.load(extra_dirs=tmp_path / "nowhere")


def test_data_found_from_a_source_checkout():
    # This test suite runs from the repository (editable or plain checkout): the loader must
    # fall back to <repo>/materials. The installed-wheel path is checked by hand (report).
    here = materials.builtin_dir()
    assert here.name in ("materials", "_materials")
    code = "from agglomtool import materials; print(materials.builtin_dir())"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env={**os.environ, materials.ENV_VAR: ""})
    assert out.stdout.strip() == str(here)
