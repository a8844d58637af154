"""CPU seconds of validate's background STEP worker, spawned or forked from the cases' fork server.

The worker exports every part with its preview, as validate's does, and reports its own user + system CPU
seconds (``getrusage``). The fork server is started before the count, as the run's first FEA case starts it.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/step_worker_cpu.py spawn|fork [PARAMS.toml]   # alternate them
"""
from __future__ import annotations

import multiprocessing
import os
import resource
import sys
import tempfile
import time
from pathlib import Path


def _measured(conn, cpu_conn, jobs, params) -> None:
    from strainwave.compare.validate import step_export
    try:
        step_export._worker(conn, jobs, params)
    finally:
        own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu_conn.send(own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime)


def main(mode: str, params_file: str | None) -> None:
    from strainwave.compare.validate.isolated import fork_server_context
    from strainwave.compare.validate.step_export import PREVIEWED
    from strainwave.geometry.part import PartName
    from strainwave.params import load_params

    params = load_params(params_file)
    out = Path(tempfile.mkdtemp())
    jobs = [(p.value, out / f"{p.value}.step", out / f"{p.value}.png" if p.value in PREVIEWED else None)
            for p in PartName]
    ctx = fork_server_context() if mode == "fork" else multiprocessing.get_context("spawn")
    if mode == "fork":
        warm = ctx.Process(target=os.getpid)
        warm.start()
        warm.join()
    parts_in, parts_out = ctx.Pipe(duplex=False)
    cpu_in, cpu_out = ctx.Pipe(duplex=False)
    start = time.perf_counter()
    ctx.Process(target=_measured, args=(parts_out, cpu_out, jobs, params), daemon=True).start()
    for _ in jobs:
        parts_in.recv()
    print(f"{mode}: worker CPU {cpu_in.recv():.2f} s, wall {time.perf_counter() - start:.2f} s, "
          f"load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    if len(sys.argv) < 2 or sys.argv[1] not in ("spawn", "fork"):
        sys.exit("usage: step_worker_cpu.py spawn|fork [PARAMS.toml]")
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None)
