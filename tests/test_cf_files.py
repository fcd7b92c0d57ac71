"""Files other tools read: maps and bed files are CF-1.8 netCDF.

Every file agglomtool writes to netCDF (a map by ``write_map`` and by ``agglomtool map``, a
bed by ``write_map`` and by ``agglomtool bed``, an efficiency matrix by
``export_efficiency``) is checked by the IOOS compliance checker's ``cf:1.8`` suite and read
by cf_xarray and pint-xarray, the tools a user of the files is most likely to reach for.
"""

import datetime
import json
import re

# The checkers are in the ``test`` extra (pyproject.toml): imported, never skipped.
import cf_xarray  # noqa: F401  (registers the .cf accessor)
import cf_xarray.units
import numpy as np
import pint
import pint_xarray  # noqa: F401  (registers the .pint accessor)
import pytest
import xarray as xr
from compliance_checker.base import BaseCheck
from compliance_checker.runner import CheckSuite

import agglomtool as at
from agglomtool import materials
from agglomtool.bed import Component, bed_propensity, bed_sweep, export_efficiency
from agglomtool.cli import main
from agglomtool.maps.export import read_names
from agglomtool.scene import CA_VISCOUS, Resolved, Scene

WATER = Scene(liquid="water", T=298.15, h0=5e-6, d_i=300e-6)
WATER_GRID = dict(solid_j=["silica-sand", "ilmenite"], U_Umf=[2.0, 4.0], h0=[2e-6, 8e-6])
MELT = Scene(u0=0.5, liquid="hypothetical-slag", h0=0.5e-6, d_i=300e-6)
# h0 out of order: a grid may list its values in any order; a file's axis is monotonic.
MELT_GRID = dict(mode=["paper", "relative"], T=[1000.0, 1100.0],
                 h0=[0.2e-6, 0.02e-6, 0.5e-6])
MAP_TOML = """
[scene]
liquid = "water"
T = 323.15
solid_i = "glass-beads"
d_i = 300e-6
[grid]
solid_j = ["glass-beads", "silica-sand"]
U_Umf = [1.5, 3.0]
h0 = [1e-6, 5e-6]
"""
BED_SCENE = Scene(liquid="water", T=298.15, h0=5e-6, U_Umf=2.0)
# No asperity heights given: the bed uses the database's (assumed) values.
BED = [Component("silica-sand", 0.7, d50=800e-6, gsd=1.3, classes=2),
       Component("ilmenite", 0.3, d=[300e-6, 400e-6])]
BED_TOML = """
[scene]
liquid = "water"
T = 298.15
h0 = 5e-6
U_Umf = 2.0
[[component]]
solid = "silica-sand"
fraction = 0.7
d50 = 800e-6
gsd = 1.3
classes = 2
[[component]]
solid = "ilmenite"
fraction = 0.3
d = [300e-6, 400e-6]
[options]
directions = 4
"""
#: CF (section 2.3): names begin with a letter and hold letters, digits and underscores.
CF_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def _names(var) -> bool:
    """Whether ``var`` holds names: str, or (a file's character arrays, as xarray reads
    them) objects that are all str."""
    if var.dtype.kind in "US":
        return True
    return var.dtype.kind == "O" and all(isinstance(x, str) for x in np.ravel(var.values))


@pytest.fixture(scope="module")
def maps():
    return {"water": at.sweep(WATER, **WATER_GRID), "melt": at.sweep(MELT, **MELT_GRID)}


@pytest.fixture(scope="module")
def beds():
    return {"bed_point": bed_propensity(BED_SCENE, BED, directions=4),
            "bed_sweep": bed_sweep(BED_SCENE, BED, directions=4, matrix=True, mix="ilmenite",
                                   U_Umf=[1.5, 3.0], fraction=[0.2, 0.4])}


@pytest.fixture(scope="module")
def files(maps, beds, tmp_path_factory):
    """Every kind of netCDF file agglomtool writes: name -> path."""
    d = tmp_path_factory.mktemp("cf")
    out = {name: at.write_map(ds, d / f"{name}.nc") for name, ds in {**maps, **beds}.items()}
    out["efficiency"] = export_efficiency(beds["bed_point"], d / "efficiency.nc")
    (d / "map.toml").write_text(MAP_TOML)
    out["cli_map"] = d / "cli_map.nc"  # through the resumable store (zarr) and back
    assert main(["map", str(d / "map.toml"), "-o", str(out["cli_map"]), "-q"]) == 0
    (d / "bed.toml").write_text(BED_TOML)
    out["cli_bed"] = d / "cli_bed.nc"
    out["cli_efficiency"] = d / "cli_efficiency.nc"
    assert main(["bed", str(d / "bed.toml"), "-o", str(out["cli_bed"]), "--efficiency",
                 str(out["cli_efficiency"])]) == 0
    return out


FILES = ["water", "melt", "bed_point", "bed_sweep", "efficiency", "cli_map", "cli_bed",
         "cli_efficiency"]
MAP_FILES = ["water", "melt", "cli_map"]


def cf_results(path) -> dict:
    """The failed results of the compliance checker's cf:1.8 suite on ``path``, by level:
    ``{BaseCheck.HIGH: [...], BaseCheck.MEDIUM: [...], BaseCheck.LOW: [...]}``.

    A check that raises instead of judging is a failure. (Its strict monotonicity check
    had raised on a coordinate of names written as netCDF-4 strings; names are character
    arrays now, and every check judges every file.)"""
    cs = CheckSuite()
    cs.load_all_available_checkers()
    nc = cs.load_dataset(str(path))
    try:
        results, crashed = cs.run_all(nc, ["cf:1.8"], [], [])["cf:1.8"]
        coords = {k: v[:] for k, v in nc.variables.items() if v.dimensions == (k,)}
    finally:
        nc.close()
    names = [k for k, v in coords.items() if np.asarray(v).dtype.kind in "OUS"]
    assert not crashed, f"checks that raised instead of judging the file: {crashed}"
    out = {BaseCheck.HIGH: [], BaseCheck.MEDIUM: [], BaseCheck.LOW: []}
    for r in results:
        ok = r.value if isinstance(r.value, bool) else r.value[0] >= r.value[1]
        if not ok:
            out[r.weight].extend(f"{r.name}: {m}" for m in (r.msgs or ["(no message)"]))
    for k, v in coords.items():  # CF 1.2: coordinate variables are strictly monotonic
        if k not in names and v.size > 1:
            step = np.diff(np.asarray(v, dtype=float))
            if not (np.all(step > 0) or np.all(step < 0)):
                out[BaseCheck.HIGH].append(f"coordinate {k} is not strictly monotonic: {v}")
    return out


@pytest.mark.parametrize("name", FILES)
def test_cf_checker_finds_no_high_or_medium_failures(files, name):
    """The checker's levels: HIGH is what CF-1.8 says a file MUST do (units UDUNITS can read,
    flag_values of the variable's type, no _FillValue on coordinate variables, netCDF
    classic integer types, strictly monotonic coordinates), MEDIUM what it SHOULD do
    (Conventions, history, names of letters, digits and underscores). A failure at either
    level makes a file that CF tools may misread, so there must be none. LOW holds the
    checker's suggestions beyond CF's requirements (none fail today); they are not asserted,
    so that a new suggestion in a later checker does not read as a broken file."""
    failed = cf_results(files[name])
    assert failed[BaseCheck.HIGH] == [], "\n".join(failed[BaseCheck.HIGH])
    assert failed[BaseCheck.MEDIUM] == [], "\n".join(failed[BaseCheck.MEDIUM])


@pytest.mark.parametrize("name", FILES)
def test_pint_xarray_gives_every_number_a_unit(files, name):
    """``ds.pint.quantify()`` (pint's own registry) makes every numeric variable a Quantity in
    the units its attributes state; names (solids, modes, components) stay plain strings,
    and the quantified Dataset can still be selected by name."""
    ureg = pint.get_application_registry()
    with xr.open_dataset(files[name]) as ds:
        q = ds.pint.quantify()
        for k, var in ds.variables.items():
            if _names(var):
                assert "units" not in var.attrs, k
                assert not isinstance(q[k].data, pint.Quantity), k
                continue
            assert "units" in var.attrs, k
            if k in ds.data_vars:
                assert isinstance(q[k].data, pint.Quantity), k
            assert q[k].pint.units == ureg.Unit(var.attrs["units"]), k
        for k in (k for k in ds.dims if k in ds and _names(ds[k])):
            label = str(ds[k].values[-1])
            assert str(q.sel({k: label})[k].values) == label


@pytest.mark.parametrize("name", FILES)
def test_cf_xarray_units_read_every_number(files, name):
    """cf_xarray's UDUNITS-style registry quantifies every numeric variable, coordinates
    included, and leaves the names alone."""
    ureg = cf_xarray.units.units
    with xr.open_dataset(files[name]) as ds:
        q = ds.pint.quantify(unit_registry=ureg)
        for k, var in ds.variables.items():
            if _names(var):
                assert not isinstance(q[k].data, pint.Quantity), k
            else:
                assert q[k].pint.units == ureg.Unit(var.attrs["units"]), k


@pytest.mark.parametrize("name", MAP_FILES)
def test_cf_xarray_decodes_the_flags(files, name):
    """cf_xarray turns ``flag_values``/``flag_meanings`` into masks that mean what the
    variables are defined to mean."""
    with xr.open_dataset(files[name]) as ds:
        for k in ("u_star_flag", "regime", "stage", "agglomerated"):
            assert ds[k].cf.is_flag_variable, k
        flags = ds.agglomerated.cf.flags
        np.testing.assert_array_equal(flags["sticks"], ds.e_w == 0.0)
        np.testing.assert_array_equal(flags["rebounds"], ds.e_w > 0.0)
        regime = ds.regime.cf.flags
        np.testing.assert_array_equal(regime["viscous_limited"], ds.Ca_star > CA_VISCOUS)
        u_flag = ds.u_star_flag.cf.flags
        np.testing.assert_array_equal(u_flag["no_bridge"], ds.u_star == 0.0)
        np.testing.assert_array_equal(u_flag["sticks_up_to_ceiling"], np.isinf(ds.u_star))
        stage = ds.stage.cf.flags
        np.testing.assert_array_equal(stage["rebound"], ds.e_w > 0.0)


@pytest.mark.parametrize("name", FILES)
def test_global_attributes_name_the_file(files, name):
    """Conventions, title, source and a history line (a UTC time, the version, the call or
    command); every attribute name is a CF name."""
    with xr.open_dataset(files[name]) as ds:
        attrs = ds.attrs
        bad = [k for v in ds.variables.values() for k in v.attrs if not CF_NAME.match(k)]
    assert attrs["Conventions"] == "CF-1.8"
    assert attrs["title"].startswith("agglomtool")
    assert at.__version__ in attrs["source"]
    assert [k for k in attrs if not CF_NAME.match(k)] == [] and bad == []
    line = attrs["history"].splitlines()[0]
    stamp, _, rest = line.partition(" ")
    when = datetime.datetime.fromisoformat(stamp)
    assert abs(datetime.datetime.now(datetime.UTC) - when) < datetime.timedelta(minutes=30)
    assert f"agglomtool {at.__version__}" in rest
    if name.startswith("cli_"):
        assert f"agglomtool {'map' if name == 'cli_map' else 'bed'} " in rest
        assert str(files[name]) in rest
    elif name == "efficiency":
        assert "export_efficiency" in rest
    else:
        assert "write_map" in rest and files[name].name in rest


def test_map_provenance_is_kept_whole(maps, files):
    """Every resolved input of the scene (value, units, origin, confidence) and every
    material's source survive in the file, under CF names (nothing a user gave is lost)."""
    with xr.open_dataset(files["water"]) as ds:
        prov = json.loads(ds.attrs["provenance"])
        sources = json.loads(ds.attrs["material_sources"])
    first = {**WATER.values(), **{k: (str(v[0]) if isinstance(v[0], str) else float(v[0]))
                                  for k, v in WATER_GRID.items()}}
    expected = {k: v for k, v in WATER.replace(**{k: first[k] for k in WATER_GRID})
                .provenance().items() if k not in WATER_GRID}
    assert set(prov) == set(expected)
    for k, (value, _units, origin, conf) in expected.items():
        assert prov[k]["value"] == value and prov[k]["origin"] == origin, k
        assert prov[k]["confidence"] == conf, k
    assert prov["T"]["units"] == "K" and prov["eps"]["units"] == "1"
    for solid in WATER_GRID["solid_j"]:
        r = Resolved({**first, "solid_j": solid})
        for key, text in r.sources.items():
            assert sources[key] == " ".join(text.split()), key


@pytest.mark.parametrize("name", ["bed_point", "bed_sweep", "cli_bed"])
def test_bed_files_carry_provenance_and_assumed_values(files, name):
    """A bed file says what a map says: every input's origin, the database values that are
    assumptions (here the asperity heights no component gives) and the materials' sources."""
    with xr.open_dataset(files[name]) as ds:
        attrs = ds.attrs
    prov = json.loads(attrs["provenance"])
    assert prov["T"]["value"] == 298.15 and prov["T"]["origin"] == "given"
    for c in BED:
        entry = materials.solid(c.solid)
        assert prov[f"{entry.name} density"]["value"] == entry.density
        for field in entry.assumed:
            text = f"{entry.name} {field}"
            assert text in attrs["assumed_inputs"], text
            assert prov[text]["confidence"] == "assumed", text
    sources = json.loads(attrs["material_sources"])
    for c in BED:
        assert sources[f"solid {c.solid}"] == " ".join(materials.solid(c.solid).source.split())
    assert "liquid water" in sources and "gas air" in sources


@pytest.mark.parametrize("name", MAP_FILES)
def test_map_round_trip_reads_back_the_same_map(maps, files, name):
    """write_map then xarray: the same numbers and types (agglomerated a boolean again;
    names, which the file holds as character arrays that xarray reads as objects, str
    again through read_names, as open_map reads them), a numeric axis given out of order
    in increasing order."""
    with xr.open_dataset(files[name]) as back:
        back = read_names(back.load())
    assert back.agglomerated.dtype == bool
    np.testing.assert_array_equal(back.agglomerated, back.e_w == 0.0)
    if name in maps:
        assert "history" not in maps[name].attrs  # writing left the map as it was
        numeric = [d for d in maps[name].dims if maps[name][d].dtype.kind == "f"]
        xr.testing.assert_equal(back, maps[name].sortby(numeric))
        for k, var in maps[name].variables.items():
            assert back[k].dtype == var.dtype, k
            for a, v in var.attrs.items():
                np.testing.assert_array_equal(back[k].attrs[a], v, err_msg=f"{k} {a}")


@pytest.mark.parametrize("var", ["agglomerated", "stage", "propensity"])
def test_cli_plot_reads_the_file(files, tmp_path, var):
    png = tmp_path / f"{var}.png"
    assert main(["plot", str(files["water"]), "-o", str(png), "--var", var]) == 0
    assert png.stat().st_size > 10_000


def test_write_map_refuses_what_a_cf_file_cannot_hold(tmp_path):
    """A repeated coordinate value cannot be made monotonic, flag values outside the
    variable's type cannot be stored, 64-bit integers beyond 32 bits cannot be kept:
    each is a ValueError naming the variable, and no file is left behind."""
    x = xr.DataArray([1.0, 2.0, 1.0], dims=["x"], attrs={"units": "m", "long_name": "x"})
    ds = xr.Dataset({"v": (("x",), [0.0, 1.0, 2.0], {"units": "1", "long_name": "v"})},
                    coords={"x": x})
    with pytest.raises(ValueError, match="coordinate x repeats a value"):
        at.write_map(ds, tmp_path / "a.nc")
    flags = xr.Dataset({"f": (("n",), np.array([0, 1], np.int8),
                              {"flag_values": [0, 300], "flag_meanings": "a b"})})
    with pytest.raises(ValueError, match=r"variable f: flag_values = \[0, 300\]"):
        at.write_map(flags, tmp_path / "b.nc")
    big = xr.Dataset({"n": (("k",), np.array([0, 2**40]), {"units": "1"})})
    with pytest.raises(ValueError, match="variable n: values 0-1099511627776"):
        at.write_map(big, tmp_path / "c.nc")
    assert list(tmp_path.iterdir()) == []
