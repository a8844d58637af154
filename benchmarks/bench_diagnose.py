"""Diagnosis benchmark: blind accuracy at larger n, the whole CHA table, and the 10,000-row speed target.

Run: .venv/bin/python benchmarks/bench_diagnose.py [--n 20] [--seed 0] [--out reports/bench_diagnose]
Exit status 1 if a target (>= 95 % at signal >= 3x noise, <= 5 % false alarms, 10,000 rows < 5 s) is missed.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")


def cha_table(params) -> list[str]:
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.cha import cha_recording, cha_rows
    from strainwave.compare.diagnose.recording import parse_text
    lines = ["CHA table recovery (2000 rows, 20-bit encoder): relative error of the fitted parameters in %",
             f"{'gear':<10s} {'loop':<5s} {'named':<34s} {'K1':>6s} {'K2':>6s} {'K3':>6s} {'T1':>6s} {'T2':>6s} "
             f"{'loss':>6s}"]
    worst = 0.0
    for row in cha_rows():
        for loop in (False, True):
            diag, _ = diagnose(parse_text(cha_recording(row, hysteresis=loop)), params)
            top = diag.effects[0]
            pre = "nonlinear_stiffness." if len(top.components) > 1 else ""
            errs = [100 * (top.parameters[pre + k][0] / getattr(row, f"{k}_Nmm_per_rad") - 1) for k in ("K1", "K2", "K3")]
            errs += [100 * (top.parameters[pre + k][0] / getattr(row, f"{k}_Nmm") - 1) for k in ("T1", "T2")]
            loss = (100 * (top.parameters["hysteresis.hysteresis_loss_arcmin"][0] / (0.8 * row.hysteresis_limit_arcmin) - 1)
                    if "hysteresis.hysteresis_loss_arcmin" in top.parameters else float("nan"))
            worst = max(worst, max(abs(e) for e in errs[:3]))
            lines.append(f"CHA-{row.size}-{row.ratio:<4s} {'yes' if loop else 'no':<5s} {top.id:<34s} "
                         + " ".join(f"{e:+6.1f}" for e in errs) + f" {loss:+6.1f}")
    lines.append(f"worst stiffness error: {worst:.1f} %")
    return lines


def speed(params) -> tuple[float, str]:
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.cha import cha_recording, cha_rows
    from strainwave.compare.diagnose.recording import parse_text
    text = cha_recording(cha_rows()[10], hysteresis=True, n=10_000)
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        diag, _ = diagnose(parse_text(text), params)
        best = min(best, time.perf_counter() - t)
    return best, f"10,000-row recording (parse + diagnose, analytic baseline): best of 3 = {best:.2f} s (target < 5 s)"


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default="reports/bench_diagnose")
    args = ap.parse_args()
    from strainwave.compare.diagnose.benchmark import run_benchmark
    from strainwave.errors import RangeWarning
    from strainwave.io_atomic import atomic_write_text
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        params = load_params()
    seconds, speed_line = speed(params)
    print(speed_line, flush=True)
    cha = cha_table(params)
    print("\n".join(cha), flush=True)
    report = run_benchmark(n_per_class=args.n, seed=args.seed, out_dir=Path(args.out))
    print(report.summary())
    atomic_write_text(Path(args.out) / "bench_diagnose.txt",
                      "\n".join([speed_line, *cha, report.summary()]) + "\n")
    return 0 if (report.meets_targets and seconds < 5.0) else 1


if __name__ == "__main__":
    sys.exit(main())
