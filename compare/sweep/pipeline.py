"""``strainwave sweep``: a parameter sweep of one study on dask.distributed.

Each point is one independent task (``compare/sweep_task.run_point``) submitted with ``client.map`` under
a key derived from its cache hash. By default the client drives an embedded ``LocalCluster`` of worker
*processes* (one thread each, ``OMP_NUM_THREADS=1``) sized to the machine; ``scheduler="tcp://host:8786"``
sends the very same tasks to an existing cluster (whose workers must see the same strainwave sources
and the output directory). Cached points are read on the driver and never resubmitted, so an
interrupted sweep resumes where it stopped and a repeated one costs nothing.
"""
from __future__ import annotations

import atexit
import gc
import logging
import math
import os
import shutil
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator

from strainwave.errors import InputError, RangeWarning, StageError
from strainwave.fea.budget import check_budget
from strainwave.drive_guard import check_drive
from strainwave.params import default_dict, load_params, params_from_dict
from strainwave.cache import ResultCache
from strainwave.registry import study as registered
from strainwave.compare.sweep.grid import build_points
from strainwave.compare.sweep.reach import CONNECT_TIMEOUT_S, check_scheduler
from strainwave.compare.sweep.task import (PointSpec, TaskFn, point_key, point_record_ok, run_point, task_name,
                                          warm_modules)

POLL_S = 0.1          # how often the driver looks for finished points
HEARTBEAT_S = 30.0    # longest silence on the terminal while points are running
WORKER_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
# outputs (pandas, matplotlib) loads while the workers start (docs/decisions/013-sweep-worker-start-up.md).


@dataclass(frozen=True)
class Outcome:
    """What a sweep did and where it wrote it."""

    study: str
    out_dir: Path
    n_points: int
    n_ok: int
    n_failed: int
    n_cached: int          # read back from the cache instead of solved
    workers: int
    wall_s: float
    files: tuple[Path, ...]
    departures: tuple[str, ...]

    def summary(self) -> str:
        lines = [f"sweep {self.study}: {self.n_points} points, {self.n_ok} ok, {self.n_failed} failed, "
                 f"{self.n_cached} from cache; {self.workers} workers, {self.wall_s:.1f} s",
                 *(f"  {line}" for line in self.departures),
                 f"  wrote {self.out_dir}/ (sweep.parquet, sweep.csv, summary.md, points.json, "
                 f"{sum(p.suffix == '.png' for p in self.files)} plots)"]
        return "\n".join(lines)


MAX_NAMED = 5   # impossible points named in the one-line refusal; the rest are counted


def refuse_impossible(specs: list[PointSpec], where: str) -> list[int]:
    """Validate every point's parameters on the driver, before any worker starts: an impossible point
    (a bore wider than the shaft, a crack through the wall) is a mistake in the grid, not a result,
    so the whole grid is refused in one line (exit 2) naming the points and why. Returns each point's
    element estimate (``fea/budget.py``), which ranks the points by cost."""
    bad, elements = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)   # possible-but-unusual points warn in their worker
        for index, spec in enumerate(specs):
            try:
                point = params_from_dict(spec.merged())
                check_drive(point)   # the parts inside each other at this point (strainwave/drive_guard.py)
                elements.append(check_budget(spec.study, point, None, spec.quick, flag="mesh").elements)
            except InputError as exc:
                values = ", ".join(f"{k}={v}" for k, v in spec.values)
                bad.append(f"point {index} ({values}): {exc}")
    if bad:
        more = f"; and {len(bad) - MAX_NAMED} more" if len(bad) > MAX_NAMED else ""
        raise InputError(where, f"{len(bad)} of {len(specs)} points",
                         "impossible, nothing was run: " + "; ".join(bad[:MAX_NAMED]) + more)
    return elements


@contextmanager
def dask_client(scheduler: str | None, workers: int | None, scratch: Path | None = None,
                warm: tuple[str, ...] = (), forked: bool = False, dashboard: bool = False
                ) -> Iterator[tuple[object, int]]:
    """A connected ``distributed.Client`` and its worker count; whatever it started is closed on exit.

    ``scheduler``: checked first (``reach.check_scheduler``: bounded connect and handshake), then
    connected with connect timeouts of ``CONNECT_TIMEOUT_S`` set in a config context, so an unreachable
    address or something that is not a Dask scheduler fails in one line within 10 s. Without it, a
    LocalCluster whose workers keep their scratch space under ``scratch`` (not /tmp/dask-scratch-space) and
    import the modules ``warm`` as they start (``worker.SweepWorker``); a cluster reached by address is
    someone else's and is left as it is. ``forked``: the workers are forked from this process's fork server
    (``prefork.start``, which the caller started with their libraries) instead of spawned. ``dashboard``: the
    local scheduler's HTTP server (dashboard, /metrics, /info) on 127.0.0.1 only; without it every HTTP server of
    the local cluster serves no route and stops listening once the cluster is up (``_http_off``).
    """
    import dask
    from distributed import Client

    if scheduler:
        check_scheduler(scheduler)
        timeout = f"{CONNECT_TIMEOUT_S:g}s"
        with dask.config.set({"distributed.comm.timeouts.connect": timeout}):
            try:
                client = Client(scheduler, timeout=timeout)
            except Exception as exc:   # noqa: BLE001 - a peer that spoke the handshake then junk, TLS refused, ...
                raise InputError("--scheduler", scheduler, f"no Dask scheduler answered ({type(exc).__name__}: "
                                                           f"{exc})") from None
            try:
                yield client, max(1, len(client.scheduler_info().get("workers", {})))
            finally:
                client.close()
        return
    n = workers or os.cpu_count() or 1
    config = {"temporary-directory": str(scratch)} if scratch else {}   # the scheduler's space too
    if forked:
        config["distributed.worker.multiprocessing-method"] = "forkserver"
    if not dashboard:   # Dask starts its HTTP servers whatever dashboard_address says: no route on them
        config.update({"distributed.scheduler.http.routes": [], "distributed.worker.http.routes": []})
    with dask.config.set(config):
        yield from _local(n, scratch, warm, dashboard)


def local_security():
    """TLS with a key and certificate made for this sweep alone (``Security.temporary``), required both ways:
    the local scheduler listens on 127.0.0.1, and without it any local user could submit code to the
    workers (``Client("tcp://127.0.0.1:PORT").submit(f)`` ran ``f`` as the sweeping user)."""
    from distributed.security import Security
    try:
        return Security.temporary()
    except ImportError as exc:   # the 'cryptography' package makes the credentials
        raise StageError("start LocalCluster", "sweep", f"no TLS credentials for the local cluster ({exc})") from exc


# Each local worker is a process with its own sockets, pipes and ~300 MB; beyond a few per core they only
# compete (10,000 ran out of file handles with 2,178 tracebacks).
MAX_WORKERS_PER_CPU = 4


def check_workers(workers: int | None) -> None:
    """Refuse (InputError) a local worker count below 1 or above MAX_WORKERS_PER_CPU per core."""
    cap = MAX_WORKERS_PER_CPU * (os.cpu_count() or 1)
    if workers is not None and not 1 <= workers <= cap:
        raise InputError("--workers", workers, f"must be an integer from 1 to {cap} ({MAX_WORKERS_PER_CPU} per core)")


def _http_off(client) -> None:
    """Stop the scheduler's and each worker's HTTP listener (Dask has no switch for them: a dashboard_address of
    None still serves /metrics, /info and the scratch paths on 8787 and one port per worker to any local user)."""
    def stop(dask_scheduler=None, dask_worker=None):
        (dask_scheduler or dask_worker).http_server.stop()

    client.run_on_scheduler(stop)
    client.run(stop)


def _local(n: int, scratch: Path | None, warm: tuple[str, ...], dashboard: bool = False
           ) -> Iterator[tuple[object, int]]:
    from distributed import Client, LocalCluster

    from strainwave.interrupt import children_ignore_sigint
    from strainwave.compare.sweep.worker import SweepWorker

    security = local_security()
    try:
        with children_ignore_sigint():   # Ctrl-C stops the sweep here; the workers are closed by it
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                   dashboard_address="127.0.0.1:0" if dashboard else None,
                                   silence_logs=logging.ERROR, env=WORKER_ENV, security=security,
                                   protocol="tls://", local_directory=str(scratch) if scratch else None,
                                   plugins=[SweepWorker(warm)])
    except (OSError, RuntimeError, TimeoutError) as exc:
        raise StageError("start LocalCluster", "sweep", f"{type(exc).__name__}: {exc}") from exc
    try:
        client = Client(cluster, security=security)
        try:
            if not dashboard:
                _http_off(client)
            yield client, n
        except KeyboardInterrupt:   # Ctrl-C or SIGTERM: the workers go at once, so the closing waits on none
            from strainwave.compare.sweep.prefork import stop_now
            stop_now()
            raise
        finally:
            client.close()
    finally:
        cluster.close()


# What Dask's ``distributed.nanny.pre-spawn-environ`` gives a spawned worker before its interpreter starts
# (one BLAS thread, glibc's trim threshold, a fixed hash seed); a forked worker inherits its fork server's.
FORK_SERVER_ENV = {**WORKER_ENV, "MALLOC_TRIM_THRESHOLD_": "65536", "PYTHONHASHSEED": "6640"}


def _exit_without_collecting() -> None:
    """At interpreter exit, after the sweep: move every object to the permanent generation, which the
    collection Python runs as it finalizes skips. That collection walks a heap holding pandas, matplotlib
    and distributed only to free memory the ending process gives back anyway
    (docs/decisions/013-sweep-worker-start-up.md); the workers do the same (``worker.SweepWorker``)."""
    gc.freeze()


@contextmanager
def _no_cyclic_collection() -> Iterator[None]:
    """The cyclic collector off around large imports: they allocate many objects and trigger collections
    over the growing heap, none of which is garbage (``prefork`` does the same in the fork server)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _import_driver_libraries() -> None:
    """pandas and matplotlib (the table and plots) and distributed, imported while the fork server imports
    the workers' libraries, without cyclic collections, which only slow them down
    (docs/decisions/013-sweep-worker-start-up.md)."""
    with _no_cyclic_collection():
        import distributed  # noqa: F401

        from strainwave.compare.sweep import outputs
        outputs.import_plotting()


def _start_fork_server(warm: tuple[str, ...]) -> bool:
    """Start the fork server the own LocalCluster's workers are forked from (``prefork``): it imports their
    libraries ``warm`` once, now, while this process imports its own and starts the scheduler. False where
    there is none (Windows): the workers are spawned then, and import ``warm`` themselves."""
    from strainwave.interrupt import children_ignore_sigint
    from strainwave.compare.sweep import prefork

    with children_ignore_sigint():   # the server and the workers forked from it leave Ctrl-C to the sweep
        return prefork.start(warm, FORK_SERVER_ENV)


def _eta(records: list[dict], remaining: int, workers: int) -> str:
    """Time left from the mean cost of the points solved so far (refusals cost nothing and are left out)."""
    costs = [r["elapsed_s"] for r in records if r["status"] == "ok" and r.get("elapsed_s")]
    if not costs:
        return "time left unknown"
    return f"~{sum(costs) / len(costs) * math.ceil(remaining / max(1, workers)):.0f} s left"


def _failed(spec: PointSpec, key: str, exc: BaseException, task: TaskFn | None) -> dict:
    """A point whose task never returned (worker killed, cancelled): recorded, not cached."""
    return {"status": "failed", "error": f"{type(exc).__name__}: {exc}", "key": key, "study": spec.study,
            "inputs": spec.inputs, "task": task_name(task), "fea": {}, "analytic": {}, "cached": False}


def _compute(client, specs: dict[str, PointSpec], cache_root: Path, task: TaskFn | None, workers: int,
             progress: Callable[[str], None], already: int, total: int, counts: dict) -> dict[str, dict]:
    """Submit every point under its cache key and collect the records as they finish."""
    from distributed import as_completed

    keys = list(specs)
    futures = client.map(run_point, [specs[k] for k in keys], keys, cache_root=str(cache_root), task=task,
                         key=[f"strainwave-sweep-{k}" for k in keys])
    by_future = dict(zip(futures, keys))
    done: dict[str, dict] = {}
    started = last_message = time.perf_counter()
    finished = as_completed(futures)
    while not finished.is_empty():
        if not finished.has_ready():
            time.sleep(POLL_S)
            if time.perf_counter() - last_message > HEARTBEAT_S:   # long solves: say the sweep is alive
                last_message = time.perf_counter()
                progress(f"sweep: {already + len(done)}/{total} points done, {len(keys) - len(done)} running or "
                         f"queued, {last_message - started:.0f} s elapsed")
            continue
        for future in finished.next_batch(block=False):
            key = by_future[future]
            try:
                record = future.result()
            except Exception as exc:  # noqa: BLE001 - a lost worker fails its point, not the sweep
                record = _failed(specs[key], key, exc, task)
            done[key] = record
            counts["failed"] += record["status"] != "ok"
            last_message = time.perf_counter()
            progress(f"sweep: {already + len(done)}/{total} points done, {counts['failed']} failed, "
                     f"{counts['cached']} from cache; {_eta(list(done.values()), len(keys) - len(done), workers)}")
    return done


def _cached_points(cache: ResultCache, keys: list[str]) -> dict[str, dict]:
    """The points a cache already holds, each checked against its own key (anything else is recomputed)."""
    by_key: dict[str, dict] = {}
    for key in keys:
        hit = cache.get(key, lambda r: point_record_ok(r, key))
        if hit is not None:
            by_key[key] = {**hit, "cached": True}
    return by_key


def run_sweep(study: str, *, vary: list[str], params_path: str | Path | None = None,
              sample_file: str | Path | None = None, scheduler: str | None = None, workers: int | None = None,
              out_dir: Path = Path("reports/sweep"), quick: bool = False, tolerance: float = 0.05,
              progress: Callable[[str], None] | None = None, task: TaskFn | None = None,
              dashboard: bool = False) -> Outcome:
    """Sweep ``study`` over a grid (``vary``) or sample rows (``sample_file``) of dotted parameter keys.

    ``task`` replaces the FEA study by another module-level function ``(study, params, quick) -> dict``
    (see ``sweep_task.TaskFn``); tests and the benchmark use it to exercise the Dask machinery cheaply.
    Results are cached in ``out_dir/cache``.
    """
    progress = progress or (lambda msg: None)
    atexit.unregister(_exit_without_collecting)   # once per process, however many sweeps it runs
    atexit.register(_exit_without_collecting)
    check_workers(workers)
    if not (tolerance > 0 and tolerance < float("inf")):
        raise InputError("--tolerance", tolerance, "must be a finite relative tolerance > 0, e.g. 0.05")
    out_dir = Path(out_dir)
    # The grid is checked against the schema before the parameters are validated, so a bad --vary is
    # refused in one line before any RangeWarning of the base parameters is printed.
    varied, points = build_points(list(vary), Path(sample_file) if sample_file else None, default_dict())
    base = load_params(params_path).to_dict()
    seed_crack = registered(study).crack_key in varied   # only a sweep over the study's own crack meshes one
    specs = [PointSpec(study, tuple(point.items()), base, quick, seed_crack) for point in points]
    elements = refuse_impossible(specs, "--samples" if sample_file and not vary else "--vary")
    keys = [point_key(spec, task) for spec in specs]
    cache = ResultCache(out_dir / "cache")
    started = time.perf_counter()

    by_key = _cached_points(cache, keys)
    # Most elements first: no worker idles at the end (docs/decisions/013-sweep-worker-start-up.md).
    order = sorted(range(len(specs)), key=lambda i: -elements[i])
    todo = {keys[i]: specs[i] for i in order if keys[i] not in by_key}
    counts = {"failed": sum(r["status"] != "ok" for r in by_key.values()), "cached": len(by_key)}
    progress(f"sweep {study}: {len(points)} points over {', '.join(varied)}; {len(by_key)} cached, "
             f"{len(todo)} to compute")
    n_workers = 0
    if todo:
        scratch = out_dir / ".dask-scratch"   # the workers' spill/lock space, removed when the sweep ends
        warm = warm_modules(study, task, specs)
        forked = scheduler is None and _start_fork_server(warm)
        try:
            _import_driver_libraries()   # while the fork server imports the workers' libraries
            with dask_client(scheduler, workers, scratch, warm, forked, dashboard) as (client, n_workers):
                progress(f"sweep: {n_workers} Dask workers at {client.scheduler.address}")
                if dashboard and not scheduler:
                    progress(f"sweep: Dask dashboard at {client.dashboard_link} (127.0.0.1: this machine only, "
                             f"no login)")
                by_key.update(_compute(client, todo, out_dir / "cache", task, n_workers, progress, len(by_key),
                                       len(points), counts))
        except KeyboardInterrupt:
            from strainwave.compare.sweep.prefork import stop_now
            stop_now()   # still importing, it would outlive the sweep by seconds
            # Interrupted, the in-process scheduler has not purged its workspace when the scratch goes below;
            # its exit finalizer would then log an ERROR about a folder that is removed on purpose.
            logging.getLogger("distributed.diskutils").setLevel(logging.CRITICAL)
            raise
        finally:
            shutil.rmtree(scratch, ignore_errors=True)

    from strainwave.compare.sweep.outputs import departures, plot_sweep, records_frame, write_markdown, write_records, write_table

    records = [{**by_key[key], "index": index, "inputs": spec.inputs}
               for index, (key, spec) in enumerate(zip(keys, specs))]
    frame = records_frame(records, varied)
    files = [*write_table(frame, out_dir), write_records(records, out_dir),
             *plot_sweep(frame, varied, out_dir, lines=sample_file is None,
                        value_label="FEA" if task is None else "task")]
    wall = time.perf_counter() - started
    n_ok = sum(r["status"] == "ok" for r in records)
    header = {"study": study, "points": len(records), "ok": n_ok, "failed": len(records) - n_ok,
              "from cache": sum(r.get("cached", False) for r in records), "quick meshes": quick,
              "task": task_name(task), "workers": n_workers or "none needed (all cached)",
              "wall time": f"{wall:.1f} s", "varied": ", ".join(varied)}
    files.append(write_markdown(frame, varied, tolerance, header, out_dir))
    return Outcome(study, out_dir, len(records), n_ok, len(records) - n_ok, header["from cache"], n_workers, wall,
                   tuple(files), tuple(departures(frame, varied, tolerance)))
