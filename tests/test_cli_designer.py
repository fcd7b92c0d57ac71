"""The command line as a bed designer uses it (comparisons, fixed dimensions, help texts)."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

import agglomtool.maps.layout as grid_module  # where the block functions look up the core
from agglomtool.cli import main

COMPARE = """
[scene]
liquid = "water"
T = 298.15
h0 = 5e-6
[grid]
solid_j = ["silica-sand", "ilmenite", "olivine"]
U_Umf = [2.0, 4.0]
"""


def _write(tmp_path, text, name="c.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_material_comparison_from_a_config(tmp_path, capsys):
    out = tmp_path / "cmp.nc"
    assert main(["map", str(_write(tmp_path, COMPARE)), "-o", str(out), "-q"]) == 0
    with xr.open_dataset(out) as ds:
        assert ds.propensity.dims == ("solid_j", "U_Umf")
        assert list(ds.solid_j.values) == ["silica-sand", "ilmenite", "olivine"]
    only = COMPARE.replace('U_Umf = [2.0, 4.0]\n', "")
    out2 = tmp_path / "only.nc"
    assert main(["map", str(_write(tmp_path, only, "o.toml")), "-o", str(out2), "-q"]) == 0
    png = tmp_path / "only.png"
    assert main(["plot", str(out2), "-o", str(png), "--var", "u_star"]) == 0
    assert png.stat().st_size > 5_000


def test_map_is_written_compressed(tmp_path):
    """Lossless zlib: a 50k-point map shrinks (the 20 MB map of the benchmark to 0.72)."""
    import agglomtool as at
    from agglomtool.maps.export import write_map

    ds = at.sweep(at.Scene(liquid="water", T=298.15, h0=5e-6),
                  solid_j=["silica-sand", "ilmenite"], U_Umf=np.linspace(1.5, 8.0, 50),
                  h0=np.geomspace(1e-6, 100e-6, 50), d_i=np.linspace(200e-6, 900e-6, 10))
    small = write_map(ds, tmp_path / "z.nc")
    big = write_map(ds, tmp_path / "raw.nc", complevel=0)
    assert small.stat().st_size < 0.85 * big.stat().st_size
    with xr.open_dataset(small) as a:
        assert a.attrs.pop("history")  # the file records when and how it was written
        xr.testing.assert_identical(a.load(), ds)  # lossless
        assert a.e_w.encoding["zlib"]


def test_interrupted_map_says_how_to_resume_and_the_rerun_finishes(tmp_path, capsys,
                                                                   monkeypatch):
    text = COMPARE + "[options]\nchunks = 1\n"
    cfg, out = _write(tmp_path, text), tmp_path / "m.nc"
    real = grid_module.flagged_collision_outputs
    calls = {"n": 0}

    def flaky(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(grid_module, "flagged_collision_outputs", flaky)
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 130
    err = capsys.readouterr().err
    assert "interrupted" in err and "run the same command again" in err
    assert "Traceback" not in err and not out.exists()
    monkeypatch.setattr(grid_module, "flagged_collision_outputs", real)
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 0  # resumes, never refuses
    fresh = tmp_path / "fresh.nc"
    assert main(["map", str(cfg), "-o", str(fresh), "-q", "--store",
                 str(tmp_path / "other")]) == 0
    with xr.open_dataset(out) as a, xr.open_dataset(fresh) as b:
        # each file's history names its own command; the rest is the same map
        assert str(out) in a.attrs.pop("history") and str(fresh) in b.attrs.pop("history")
        xr.testing.assert_identical(a.load(), b.load())


@pytest.mark.parametrize("argv,needle", [
    (["plot", "nothere.nc", "-o", "x.png"], "does not exist"),
    (["map", "nothere.toml", "-o", "x.nc"], "no such file"),
    (["collide", "--liquid", "water"], "T = 1073.15 K is the Scene's default"),
    (["collide", "--mode", "fast"], "invalid choice"),
    (["plot", "--sel", "d_i", "m.nc", "-o", "x.png"], "NAME=VALUE"),
])
def test_errors_are_one_line_without_traceback(argv, needle, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    if argv[0] == "plot" and "m.nc" in argv:
        import agglomtool as at

        at.sweep(at.Scene(u0=0.5), T=[1000.0, 1100.0]).to_netcdf(tmp_path / "m.nc")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert needle in err and "Traceback" not in err


def test_missing_matplotlib_gives_the_install_hint(tmp_path, monkeypatch, capsys):
    import agglomtool as at

    at.sweep(at.Scene(u0=0.5), T=[1000.0, 1100.0]).to_netcdf(tmp_path / "m.nc")
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    assert main(["plot", str(tmp_path / "m.nc"), "-o", str(tmp_path / "x.png")]) == 2
    assert "pip install 'agglomtool[plot]'" in capsys.readouterr().err


def test_help_states_the_true_defaults_and_allowed_names(capsys):
    assert main(["collide", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    options = text.split("options:")[1]
    u0_help = options.split("--u0 M/S")[1][:200]
    assert "(default: 0.5)" not in u0_help  # the old, wrong default
    assert "excess-gas" in options.split("--speed NAME")[1][:300]
    for name in ("silica-sand", "ilmenite", "water", "hypothetical-slag", "relative"):
        assert name in text
    assert "SCENE_" not in text


def test_help_and_version_do_not_import_the_heavy_parts():
    code = ("import sys; from agglomtool.cli import main; main(['--version']); "
            "main(['--help']); main(['collide', '--help']); "
            "heavy = [m for m in ('CoolProp', 'numba', 'xarray', 'dask', 'matplotlib') "
            "if m in sys.modules]; print('HEAVY', heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert "HEAVY []" in out


def test_collide_reports_the_ceiling_not_an_absurd_speed(capsys):
    assert main(["collide", "--liquid", "k-silicate-ash-melt", "--gas", "biomass-flue-gas",
                 "--T", "1173.15", "--h0", "1e-6"]) == 0
    out = capsys.readouterr().out
    assert "above the ceiling of 10 m/s" in out
    assert not any(f"u0* = {v}" in out for v in ("1e+04", "2.91e+05", "8.17e+06"))


def test_an_interrupt_a_library_turns_into_its_own_error_is_an_interruption(
        tmp_path, capsys, monkeypatch):
    """Ctrl-C while Numba compiles a kernel (the first map of a session, ~10-20 s): Numba's
    compiler catches the KeyboardInterrupt and raises 'RuntimeError: no compiled object
    yet', and the command ended with that traceback. After an interrupt, the command says
    it was interrupted and how to resume, whatever error follows."""
    import signal

    text = COMPARE + "[options]\nchunks = 1\n"
    cfg, out = _write(tmp_path, text), tmp_path / "m.nc"

    def compiling(*args, **kwargs):  # as numba's compiler meets the interrupt
        try:
            signal.raise_signal(signal.SIGINT)
        except KeyboardInterrupt:
            pass
        raise RuntimeError("no compiled object yet for <Library '_excess_block'>")

    monkeypatch.setattr(grid_module, "flagged_collision_outputs", compiling)
    assert main(["map", str(cfg), "-o", str(out), "-q"]) == 130
    err = capsys.readouterr().err
    assert "interrupted" in err and "run the same command again" in err
    assert "RuntimeError" not in err and not out.exists()
    # an error with no interrupt before it is not one
    monkeypatch.setattr(grid_module, "flagged_collision_outputs",
                        lambda *a, **k: (_ for _ in ()).throw(RuntimeError("a bug")))
    with pytest.raises(RuntimeError, match="a bug"):
        main(["map", str(cfg), "-o", str(tmp_path / "n.nc"), "-q"])
