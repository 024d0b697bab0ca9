"""The one place a Dask client is made (``cross_check.cluster``): bad worker counts refused, a
given client passed through untouched, an unreachable scheduler a ValueError naming it."""
import socket

import pytest

from cross_check import cluster


@pytest.mark.parametrize("workers, error", [(0, ValueError), (cluster.MAX_WORKERS + 1, ValueError),
                                            (-3, ValueError), (2.0, TypeError), (True, TypeError),
                                            ("2", TypeError)])
def test_bad_worker_counts(workers, error):
    with pytest.raises(error, match=r"workers must be an int in \[1, 256\]"):
        cluster.check_workers(workers)


def test_good_worker_counts():
    assert [cluster.check_workers(k) for k in (1, 2, cluster.MAX_WORKERS)] == [1, 2, 256]


def test_a_given_client_is_passed_through_and_not_closed():
    class Given:
        closed = False

        def close(self):
            self.closed = True

    given = Given()
    with cluster.client("tcp://127.0.0.1:1", 2, given=given) as got:
        assert got is given
    assert not given.closed


def test_an_unreachable_scheduler_is_a_value_error_naming_it(monkeypatch):
    pytest.importorskip("distributed", reason="the cluster needs the atlas extra (dask.distributed)")
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", "1s")
    with socket.socket() as s:              # a port nobody listens on: bound, never listening
        s.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
        with pytest.raises(cluster.ClusterError, match=f"cannot reach the dask scheduler at '{address}' within 1s"):
            with cluster.client(address, 2):
                pass


def test_verify_on_an_unreachable_scheduler_exits_2_naming_it(monkeypatch, tmp_path, capsys):
    pytest.importorskip("distributed", reason="the cluster needs the atlas extra (dask.distributed)")
    from cross_check.verify import run

    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", "1s")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
        assert run.main(["--scene", "F=1 f=0.3 omega=1 l=0 r=3", "--quick", "--scheduler", address,
                         "--out", str(tmp_path)]) == 2
    assert f"cannot reach the dask scheduler at '{address}'" in capsys.readouterr().err


def test_the_local_workers_run_without_dask_s_sampling_profiler_and_on_slower_clocks(client):
    """``LOCAL_CONFIG``: the workers of a cluster made here take no stack samples (no ``profile``
    periodic callback, the setting off in their own config) and tick Dask's watchdog, memory and
    system monitors every 1 s, 1 s and 10 s, while a worker made with Dask's defaults meanwhile
    samples and ticks at 20 ms, 100 ms and 500 ms (the check can fail, and the settings do not leak
    into the caller's process)."""
    import dask

    def sampling(dask_worker):
        return ("profile" in dask_worker.periodic_callbacks,
                dask.config.get("distributed.worker.profile.enabled"))

    assert set(client.run(sampling).values()) == {(False, False)}
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as plain, \
            Client(plain) as other:
        assert set(other.run(sampling).values()) == {(True, True)}
        assert set(other.run(_clocks).values()) == {("20ms", "100ms", "500ms")}      # Dask's defaults
    assert set(client.run(_clocks).values()) == {("1s", "1s", "10s")}


def _clocks():
    """A worker's intervals of the event loop's watchdog, the memory monitor and the system monitor."""
    import dask

    return tuple(dask.config.get(f"distributed.{key}") for key in (
        "admin.tick.interval", "worker.memory.monitor-interval", "admin.system-monitor.interval"))

