"""Sweeps on a dask.distributed cluster: blocks run as tasks on the workers, bitwise equal."""

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
