"""An output file whose directory is missing or is a file is refused before any work, with
a message that names the directory (netCDF's own error said 'Permission denied' for both,
and the bed command said it after computing the bed)."""

from pathlib import Path

import pytest
import xarray as xr

import agglomtool as at
from agglomtool.cli import main

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "configs" / "bed_sand_ilmenite.toml"


@pytest.fixture
def not_a_dir(tmp_path):
    f = tmp_path / "afile"
    f.write_text("")
    return f


def test_write_map_names_a_missing_directory(tmp_path):
    ds = xr.Dataset({"x": ("a", [1.0, 2.0])})
    with pytest.raises(ValueError, match=r"directory '.*missing' does not exist"):
        at.write_map(ds, tmp_path / "missing" / "m.nc")
    assert not (tmp_path / "missing").exists()


def test_write_map_names_a_file_in_place_of_the_directory(not_a_dir):
    ds = xr.Dataset({"x": ("a", [1.0, 2.0])})
    with pytest.raises(ValueError, match=r"'.*afile' is not a directory"):
        at.write_map(ds, not_a_dir / "m.nc")


@pytest.mark.parametrize("where", ["missing", "afile"])
def test_bed_command_refuses_the_output_before_computing(where, tmp_path, not_a_dir, capsys):
    out = tmp_path / where / "bed.nc"
    assert main(["bed", str(EXAMPLE), "-o", str(out), "-q"]) == 2
    captured = capsys.readouterr()
    assert "bed propensity" not in captured.out  # refused before the bed was computed
    assert f"{tmp_path / where}" in captured.err and "Permission denied" not in captured.err


MAP_EXAMPLE = EXAMPLE.with_name("granulator_window.toml")


@pytest.mark.parametrize("name", ["w.png", "w.PDF", "w.csv"])
def test_a_picture_or_text_name_is_refused_for_a_netcdf_file(tmp_path, name, capsys,
                                                             monkeypatch):
    """``map -o x.png`` wrote a netCDF file named x.png (exit 0); now refused before the
    sweep, with the command that draws a picture."""
    import agglomtool.maps.grid as grid

    def no_sweep(*a, **k):
        raise AssertionError("the map was computed")

    monkeypatch.setattr(grid, "sweep", no_sweep)
    out = tmp_path / name
    assert main(["map", str(MAP_EXAMPLE), "-o", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert name in err and ".nc" in err and "agglomtool plot" in err
    assert not out.exists()
    with pytest.raises(ValueError, match=r"ending of a picture or a text file"):
        at.write_map(xr.Dataset({"x": ("a", [1.0, 2.0])}), out)
    assert not out.exists()
    bed = EXAMPLE.with_name("bed_sand_ilmenite.toml")
    assert main(["bed", str(bed), "-o", str(out), "-q"]) == 2
    assert not out.exists()


def test_the_map_command_refuses_a_missing_directory_before_computing(tmp_path, capsys,
                                                                     monkeypatch):
    import agglomtool.maps.grid as grid

    def no_sweep(*a, **k):
        raise AssertionError("the map was computed")

    monkeypatch.setattr(grid, "sweep", no_sweep)
    assert main(["map", str(MAP_EXAMPLE), "-o", str(tmp_path / "missing" / "m.nc"),
                 "-q"]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_a_directory_is_refused_as_an_output_file(tmp_path, capsys):
    with pytest.raises(ValueError, match=r"is a directory; give a file name \(\.nc\)"):
        at.write_map(xr.Dataset({"x": ("a", [1.0, 2.0])}), tmp_path)
    assert main(["map", str(MAP_EXAMPLE), "-o", str(tmp_path), "-q"]) == 2
    assert "is a directory; give a file name (.nc)" in capsys.readouterr().err


@pytest.fixture
def read_only_dir(tmp_path, monkeypatch):
    """A directory this process may not write: its permission bits, and where they do not
    bind (root), the kernel's answer to access(2) as a read-only file system gives it."""
    import os

    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o555)
    if os.access(ro, os.W_OK):  # root: permission bits do not bind
        real = os.access

        def access(path, mode, *a, **k):
            if Path(path).absolute() == ro.absolute() and mode & os.W_OK:
                return False
            return real(path, mode, *a, **k)

        monkeypatch.setattr(os, "access", access)
    yield ro
    ro.chmod(0o755)


def test_outputs_in_a_directory_not_writable_are_refused_before_any_work(
        read_only_dir, tmp_path, capsys, monkeypatch):
    """A read-only output directory: the map was computed (into a store elsewhere) and the
    bed computed, then netCDF said 'Permission denied' on a temporary file; a store there
    failed on its writer lock with the system's error. Now refused first, naming it."""
    import agglomtool.maps.grid as grid

    def no_sweep(*a, **k):
        raise AssertionError("the map was computed")

    monkeypatch.setattr(grid, "sweep", no_sweep)
    out = read_only_dir / "m.nc"
    assert main(["map", str(MAP_EXAMPLE), "-o", str(out), "--store",
                 str(tmp_path / "st"), "-q"]) == 2
    err = capsys.readouterr().err
    assert f"directory '{read_only_dir}' is not writable" in err, err
    assert main(["bed", str(EXAMPLE), "-o", str(out), "-q"]) == 2
    captured = capsys.readouterr()
    assert "bed propensity" not in captured.out
    assert f"directory '{read_only_dir}' is not writable" in captured.err
    with pytest.raises(ValueError, match=r"directory '.*ro' is not writable"):
        at.write_map(xr.Dataset({"x": ("a", [1.0, 2.0])}), out)


@pytest.mark.parametrize("inside", ["", "new"])
def test_a_store_on_a_path_not_writable_is_refused_naming_it(read_only_dir, inside):
    store = read_only_dir / inside if inside else read_only_dir
    scene = at.Scene(liquid="water", T=298.15, d_i=300e-6)
    with pytest.raises(ValueError, match=rf"store = '{store}' is not writable"):
        at.sweep(scene, U_Umf=[1.5, 3.0], h0=[2e-6, 5e-6], store=store)
