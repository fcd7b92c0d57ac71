"""A value a picture's error prints (or suggests) selects that grid value: grid values are
shown to 6 significant digits, so a value typed as shown must match it; a material is
selected by any spelling the database accepts."""

import re

import numpy as np
import pytest

import agglomtool as at
from agglomtool.cli import main
from agglomtool.plots import plan_layout

H0 = np.geomspace(1e-6, 30e-6, 12)
U_UMF = np.linspace(1.2, 8.0, 12)


@pytest.fixture(scope="module")
def ds():
    return at.sweep(at.Scene(liquid="water", T=298.15, d_i=300e-6),
                    solid_j=["silica-sand", "ilmenite"], U_Umf=U_UMF, h0=H0)


@pytest.fixture(scope="module")
def path(ds, tmp_path_factory):
    # numbers only: a file with names on an axis may not be opened while it is open
    # (netCDF-4 strings crash HDF5 then), and the command line leaves its file to the
    # garbage collector
    out = tmp_path_factory.mktemp("sel") / "m.nc"
    at.write_map(ds.sel(solid_j="ilmenite", drop=True), out)
    return out


def _printed_values(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    return re.search(r"values: (.*)$", err.strip()).group(1).split(", ")


@pytest.mark.parametrize("dim, grid", [("h0", H0), ("U_Umf", U_UMF)])
def test_each_value_the_error_prints_selects_its_grid_value(ds, path, tmp_path, capsys, dim,
                                                            grid):
    other = {"h0": "U_Umf", "U_Umf": "h0"}[dim]
    base = ["plot", str(path), "-o", str(tmp_path / "p.png"), "--x", other]
    shown = _printed_values(capsys, base + ["--sel", f"{dim}=12345"])
    assert len(shown) == grid.size
    for k, text in enumerate(shown):
        assert main(base + ["--sel", f"{dim}={text}"]) == 0, text
        assert f"{dim} = " in capsys.readouterr().out
        layout = plan_layout(ds, sel={dim: float(text), "solid_j": "ilmenite"})
        assert layout.sel[dim] == pytest.approx(grid[k], rel=1e-12)


def test_the_suggested_selection_selects(ds):
    with pytest.raises(ValueError, match=r"--sel U_Umf=\S+\)") as info:
        plan_layout(ds, x="h0", y="solid_j")
    hint = re.search(r"--sel U_Umf=(\S+)\)", str(info.value)).group(1)
    layout = plan_layout(ds, x="h0", y="solid_j", sel={"U_Umf": float(hint)})
    assert layout.sel["U_Umf"] in U_UMF


def test_a_value_between_grid_values_is_refused(ds):
    between = float(np.sqrt(H0[3] * H0[4]))
    with pytest.raises(ValueError, match=r"h0 = .* is not a grid value"):
        plan_layout(ds, sel={"h0": between, "U_Umf": 1.2, "solid_j": "ilmenite"})


@pytest.mark.parametrize("spelling", ["Ilmenite", "ILMENITE", " ilmenite "])
def test_a_material_is_selected_by_any_spelling_the_database_accepts(ds, spelling):
    layout = plan_layout(ds, sel={"solid_j": spelling, "U_Umf": 1.2})
    assert layout.sel["solid_j"] == "ilmenite"


def test_a_picture_is_written_at_the_path_given(ds, tmp_path, capsys):
    # a name without a suffix is written as PNG there, as the command says ("wrote pic"),
    # not as pic.png beside it
    sub = ds.sel(solid_j="ilmenite", drop=True).sel(U_Umf=1.2)
    for name in ("pic", "pic.png"):
        at.plots.operating_window(sub, path=tmp_path / name)
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pic", "pic.png"]


@pytest.mark.parametrize("second", ["h0=2e-6", "h0 = 5 um", "h0=5e-6"])
def test_a_dimension_selected_twice_is_refused(path, tmp_path, capsys, second):
    """--sel h0=... twice: the last was drawn, the first dropped without a word (exit 0)."""
    out = tmp_path / "p.png"
    assert main(["plot", str(path), "-o", str(out), "--sel", f"h0={H0[0]}",
                 "--sel", second]) == 2
    err = capsys.readouterr().err
    assert err.startswith("agglomtool: error: --sel h0 is given twice") and not out.exists()


def test_a_name_not_in_the_map_lists_the_names_as_typed(ds):
    # it listed them as numpy reprs: [np.str_('silica-sand'), np.str_('ilmenite')]
    with pytest.raises(ValueError, match=r"solid_j = 'granite' is not in the map; values: "
                                         r"silica-sand, ilmenite$"):
        plan_layout(ds, sel={"solid_j": "granite", "U_Umf": U_UMF[0]})
