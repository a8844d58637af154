"""Diagnosis benchmark: speed of one long recording (10,000 and 100,000 rows) and the blind accuracy of
both generator families (`benchmark-diagnose`, incl. the whole CHA table), each target PASS/MISS.

Run: .venv/bin/python benchmarks/bench_diagnose.py [--n 10] [--seed 0] [--repeats 3] [--out reports/bench_diagnose]
     [--speed-only] [--workers N]
Exit status 1 if any target is missed. Timings are medians of repeats (parse + diagnose, analytic
baseline, one BLAS thread); the machine's load average is printed beside them because the machine is shared.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
import warnings
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

SPEED_TARGETS_S = {10_000: 2.0, 100_000: 15.0}


def speed(params, rows: int, repeats: int, workers: int | None = None) -> tuple[float, str]:
    """Median time to parse and diagnose a CHA gear recording (three slopes + friction loop) of ``rows`` rows."""
    from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.recording import parse_text
    text = cha_recording(cha_rows()[10], hysteresis=True, n=rows)
    times = []
    diagnose(parse_text(cha_recording(cha_rows()[10], hysteresis=True, n=200)), params, workers=workers)  # warm
    load = os.getloadavg()
    for _ in range(repeats):
        t = time.perf_counter()
        diagnose(parse_text(text), params, workers=workers)
        times.append(time.perf_counter() - t)
    med = statistics.median(times)
    target = SPEED_TARGETS_S[rows]
    status = "PASS" if med < target else "MISS"
    return med, (f"{status} {rows:,}-row recording: median of {repeats} = {med:.2f} s (target < {target:g} s; "
                 f"runs {', '.join(f'{x:.2f}' for x in times)} s; load average {load[0]:.2f} {load[1]:.2f} "
                 f"on {os.cpu_count()} cores)")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=10, help="recordings per class and family")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="reports/bench_diagnose")
    ap.add_argument("--speed-only", action="store_true", help="only the two speed targets")
    ap.add_argument("--workers", type=int, default=None, help="fit processes (default: what the machine offers)")
    args = ap.parse_args()
    from strainwave.compare.diagnose.generators.benchmark import run_benchmark
    from strainwave.errors import RangeWarning
    from strainwave.io_atomic import atomic_write_text
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        params = load_params()
    lines, ok = [], True
    for rows in SPEED_TARGETS_S:
        seconds, line = speed(params, rows, args.repeats, args.workers)
        ok &= seconds < SPEED_TARGETS_S[rows]
        print(line, flush=True)
        lines.append(line)
    if args.speed_only:
        return 0 if ok else 1
    report = run_benchmark(n_per_class=args.n, seed=args.seed, out_dir=Path(args.out))
    print(report.summary())
    atomic_write_text(Path(args.out) / "bench_diagnose.txt", "\n".join([*lines, report.summary()]) + "\n")
    return 0 if (ok and report.meets_targets) else 1


if __name__ == "__main__":
    sys.exit(main())
