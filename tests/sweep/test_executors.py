"""Byte-identical tables on 1 worker, 2 local processes and a 2-worker Dask LocalCluster."""

import importlib.util

import pytest

from mtcal.sweep.engine import run_sweep
from mtcal.sweep.executors import DaskExecutor, LocalExecutor, SerialExecutor, make_executor
from mtcal.sweep.spec import parse_spec

from .conftest import windtunnel_spec_text

SPEC = windtunnel_spec_text(name="identical", seed=5, trials=6, block=2, filters='["qncf", "mahony", "vqf"]',
                            vibration="[0.0, 3.0]")

HAS_DASK = importlib.util.find_spec("distributed") is not None


def _table_bytes(tmp_path, name, **kw):
    out = tmp_path / name
    run_sweep(parse_spec(SPEC), out, progress=False, **kw)
    return (out / "table.csv").read_bytes()


@pytest.mark.skipif(not HAS_DASK, reason="optional dask.distributed missing")
def test_one_worker_two_processes_and_dask_give_byte_identical_tables(tmp_path):
    from distributed import Client, LocalCluster

    serial = _table_bytes(tmp_path, "serial", workers=1)
    local = _table_bytes(tmp_path, "local", workers=2)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        dask = _table_bytes(tmp_path, "dask", scheduler=client)
        # an address works too (a client is opened and closed by the executor)
        ex = DaskExecutor(cluster.scheduler_address)
        assert ex.workers == 2 and "dask.distributed" in ex.description
        ex.close()
    assert serial == local == dask
    assert serial.count(b"\n") == 1 + 4 * 9


def test_executor_choice_and_errors():
    assert isinstance(make_executor(workers=1), SerialExecutor)
    ex = make_executor(workers=2)
    assert isinstance(ex, LocalExecutor) and ex.workers == 2
    assert sorted(ex.run([(k, pow, (k, 2)) for k in range(5)])) == [(k, k * k) for k in range(5)]
    ex.close()
    with pytest.raises(ValueError, match="workers must be a positive integer"):
        make_executor(workers=-2)
    with pytest.raises(ValueError, match="either workers"):
        make_executor(workers=2, scheduler="tcp://127.0.0.1:1")


@pytest.mark.skipif(not HAS_DASK, reason="optional dask.distributed missing")
def test_dask_errors():
    with pytest.raises(ValueError, match="scheduler must be an address like tcp://"):
        DaskExecutor("localhost:8786")
    with pytest.raises(TypeError, match="client must be a distributed.Client"):
        DaskExecutor(42)
