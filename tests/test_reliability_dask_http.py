"""Issue 53, item 7: the local cluster's HTTP servers (dashboard, /metrics, /info: the TLS addresses and scratch
paths, to any local process) do not listen unless --dashboard asks, and then only on 127.0.0.1."""
import socket
import urllib.request

import pytest


def _http_ports(client) -> list[int]:
    info = client.scheduler_info()
    ports = [info["services"]["dashboard"]]
    ports += [w["services"]["dashboard"] for w in info["workers"].values() if "dashboard" in w.get("services", {})]
    return ports


def _listening(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(2)
        return s.connect_ex(("127.0.0.1", port)) == 0


@pytest.mark.heavy   # two clusters; the cheap half (no listener without --dashboard) is in test_reliability_guards
def test_no_http_server_listens_without_dashboard_and_with_it_only_on_loopback(tmp_path):
    from strainwave.compare.sweep.pipeline import dask_client
    with dask_client(None, 1, tmp_path / "scratch") as (client, _):
        ports = _http_ports(client)
        assert len(ports) == 2, ports   # the scheduler's and the worker's
        assert not [p for p in ports if _listening(p)], ports
    with dask_client(None, 1, tmp_path / "scratch2", dashboard=True) as (client, _):
        port = client.scheduler_info()["services"]["dashboard"]
        assert client.dashboard_link.startswith("http://127.0.0.1:")
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/health", timeout=10) as page:
            assert page.read() == b"ok"
        host = socket.gethostbyname(socket.gethostname())
        if not host.startswith("127."):   # a machine with another interface: nothing answers there
            with socket.socket() as s:
                s.settimeout(2)
                assert s.connect_ex((host, port)) != 0
