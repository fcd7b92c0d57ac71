"""Faults of stores, runs and clusters: every byte of a store checked and mended,
lifecycles with one owner, inputs read once per run, cluster failures said.

Random choices (which files, which bytes) come from seeded generators: a failure is
reproduced by its test id.
"""

import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from _user_materials import MY_SAND

import agglomtool as at
from agglomtool.maps import sweep
from agglomtool.maps.store import StoreWarning, open_store
from agglomtool.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
GRID = dict(T=np.linspace(950.0, 1250.0, 3), h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 4.0, 6.0],
            d_i=[500e-6, 1000e-6])
CHUNKS = 6


@pytest.fixture(scope="module")
def ref():
    return sweep(SCENE, chunks=None, **GRID)


def _run(store, scene=SCENE, **grid):
    return sweep(scene, chunks=CHUNKS, store=store, **{**GRID, **grid})


def _same(ref, got):
    got = got.compute()
    xr.testing.assert_identical(ref, got)
    for name in ref.variables:  # bitwise, NaNs and coordinates included
        assert ref[name].values.tobytes() == got[name].values.tobytes(), name


def _clean(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", StoreWarning)
        return fn(*args, **kw)


def _flip_at(p: Path, offset: int, mask: int = 0x01) -> None:
    b = bytearray(p.read_bytes())
    b[offset] ^= mask
    p.write_bytes(bytes(b))


def _flip_in(text: str):
    """Flip one bit of the first byte of ``text`` in a file."""
    def damage(p: Path):
        _flip_at(p, p.read_bytes().index(text.encode()), 0x02)
    return damage


def _replace(old: str, new: str):
    def damage(p: Path):
        raw = p.read_bytes()
        assert old.encode() in raw
        p.write_bytes(raw.replace(old.encode(), new.encode(), 1))
    return damage


def _copy_from_other(rel: str):
    def damage(p: Path, other: Path):
        shutil.copyfile(other / "map.zarr" / rel, p)
    return damage


# (file under map.zarr, damage): the layout files (metadata, attributes, coordinates)
LAYOUT_DAMAGE = {
    "deleted coordinate chunk": ("h0/c/0", lambda p: p.unlink()),
    "flipped bit in a coordinate chunk": ("U_Umf/c/0", lambda p: _flip_at(p, len(
        p.read_bytes()) // 2)),
    "deleted coordinate metadata": ("d_i/zarr.json", lambda p: p.unlink()),
    "h0 flipped to j0 in e_w/zarr.json": ("e_w/zarr.json", _replace('"h0"', '"j0"')),
    "bit flip in the scene attribute": ("zarr.json", _flip_in('\\"e\\": null')),
    "bit flip in the provenance attribute": ("zarr.json", _flip_in("confidence")),
    "truncated group metadata": ("zarr.json", lambda p: p.write_bytes(
        p.read_bytes()[:638])),
    "truncated array metadata": ("T/zarr.json", lambda p: p.write_bytes(
        p.read_bytes()[:40])),
    "not UTF-8 metadata": ("mu_g/zarr.json", lambda p: p.write_bytes(
        b"\xff\xfe" + p.read_bytes()[2:])),
    "empty coordinate chunk": ("T/c/0", lambda p: p.write_bytes(b"")),
}


@pytest.mark.parametrize("case", sorted(LAYOUT_DAMAGE))
def test_damaged_layout_file_is_named_refused_on_open_and_mended_by_a_rerun(ref, tmp_path,
                                                                           case):
    store = tmp_path / "s"
    _clean(_run, store)
    rel, damage = LAYOUT_DAMAGE[case]
    damage(store / "map.zarr" / rel)
    with pytest.raises(ValueError, match=f"map.zarr/{rel}.*run the same sweep again"):
        open_store(store)
    with pytest.warns(StoreWarning, match=f"map.zarr/{rel}.*rewritten from the sweep's plan"):
        got = _run(store)
    _same(ref, got)
    _same(ref, _clean(_run, store))  # mended for good
    _same(ref, open_store(store))


def test_coordinate_chunk_copied_from_another_sweep_is_mended(ref, tmp_path):
    store, other = tmp_path / "s", tmp_path / "o"
    _run(store)
    _run(other, T=np.linspace(1000.0, 1300.0, 3))
    shutil.copyfile(other / "map.zarr" / "T" / "c" / "0", store / "map.zarr" / "T" / "c" / "0")
    with pytest.raises(ValueError, match="map.zarr/T/c/0 does not match"):
        open_store(store)
    with pytest.warns(StoreWarning, match="map.zarr/T/c/0"):
        _same(ref, _run(store))


def test_an_extra_array_in_the_layout_is_removed(ref, tmp_path):
    store = tmp_path / "s"
    _run(store)
    shutil.copytree(store / "map.zarr" / "e_w", store / "map.zarr" / "e_w2")
    with pytest.warns(StoreWarning, match="map.zarr/e_w2/zarr.json"):
        _same(ref, _run(store))
    assert not (store / "map.zarr" / "e_w2").exists()


@pytest.mark.parametrize("seed", range(4))
def test_bit_flips_in_the_record_are_found_and_rebuilt(ref, tmp_path, seed):
    store = tmp_path / "s"
    _run(store)
    rec = store / "sweep.json"
    rng = np.random.default_rng(seed)
    _flip_at(rec, int(rng.integers(len(rec.read_bytes()))), 1 << int(rng.integers(8)))
    with pytest.raises(ValueError, match="sweep.json"):
        open_store(store)
    with pytest.warns(StoreWarning):
        _same(ref, _run(store))
    _same(ref, _clean(_run, store))


def test_a_store_deleted_after_it_was_opened_is_an_error_naming_it(ref, tmp_path):
    store = tmp_path / "st"
    ds = _run(store)
    shutil.rmtree(store)
    with pytest.raises(ValueError, match=f"store {store}: .* changed or deleted after it "
                       "was opened"):
        at.write_map(ds, tmp_path / "b.nc")
    assert not (tmp_path / "b.nc").exists()


def test_a_chunk_replaced_after_the_store_was_opened_is_an_error(ref, tmp_path):
    store, other = tmp_path / "s", tmp_path / "o"
    ds = _run(store)
    _run(other, scene=SCENE.replace(e=0.7))
    for src in sorted((other / "map.zarr" / "e_w" / "c").rglob("*")):
        if src.is_file():
            shutil.copyfile(src, store / src.relative_to(other))
    with pytest.raises(ValueError, match="e_w of block .* no longer matches"):
        ds["e_w"].values  # noqa: B018 - reading is the test


def _env():
    return {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "agglomtool", *map(str, args)], cwd=cwd,
                          env=_env(), capture_output=True, text=True, timeout=600)


CONFIG = """
[scene]
liquid = "hypothetical-slag"
h0 = 0.15e-6
d_i = 1000e-6

[grid]
T = [950.0, 1100.0, 1250.0]
h0 = [0.15e-6, 0.6e-6]
U_Umf = [2.0, 4.0, 6.0]
d_i = [500e-6, 1000e-6]

[options]
chunks = 6
"""


@pytest.fixture(scope="module")
def kept(tmp_path_factory):
    """A CLI run that kept its store: (directory, config, reference map bytes)."""
    d = tmp_path_factory.mktemp("cli")
    (d / "map.toml").write_text(CONFIG)
    res = _cli("map", "map.toml", "-o", "ref.nc", "--store", "st", "--keep-parts", "-q",
               cwd=d)
    assert res.returncode == 0, res.stderr
    return d


def _map_values(path):
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    ds.attrs.pop("history")
    return ds


@pytest.mark.parametrize("seed", range(6))
def test_any_files_deleted_from_a_store_are_mended_by_the_same_command(kept, tmp_path, seed):
    """A kill during the final cleanup (or any deletion) leaves files missing in any order:
    the same command mends the store and writes the same map, with no traceback."""
    shutil.copytree(kept / "st", tmp_path / "st")
    shutil.copy(kept / "map.toml", tmp_path / "map.toml")
    files = sorted(p for p in (tmp_path / "st").rglob("*") if p.is_file())
    rng = np.random.default_rng(seed)
    for i in rng.choice(len(files), size=int(rng.integers(1, len(files))), replace=False):
        files[i].unlink()
    res = _cli("map", "map.toml", "-o", "m.nc", "--store", "st", "-q", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    xr.testing.assert_identical(_map_values(kept / "ref.nc"), _map_values(tmp_path / "m.nc"))
    assert not (tmp_path / "st").exists()  # removed (no --keep-parts)


@pytest.mark.parametrize("case", ["truncated group metadata", "not UTF-8 metadata",
                                  "h0 flipped to j0 in e_w/zarr.json"])
def test_cli_mends_damaged_metadata_naming_the_file(kept, tmp_path, case):
    shutil.copytree(kept / "st", tmp_path / "st")
    shutil.copy(kept / "map.toml", tmp_path / "map.toml")
    rel, damage = LAYOUT_DAMAGE[case]
    damage(tmp_path / "st" / "map.zarr" / rel)
    res = _cli("map", "map.toml", "-o", "m.nc", "--store", "st", "--keep-parts", "-q",
               cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    assert f"map.zarr/{rel}" in res.stderr and "rewritten" in res.stderr
    xr.testing.assert_identical(_map_values(kept / "ref.nc"), _map_values(tmp_path / "m.nc"))


def test_record_is_json_with_a_manifest_of_the_layout(tmp_path):
    store = tmp_path / "s"
    _run(store)
    rec = json.loads((store / "sweep.json").read_text())
    assert "zarr.json" in rec["layout"] and "h0/c/0" in rec["layout"]
    assert not any(k.startswith("e_w/c") for k in rec["layout"])  # blocks: their records


# ---------------------------------------------------------------------------------------
# Lifecycles with one owner

PROBE = """
import sys
from pathlib import Path
from agglomtool.maps.store import StoreLockedError, _writer_lock
try:
    with _writer_lock(Path(sys.argv[1])):
        print("free")
except StoreLockedError:
    print("locked")
"""


def _probe(store) -> str:
    res = subprocess.run([sys.executable, "-c", PROBE, str(store)], env=_env(),
                         capture_output=True, text=True, timeout=300)
    return res.stdout.strip() or res.stderr


def test_cli_holds_the_store_lock_through_export_and_removal(tmp_path, monkeypatch):
    """A second run could reuse the blocks of a store that the first run is exporting or
    deleting: the first holds the lock until its store is gone."""
    from agglomtool import cli
    from agglomtool.maps import export
    from agglomtool.maps import store as store_mod

    (tmp_path / "map.toml").write_text(CONFIG)
    monkeypatch.chdir(tmp_path)
    seen = {}
    write_map, remove_store = export.write_map, store_mod.remove_store

    def exporting(ds, path, **kw):
        seen["export"] = _probe(tmp_path / "st")
        return write_map(ds, path, **kw)

    def removing(path):
        seen["remove"] = _probe(tmp_path / "st")
        return remove_store(path)

    monkeypatch.setattr(export, "write_map", exporting)
    monkeypatch.setattr(store_mod, "remove_store", removing)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", at.PlausibilityWarning)
        assert cli.main(["map", "map.toml", "-o", "m.nc", "--store", "st", "-q"]) == 0
    assert seen == {"export": "locked", "remove": "locked"}
    assert not (tmp_path / "st").exists()


def test_two_writers_of_the_same_file_do_not_share_a_temporary(ref, tmp_path, monkeypatch):
    """A second write of the same output starting while the first is writing: both end,
    and the file is a whole map (each writes its own temporary)."""
    out = tmp_path / "m.nc"
    to_netcdf = xr.Dataset.to_netcdf
    calls = []

    def nested(self, path, *args, **kw):
        calls.append(Path(path).name)
        result = to_netcdf(self, path, *args, **kw)
        if len(calls) == 1:  # the other writer starts and ends while this one writes
            at.write_map(ref, out)
        return result

    monkeypatch.setattr(xr.Dataset, "to_netcdf", nested)
    at.write_map(ref, out)
    assert len(set(calls)) == 2
    with xr.open_dataset(out) as back:
        back.attrs.pop("history")
        _same(ref, back)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc"]


def test_temporaries_of_killed_writers_are_removed(ref, tmp_path):
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True)
    dead = int(proc.stdout)  # a process that has ended
    import socket

    host = socket.gethostname().replace(".", "_")
    stale = tmp_path / f".m.nc.{host}.{dead}.0123abcd.tmp"
    stale.write_bytes(b"half a map")
    live = tmp_path / f".m.nc.{host}.{os.getpid()}.0123abcd.tmp"  # a writer still running
    live.write_bytes(b"being written")
    at.write_map(ref, tmp_path / "m.nc")
    assert not stale.exists() and live.exists()


@pytest.mark.parametrize("seed", range(3))
def test_cli_killed_at_a_random_moment_is_mended_by_the_same_command(kept, tmp_path, seed):
    """SIGKILL during the sweep, the export or the cleanup: the same command then writes
    the same map."""
    import time

    shutil.copy(kept / "map.toml", tmp_path / "map.toml")
    rng = np.random.default_rng(seed)
    args = [sys.executable, "-m", "agglomtool", "map", "map.toml", "-o", "m.nc", "-q"]
    start = time.monotonic()
    first = subprocess.Popen(args, cwd=tmp_path, env=_env(), stderr=subprocess.PIPE)
    first.wait(timeout=600)
    took = time.monotonic() - start
    (tmp_path / "m.nc").unlink()
    proc = subprocess.Popen(args, cwd=tmp_path, env=_env(), stderr=subprocess.DEVNULL)
    time.sleep(float(rng.uniform(0.3, 1.0)) * took)
    proc.kill()
    proc.wait()
    res = _cli("map", "map.toml", "-o", "m.nc", "-q", cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    xr.testing.assert_identical(_map_values(kept / "ref.nc"), _map_values(tmp_path / "m.nc"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc", "map.toml"]


def test_cli_runs_started_together_on_one_store_and_output_never_write_a_wrong_map(
        kept, tmp_path):
    """Three runs of the same command at once (same store, same -o): each writes a whole,
    right map or is refused in one line, and none leaves a store behind."""
    shutil.copy(kept / "map.toml", tmp_path / "map.toml")
    args = [sys.executable, "-m", "agglomtool", "map", "map.toml", "-o", "m.nc", "-q"]
    procs = [subprocess.Popen(args, cwd=tmp_path, env=_env(), stderr=subprocess.PIPE,
                              text=True) for _ in range(3)]
    results = [(p.wait(timeout=600), p.stderr.read()) for p in procs]
    for rc, err in results:
        assert "Traceback" not in err
        assert rc == 0 or (rc == 2 and "is being written by" in err), err
    assert any(rc == 0 for rc, _ in results)
    xr.testing.assert_identical(_map_values(kept / "ref.nc"), _map_values(tmp_path / "m.nc"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc", "map.toml"]


# ---------------------------------------------------------------------------------------
# Inputs read once per run

SAND = MY_SAND
MY_GRID = dict(T=[950.0, 1250.0], h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 4.0, 6.0])


@pytest.fixture()
def my_sand(tmp_path, monkeypatch):
    from agglomtool import materials

    d = tmp_path / "mat"
    d.mkdir()
    (d / "mine.toml").write_text(SAND.format("2650.0"))
    monkeypatch.setenv(materials.ENV_VAR, str(d))
    return d / "mine.toml"


def _my_scene():
    return SCENE.replace(solid_i="my-sand", d_i=400e-6)


def _fresh_sweep(**kw):
    """The sweep as a new process computes it: nothing cached."""
    from agglomtool import materials

    materials._LAST.clear()
    materials._BY_CONTENT.clear()
    return sweep(_my_scene(), chunks=6, **MY_GRID, **kw)


def test_an_edit_keeping_size_and_mtime_is_seen_by_the_next_run(my_sand, tmp_path):
    from agglomtool import materials

    before = sweep(_my_scene(), chunks=6, store=tmp_path / "a", **MY_GRID)
    st = my_sand.stat()
    my_sand.write_text(SAND.format("1500.0"))  # as cp -p, rsync -a or tar x leave it
    os.utime(my_sand, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert my_sand.stat().st_size == st.st_size
    assert my_sand.stat().st_mtime_ns == st.st_mtime_ns
    assert materials.solid("my-sand").density == 1500.0  # a look-up outside a run
    after = sweep(_my_scene(), chunks=6, store=tmp_path / "b", **MY_GRID).compute()
    assert not np.array_equal(before["St"].values, after["St"].values)
    _same(_fresh_sweep(), after)
    fp = json.loads((tmp_path / "b" / "sweep.json").read_text())["fingerprint"]
    import hashlib

    assert hashlib.sha256(my_sand.read_bytes()).hexdigest() in fp["materials"]["solid my-sand"]


def test_a_file_edited_during_a_run_then_reverted_leaves_no_block_of_the_edit(
        my_sand, tmp_path, monkeypatch):
    from agglomtool import materials
    from agglomtool.maps import plan as plan_mod

    ref = _fresh_sweep()
    original = my_sand.read_text()
    evaluate = plan_mod.SweepPlan.evaluate
    calls = []

    def editing(self, sl, wanted):
        calls.append(1)
        if len(calls) == 2:  # the file is edited between the first and second blocks
            my_sand.write_text(SAND.format("900.0"))
        return evaluate(self, sl, wanted)

    monkeypatch.setattr(plan_mod.SweepPlan, "evaluate", editing)
    with pytest.warns(materials.MaterialsChangedWarning, match="mine.toml changed while"):
        first = sweep(_my_scene(), chunks=3, store=tmp_path / "s", **MY_GRID)
    assert len(calls) > 2
    _same(ref, first)  # every block from the files as read at the start
    monkeypatch.setattr(plan_mod.SweepPlan, "evaluate", evaluate)
    my_sand.write_text(original)  # reverted: the blocks are reused, and right
    _same(ref, _clean(sweep, _my_scene(), chunks=3, store=tmp_path / "s", **MY_GRID))


def test_look_ups_in_a_run_touch_no_file(my_sand):
    from agglomtool import materials

    touched = []
    originals = Path.stat, Path.read_bytes, os.stat

    def spy(original):
        def wrapper(*args, **kw):
            touched.append(args[0])
            return original(*args, **kw)
        return wrapper

    with materials.pinned():
        Path.stat, Path.read_bytes, os.stat = map(spy, originals)
        try:
            for _ in range(3):
                density = materials.solid("my-sand").density
                model = materials.liquid_entry("hypothetical-slag").model
                known = materials.names("solid")
                fp = materials.fingerprint({"solid": ["my-sand"]})
        finally:
            Path.stat, Path.read_bytes, os.stat = originals
    assert touched == []
    assert density == 2650.0 and model == "fixed" and "my-sand" in known
    assert "mine.toml" in fp["solid my-sand"]


def test_a_snapshot_travels_with_its_bytes(my_sand):
    """What a cluster's worker gets: the files' content, not their paths."""
    import pickle

    from agglomtool import materials

    snap = materials.snapshot()
    blob = pickle.dumps(snap)
    my_sand.write_text(SAND.format("1000.0"))
    back = pickle.loads(blob)
    with materials.pinned(back):
        assert materials.solid("my-sand").density == 2650.0
    assert back.changed() == [str(my_sand.resolve())]


# ---------------------------------------------------------------------------------------
# Clusters


def _in_thread(fn, seconds):
    import threading

    box = {}

    def target():
        try:
            box["value"] = fn()
        except BaseException as exc:  # noqa: BLE001 - handed to the test
            box["error"] = exc

    t = threading.Thread(target=target, daemon=True)
    t.start()
    t.join(seconds)
    assert not t.is_alive(), f"still running after {seconds} s"
    return box


def test_a_cluster_with_no_live_worker_fails_after_the_stated_time(tmp_path, monkeypatch):
    from distributed import Client, LocalCluster

    from agglomtool.maps import cluster

    monkeypatch.setenv(cluster.TIMEOUT_VAR, "2")
    with LocalCluster(n_workers=0, processes=True, dashboard_address=None) as lc, \
            Client(lc) as client:
        box = _in_thread(lambda: sweep(SCENE, chunks=CHUNKS, store=tmp_path / "s",
                                       client=client, **GRID), 120)
    assert isinstance(box.get("error"), cluster.NoWorkersError), box
    assert "no live worker for 2 s" in str(box["error"])


def test_an_error_on_a_worker_surfaces_as_itself(tmp_path):
    """Many blocks in flight when one fails: the others are cancelled, and the error is
    the worker's own (cancelling once changed the set being iterated over, raising
    ``RuntimeError: dictionary changed size during iteration`` instead)."""
    from distributed import Client, LocalCluster

    from agglomtool.maps.cluster import run_blocks

    def fails(i):
        import time

        if i == 3:
            raise ValueError(f"field x = {i} is outside the allowed range (file mine.toml)")
        time.sleep(0.05)
        return i

    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                      dashboard_address=None) as lc, Client(lc) as client:
        for _ in range(3):
            with pytest.raises(ValueError, match="field x = 3 .*mine.toml"):
                run_blocks(client, [((i,), {}) for i in range(400)], lambda idx, sl: idx,
                           fails, lambda idx, r: None, in_flight=300)


def test_cli_with_a_scheduler_without_workers_says_so_in_one_line(tmp_path):
    from distributed import LocalCluster

    (tmp_path / "map.toml").write_text(CONFIG)
    with LocalCluster(n_workers=0, processes=True, dashboard_address=None) as lc:
        env = {**_env(), "AGGLOMTOOL_WORKER_TIMEOUT": "2"}
        res = subprocess.run([sys.executable, "-m", "agglomtool", "map", "map.toml", "-o",
                              "m.nc", "--scheduler", lc.scheduler_address, "-q"],
                             cwd=tmp_path, env=env, capture_output=True, text=True,
                             timeout=300)
    assert res.returncode != 0
    assert "Traceback" not in res.stderr
    lines = [ln for ln in res.stderr.splitlines() if "error" in ln]
    assert len(lines) == 1 and "no live worker for 2 s" in lines[0], res.stderr


def test_a_file_edited_during_a_bed_sweep_is_said_and_not_used(my_sand, monkeypatch):
    """A bed sweep computes from the files as read at its start, like a map, and says so
    (MaterialsChangedWarning) when one changed while it ran, as a map does."""
    from agglomtool import materials
    from agglomtool.bed import Component, bed_sweep
    from agglomtool.bed import propensity as bed_mod

    comps = [Component("my-sand", 1.0, d50=400e-6, gsd=1.2, classes=3)]
    grid = dict(T=[950.0, 1250.0], U_Umf=[2.0, 4.0])
    materials._LAST.clear()
    ref = bed_sweep(SCENE, comps, **grid)
    evaluate = bed_mod._evaluate

    def editing(*args, **kwargs):
        my_sand.write_text(SAND.format("900.0"))  # edited once the run has started
        return evaluate(*args, **kwargs)

    monkeypatch.setattr(bed_mod, "_evaluate", editing)
    with pytest.warns(materials.MaterialsChangedWarning, match="mine.toml changed while the "
                      "bed sweep"):
        during = bed_sweep(SCENE, comps, **grid)
    xr.testing.assert_identical(ref, during)  # every value from the files at the start


def test_a_bed_sweep_with_unchanged_files_says_nothing(my_sand):
    from agglomtool import materials
    from agglomtool.bed import Component, bed_sweep

    comps = [Component("my-sand", 1.0, d50=400e-6, gsd=1.2, classes=3)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", materials.MaterialsChangedWarning)
        bed_sweep(SCENE, comps, T=[950.0], U_Umf=[2.0, 4.0])
