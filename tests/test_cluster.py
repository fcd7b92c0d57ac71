"""Sweeps on a dask.distributed cluster: blocks run as tasks on the workers, bitwise equal."""

import warnings

import numpy as np
import pytest
import xarray as xr
from distributed import Client, LocalCluster, get_task_stream

from agglomtool.maps import sweep
from agglomtool.maps.store import open_store
from agglomtool.scene import Scene

SCENE = Scene(liquid="hypothetical-slag", h0=0.15e-6, d_i=1000e-6)
GRID = dict(T=np.linspace(950.0, 1250.0, 3), solid_j=["silica-sand", "ilmenite"],
            h0=[0.15e-6, 0.6e-6], U_Umf=[2.0, 6.0])


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        yield c


def _bitwise(a, b):
    xr.testing.assert_identical(a, b)
    for name in a.data_vars:
        assert a[name].values.tobytes() == b[name].values.tobytes(), name


def _block_tasks(ts):
    return [t for t in ts.data if str(t["key"]).startswith("agglomtool-block-")]


def test_cluster_sweep_through_a_store_equals_the_default_bitwise(client, tmp_path):
    ref = sweep(SCENE, chunks=4, client=False, **GRID)
    with get_task_stream(client) as ts:
        got = sweep(SCENE, chunks=4, store=tmp_path / "s", client=client, **GRID)
    _bitwise(ref, got.compute(scheduler="synchronous"))
    tasks = _block_tasks(ts)
    assert len(tasks) == 6  # one task per block, all on the workers
    assert {t["worker"] for t in tasks} <= set(client.scheduler_info()["workers"])
    _bitwise(ref, open_store(tmp_path / "s").compute(scheduler="synchronous"))


def test_active_client_is_used_without_a_store(client):
    ref = sweep(SCENE, chunks=4, client=False, **GRID)
    with get_task_stream(client) as ts:
        got = sweep(SCENE, chunks=4, **GRID)  # the active client
    assert len(_block_tasks(ts)) == 6
    _bitwise(ref, got)


MELT = Scene(gas="biomass-flue-gas", liquid="k-silicate-ash-melt", T=1123.15,
             solid_i="silica-sand", d_i=300e-6)
# no bridge at 0.05 um, every bridge held at 1 um (the map's deciding regime); U/U_mf 0.8
# is not fluidized (no impact speed there: flagged, and warned)
MELT_GRID = dict(T=[1073.15, 1223.15], h0=[0.05e-6, 1e-6], U_Umf=[0.8, 2.0, 8.0])


def _said(fn):
    """``fn()`` and the messages of its NoImpactSpeedWarnings."""
    from agglomtool.bed.speed_models import NoImpactSpeedWarning

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = fn()
    return ds, [str(w.message) for w in rec if issubclass(w.category, NoImpactSpeedWarning)]


def test_a_store_is_summarised_from_its_blocks_not_read_back_through_the_cluster(client,
                                                                               tmp_path):
    """The flagged points' warning and the deciding regime of a map made into a store come
    from the blocks as they are written (and as a rerun checks them), the same as the
    in-memory map's; nothing of the map is read back through the cluster for them."""
    ref, ref_said = _said(lambda: sweep(MELT, chunks=2, client=False, **MELT_GRID))
    assert len(ref_said) == 1 and ref.attrs["deciding_regime"]
    for run in ("new", "rerun"):  # blocks written now; blocks found finished and checked
        with get_task_stream(client) as ts:
            got, said = _said(lambda: sweep(MELT, chunks=2, store=tmp_path / "s",
                                            client=client, **MELT_GRID))
        assert said == ref_said, run
        assert got.attrs["deciding_regime"] == ref.attrs["deciding_regime"], run
        other = [t["key"] for t in ts.data
                 if not str(t["key"]).startswith(("agglomtool-block-", "agglomtool-shared-"))]
        assert other == [], run
        _bitwise(ref, got.compute(scheduler="synchronous"))


def test_a_store_made_here_says_the_same_as_the_map_in_memory(tmp_path):
    ref, ref_said = _said(lambda: sweep(MELT, chunks=2, client=False, **MELT_GRID))
    for _ in range(2):
        got, said = _said(lambda: sweep(MELT, chunks=2, store=tmp_path / "s", client=False,
                                        **MELT_GRID))
        assert said == ref_said
        assert got.attrs["deciding_regime"] == ref.attrs["deciding_regime"]
