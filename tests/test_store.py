"""Resumable sweep stores: resume, provenance, damaged blocks, bad paths, one writer at a time."""

import json
import os
import shutil
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from _user_materials import MY_SAND

from agglomtool import materials
from agglomtool.maps import sweep
from agglomtool.maps.store import StoreLockedError, StoreWarning, export_netcdf, open_store
from agglomtool.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
GRID = dict(T=np.linspace(950.0, 1250.0, 3), solid_j=["silica-sand", "ilmenite"],
            h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 6.0])
CHUNKS = 4  # 6 blocks of (1, 1, 2, 2) points


@pytest.fixture(scope="module")
def ref():
    return sweep(SCENE, chunks=None, **GRID)


def _run(store, scene=SCENE, chunks=CHUNKS, **kw):
    grid = {**GRID, **{k: v for k, v in kw.items() if k in GRID}}
    opts = {k: v for k, v in kw.items() if k not in GRID}
    return sweep(scene, chunks=chunks, store=store, **opts, **grid)


def _same(ref, got):
    got = got.compute()
    xr.testing.assert_identical(ref, got)
    for name in ref.data_vars:  # bitwise, NaNs included
        a, b = ref[name].values, got[name].values
        assert a.tobytes() == b.tobytes(), name


def _clean(fn, *args, **kw):
    """``fn(*args, **kw)`` failing on any StoreWarning: nothing was damaged."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", StoreWarning)
        return fn(*args, **kw)


def _chunk_files(store, var):
    return sorted(p for p in (Path(store) / "map.zarr" / var / "c").rglob("*") if p.is_file())


def test_store_equals_in_memory_and_resumes_after_interruption(ref, tmp_path):
    store = tmp_path / "s"
    _same(ref, _clean(_run, store))
    records = sorted((store / "done").glob("*.json"))
    assert len(records) == 6
    for rec in records[::2]:  # an interrupted run: some blocks never recorded,
        rec.unlink()
    _chunk_files(store, "e_w")[0].unlink()  # one never written
    with pytest.raises(ValueError, match="incomplete: 3 of 6 blocks"):
        open_store(store)
    _same(ref, _clean(_run, store))
    out = export_netcdf(store, tmp_path / "m.nc")
    with xr.open_dataset(out) as back:
        assert back.attrs.pop("history")  # the file records when and how it was written
        _same(ref, back)


@pytest.mark.parametrize(("change", "what"), [
    (dict(scene=SCENE.replace(e=0.7)), "scene e: stored null, now 0.7"),
    (dict(T=np.linspace(950.0, 1300.0, 3)), "grid T last: stored 1250.0, now 1300.0"),
    (dict(T=[950.0, 1200.0, 1250.0]), "grid T sha256"),
    (dict(chunks=8), "chunks T: stored 3 chunks [1, 1, 1], now 2 chunks [2, 1]"),
    (dict(nodes=8), "nodes: stored 16, now 8"),
])
def test_a_different_sweep_is_refused_saying_what_differs(ref, tmp_path, change, what):
    store = tmp_path / "s"
    _run(store)
    with pytest.raises(ValueError, match="holds a different sweep") as info:
        _run(store, **change)
    assert what in str(info.value)
    again = _clean(_run, store)  # the store is intact
    _same(ref, again)
    new = _run(store, overwrite=True, **change)  # asked for: a new store
    expect = sweep(change.get("scene", SCENE), chunks=None, nodes=change.get("nodes", 16),
                   **{**GRID, **{k: v for k, v in change.items() if k in GRID}})
    _same(expect, new)


def test_record_deleted_then_grid_changed_is_refused_same_grid_resumes(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    (store / "sweep.json").unlink()
    with pytest.raises(ValueError, match="different sweep .*cannot be listed"):
        _run(store, T=[950.0, 1000.0, 1250.0])
    _same(ref, _clean(_run, store))
    assert (store / "sweep.json").exists()


def test_unreadable_record_is_named_and_rebuilt(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    (store / "sweep.json").write_text("{not json")
    with pytest.warns(StoreWarning, match="sweep.json is unreadable"):
        got = _run(store)
    _same(ref, got)


def test_user_material_edited_between_runs_is_refused(tmp_path, monkeypatch):
    d = tmp_path / "mat"
    d.mkdir()
    (d / "mine.toml").write_text(MY_SAND.format(2650.0))
    monkeypatch.setenv(materials.ENV_VAR, str(d))
    scene = SCENE.replace(solid_i="my-sand")
    store = tmp_path / "s"
    sweep(scene, chunks=CHUNKS, store=store, T=GRID["T"], h0=GRID["h0"])
    (d / "mine.toml").write_text(MY_SAND.format(1500.0))
    with pytest.raises(ValueError, match=r"materials solid my-sand: .*mine.toml has changed"):
        sweep(scene, chunks=CHUNKS, store=store, T=GRID["T"], h0=GRID["h0"])


def _flip(p):
    b = bytearray(p.read_bytes())
    b[len(b) // 2] ^= 0x10
    p.write_bytes(bytes(b))


DAMAGE = {
    "flipped bit": _flip,
    "truncated": lambda p: p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2]),
    "garbage": lambda p: p.write_bytes(os.urandom(64)),
    "empty": lambda p: p.write_bytes(b""),
    "deleted": lambda p: p.unlink(),
}


@pytest.mark.parametrize(("damage", "var"), [(k, "propensity") for k in sorted(DAMAGE)]
                         + [("flipped bit", "u_star"), ("garbage", "mu_g")])
def test_damaged_block_is_recomputed(ref, tmp_path, damage, var):
    store = tmp_path / "s"
    _run(store)
    DAMAGE[damage](_chunk_files(store, var)[1])
    with pytest.warns(StoreWarning, match=r"1 finished block\(s\) are recomputed"):
        got = _run(store)
    _same(ref, got)
    _same(ref, _clean(_run, store))  # repaired for good


def test_damaged_completion_record_is_recomputed(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    rec = sorted((store / "done").glob("*.json"))[2]
    rec.write_text("{")
    with pytest.warns(StoreWarning, match="cannot be read"):
        got = _run(store)
    _same(ref, got)


@pytest.mark.parametrize("with_records", [False, True])
def test_blocks_copied_from_another_sweep_are_recomputed(ref, tmp_path, with_records):
    store, other = tmp_path / "s", tmp_path / "o"
    _run(store)
    _run(other, scene=SCENE.replace(e=0.7))
    for src in _chunk_files(other, "e_w"):
        shutil.copy(src, store / src.relative_to(other))
    if with_records:
        for src in (other / "done").glob("*.json"):
            shutil.copy(src, store / "done" / src.name)
    match = "another sweep" if with_records else "e_w fails its checksum"
    with pytest.warns(StoreWarning, match=match):
        got = _run(store)
    _same(ref, got)


def test_damaged_zarr_metadata_is_rewritten_from_the_plan(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    (store / "map.zarr" / "zarr.json").write_text("garbage")
    with pytest.warns(StoreWarning, match="map.zarr/zarr.json did not match .* rewritten"):
        got = _run(store)
    _same(ref, got)


def test_record_and_zarr_metadata_both_lost_recomputes_everything(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    (store / "map.zarr" / "zarr.json").write_text("garbage")
    (store / "sweep.json").unlink()
    with pytest.warns(StoreWarning, match="every block is recomputed"):
        got = _run(store)
    _same(ref, got)


def test_existing_file_as_store_is_a_value_error(tmp_path):
    f = tmp_path / "taken"
    f.write_text("my notes")
    with pytest.raises(ValueError, match=r"store = '.*taken' is an existing file"):
        _run(f)
    assert f.read_text() == "my notes"


@pytest.mark.parametrize("files", [["notes.txt"], ["manifest.json", "block_0.nc"]])
def test_other_directories_are_refused_and_left_alone(tmp_path, files):
    d = tmp_path / "d"
    d.mkdir()
    for name in files:
        (d / name).write_text("mine")
    for overwrite in (False, True):
        with pytest.raises(ValueError, match="not a sweep store"):
            _run(d, overwrite=overwrite)
    assert sorted(p.name for p in d.iterdir()) == sorted(files)


def _env():
    return {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}


HOLD = """
import sys, time
from pathlib import Path
from agglomtool.maps.store import _writer_lock
with _writer_lock(Path(sys.argv[1])):
    print("locked", flush=True)
    time.sleep(120)
"""


def test_second_writer_is_refused_and_a_killed_writer_leaves_no_lock(ref, tmp_path):
    store = tmp_path / "s"
    store.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", HOLD, str(store)], env=_env(),
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(StoreLockedError, match=f"being written by process {holder.pid}"):
            _run(store)
    finally:
        holder.kill()
        holder.wait()
    _same(ref, _clean(_run, store))


WRITER = """
import sys, time
from pathlib import Path
import numpy as np
from agglomtool.maps import sweep
from agglomtool.maps.store import StoreLockedError
from agglomtool.scene import Scene
go = Path(sys.argv[2])
while not go.exists():
    time.sleep(0.005)
try:
    sweep(Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6), chunks={chunks},
          store=sys.argv[1], T=np.linspace(950.0, 1250.0, 3),
          solid_j=["silica-sand", "ilmenite"], h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 6.0])
except StoreLockedError as exc:
    print(exc, file=sys.stderr)
    sys.exit(3)
"""


def test_writer_processes_started_together_leave_a_complete_correct_store(ref, tmp_path):
    store, go = tmp_path / "s", tmp_path / "go"
    procs = [subprocess.Popen([sys.executable, "-c", WRITER.format(chunks=CHUNKS), str(store),
                               str(go)], env=_env(), stderr=subprocess.PIPE, text=True)
             for _ in range(3)]
    time.sleep(0.5)
    go.touch()
    results = [(p.wait(timeout=600), p.stderr.read()) for p in procs]
    for rc, err in results:
        assert rc == 0 or (rc == 3 and "is being written by process" in err), err
    assert any(rc == 0 for rc, _ in results)
    _same(ref, open_store(store))
    _same(ref, _clean(_run, store))
    assert not list(store.rglob("*.tmp"))


def test_open_store_of_something_else_names_it(tmp_path):
    with pytest.raises(ValueError, match="is not a sweep store"):
        open_store(tmp_path)
    (tmp_path / "sweep.json").write_text(json.dumps({"fingerprint": {"format": ["x", 1]}}))
    with pytest.raises(ValueError, match="layout"):
        open_store(tmp_path)


KILLED = """
import sys
import numpy as np
from agglomtool.maps import sweep
from agglomtool.scene import Scene
sweep(Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6), chunks=2,
      store=sys.argv[1], T=np.linspace(950.0, 1250.0, 3), solid_j=["silica-sand", "ilmenite"],
      h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 6.0])
"""


def test_a_run_killed_midway_is_resumed(ref, tmp_path):
    store = tmp_path / "s"
    proc = subprocess.Popen([sys.executable, "-c", KILLED, str(store)], env=_env())
    try:
        deadline = time.monotonic() + 300
        while proc.poll() is None and time.monotonic() < deadline:
            if len(list((store / "done").glob("*.json"))) >= 3:
                break
            time.sleep(0.01)
    finally:
        proc.kill()
        proc.wait()
    got = sweep(SCENE, chunks=2, store=store, **GRID)  # same sweep: resumes, never refuses
    _same(ref, got)


def test_a_layout_interrupted_before_its_record_is_laid_out_again(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    shutil.rmtree(store / "done")
    (store / "sweep.json").unlink()
    shutil.rmtree(store / "map.zarr" / "propensity")  # arrays not all written yet
    _same(ref, _clean(_run, store))


def test_outputs_that_do_not_vary_over_the_grid_are_stored(tmp_path):
    """A grid over U_Umf only: gas, liquid and u0* outputs are 0-d variables."""
    ref = sweep(SCENE, chunks=None, U_Umf=[2.0, 4.0, 8.0])
    assert ref.mu_g.ndim == 0
    _same(ref, _clean(sweep, SCENE, chunks=1, store=tmp_path / "s", U_Umf=[2.0, 4.0, 8.0]))
    _same(ref, _clean(sweep, SCENE, chunks=1, store=tmp_path / "s", U_Umf=[2.0, 4.0, 8.0]))
