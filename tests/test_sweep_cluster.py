"""``strainwave sweep --scheduler`` against a real cluster and against things that are not one.

The cluster is the dask command-line tools: one ``dask scheduler`` and two ``dask worker`` processes,
each in its own process group (as on separate machines), killed in ``finally`` whatever happens.
Every wait is bounded; the bad-address tests are bounded by the 10 s the CLI promises.
"""
import http.server
import json
import math
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path

import pandas as pd
import pytest

from strainwave import cache
from strainwave.compare.sweep.pipeline import run_sweep
from strainwave.compare.sweep.task import closed_form_probe

BIN = Path(sys.executable).parent
TESTS = Path(__file__).parent
D, L, E, NU = 70.0, 60.0, 2.1e5, 0.3
G = E / (2 * (1 + NU))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _kill(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait(timeout=30)


@contextmanager
def dask_cli_cluster(scratch: Path, n_workers: int = 2):
    """(address, [worker Popen]) of a scheduler and workers started with the ``dask`` CLI."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, "DASK_TEMPORARY_DIRECTORY": str(scratch), "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
           "PYTHONPATH": os.pathsep.join([str(TESTS), os.environ.get("PYTHONPATH", "")])}
    procs = []
    try:
        procs.append(subprocess.Popen([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                       "--no-dashboard"], start_new_session=True, env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        workers = []
        for i in range(n_workers):
            workers.append(subprocess.Popen(
                [str(BIN / "dask"), "worker", address, "--nthreads", "1", "--no-dashboard",
                 "--local-directory", str(scratch / f"worker{i}")], start_new_session=True, env=env,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
            procs.append(workers[-1])
        from distributed import Client
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(n_workers, timeout=60)
        yield address, workers
    finally:
        for proc in reversed(procs):
            _kill(proc)


def journal_probe(study, params, quick, *, journal: str, delay_s: float):
    """closed_form_probe that appends one line per *finished* computation (O_APPEND: whole lines)."""
    result = closed_form_probe(study, params, quick, delay_s=delay_s)
    with open(journal, "a") as fh:
        fh.write(f"{params.output_shaft.inner_diameter_mm} {os.getpid()}\n")
    return result


@pytest.mark.heavy
def test_cli_sweep_on_a_dask_cli_cluster(strainwave_cmd, tmp_path):
    short = tmp_path / "short.toml"
    short.write_text(f"[output_shaft]\nlength_mm = {L}\n")
    out = tmp_path / "sweep"
    with dask_cli_cluster(tmp_path / "scratch") as (address, _):
        run = subprocess.run([*strainwave_cmd, "sweep", "shaft-torsion", "--vary", "output_shaft.inner_diameter_mm=40,50",
                              "--params", str(short), "--quick", "--scheduler", address, "--out", str(out)],
                             capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "2 points, 2 ok, 0 failed, 0 from cache; 2 workers" in run.stdout
    frame = pd.read_parquet(out / "sweep.parquet")
    rows = frame[frame["quantity"] == "flexibility_rad_per_Nmm"].set_index("output_shaft.inner_diameter_mm")
    for d in (40.0, 50.0):   # Saint-Venant hollow shaft, G = E/(2(1+nu)); quick P2 meshes within 1e-3
        assert rows.loc[d, "fea"] == pytest.approx(32 * L / (math.pi * G * (D ** 4 - d ** 4)), rel=1e-3)
    assert not (out / ".dask-scratch").exists()


@pytest.mark.heavy
def test_a_killed_worker_loses_no_point(tmp_path, monkeypatch):
    import functools
    monkeypatch.setattr(cache, "code_version", lambda: "pinned-for-the-lost-worker-test")
    journal, out = tmp_path / "journal.txt", tmp_path / "sweep"
    task = functools.partial(journal_probe, journal=str(journal), delay_s=0.6)
    vary = ["output_shaft.inner_diameter_mm=20:48:8"]
    result = {}
    with dask_cli_cluster(tmp_path / "scratch") as (address, workers):
        runner = threading.Thread(target=lambda: result.update(outcome=run_sweep(
            "shaft-torsion", vary=vary, scheduler=address, out_dir=out, task=task)), daemon=True)
        runner.start()
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and len(list((out / "cache").glob("*.json"))) < 2:
            time.sleep(0.02)
        _kill(workers[1])           # SIGKILL the worker (and its nanny): it is gone for good
        runner.join(timeout=120)
        assert not runner.is_alive(), "the sweep did not finish on the remaining worker"
    outcome = result["outcome"]
    assert (outcome.n_points, outcome.n_ok, outcome.n_failed) == (8, 8, 0)
    lines = journal.read_text().split()
    diameters = [float(x) for x in lines[0::2]]
    assert sorted(set(diameters)) == [20.0 + 4.0 * i for i in range(8)]   # every point computed
    # once each, except the one point the killed worker (one thread) may have finished but not yet cached when it
    # died (the journal is written before the cache): redone once, by the other worker
    redone = {d for d in diameters if diameters.count(d) > 1}
    assert len(diameters) == 8 + len(redone) and len(redone) <= 1
    assert all(len({pid for x, pid in zip(diameters, lines[1::2]) if x == d}) == 2 for d in redone)
    assert len(set(lines[1::2])) == 2                                  # ... by both workers, before and after the kill
    frame = pd.read_parquet(out / "sweep.parquet")
    exact = [32 * 200.0 / (math.pi * 8.0e4 * (D ** 4 - d ** 4)) for d in frame["output_shaft.inner_diameter_mm"]]
    assert frame["fea"].tolist() == pytest.approx(exact, rel=1e-12)
    assert len(list((out / "cache").glob("*.json"))) == 8
    again = run_sweep("shaft-torsion", vary=vary, out_dir=out, task=task)   # no cluster needed: all cached
    assert (again.n_cached, again.workers) == (8, 0) and journal.read_text().split() == lines


@contextmanager
def _server(handler):
    """A listener on 127.0.0.1 serving each connection with ``handler(conn)`` in a thread."""
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    sock.listen(8)
    stop = threading.Event()

    def serve():
        sock.settimeout(0.2)
        while not stop.is_set():
            try:
                conn, _ = sock.accept()
            except (TimeoutError, OSError):
                continue
            with conn:
                handler(conn, stop)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{sock.getsockname()[1]}"
    finally:
        stop.set()
        thread.join(timeout=5)
        sock.close()


def _silent(conn, stop):
    stop.wait(15)


def _garbage(conn, stop):
    conn.sendall(b"\xff" * 64 + b"hello, I am not dask\r\n")
    stop.wait(15)


def _run_cli(strainwave_cmd, address, tmp_path):
    started = time.monotonic()
    run = subprocess.run([*strainwave_cmd, "sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,200",
                          "--scheduler", address, "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=10)   # the promised bound: never a hang
    return run, time.monotonic() - started


@pytest.mark.parametrize("kind", ["silent", "garbage", "http", "nothing"])
def test_an_address_that_is_no_scheduler_fails_in_one_line(strainwave_cmd, tmp_path, kind):
    if kind == "http":
        httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
        threading.Thread(target=httpd.serve_forever, daemon=True).start()
        context = contextmanager(lambda: (yield f"tcp://127.0.0.1:{httpd.server_address[1]}"))()
    elif kind == "nothing":
        context = contextmanager(lambda: (yield f"tcp://127.0.0.1:{_free_port()}"))()
    else:
        context = _server(_silent if kind == "silent" else _garbage)
    try:
        with context as address:
            run, _ = _run_cli(strainwave_cmd, address, tmp_path)
    finally:
        if kind == "http":
            httpd.shutdown()
            httpd.server_close()
    assert run.returncode == 2 and "Traceback" not in run.stderr and run.stdout == ""
    errors = [line for line in run.stderr.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and f"--scheduler = '{address}'" in errors[0], run.stderr
    expected = "no Dask scheduler answered: nothing listening" if kind == "nothing" else "not a Dask scheduler"
    assert expected in errors[0]
    assert not (tmp_path / "out" / ".dask-scratch").exists()
