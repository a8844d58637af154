"""Wall time of ``strainwave validate`` after set-up, --quick and full, against issue 36's goals.

Each run starts in an empty output folder, so no FEA case or STEP file comes from a cache, exactly as a
fresh clone's first ``make validate``. "full" is what ``make validate`` runs: the embedded default gear,
then strainwave/data/second_gear.toml; its time is the sum of the two. Printed per run: the wall time,
the verdict (exit status, checks passed), the time of each pipeline stage and of each FEA case (from
results.json; cases run two at a time, so their sum exceeds the FEA stage; with each case's CPU time,
which other jobs on the machine hardly change), and the machine's busy CPU seconds over the run from
/proc/stat with the share of the cores they fill: a run that keeps every core busy can get no faster than its
CPU seconds over the cores (on a quiet machine the busy seconds are the run's own). With ``--repeat N`` the modes alternate (quick, full,
quick, ...) so that both see the same load, and the goal line takes the median. Goals (issue 36, with the
wave generator's studies in the run): --quick <= 15 s, full (both gears) <= 60 s.

    python benchmarks/bench_validate.py [--only quick|full] [--repeat N]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

GOALS_S = {"quick": 15.0, "full": 60.0}
SECOND_GEAR = str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")
GEARS = {"quick": (None,), "full": (None, SECOND_GEAR)}
STRAINWAVE = str(Path(sys.executable).with_name("strainwave"))


def load_average() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def busy_cpu_s() -> float:
    """CPU seconds the machine has spent busy since boot: every /proc/stat column but idle and iowait."""
    fields = [int(v) for v in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    return (sum(fields[:8]) - fields[3] - fields[4]) / os.sysconf("SC_CLK_TCK")


def one_run(mode: str, root: Path, params: str | None = None) -> dict:
    out = root / (mode + ("-second-gear" if params else ""))
    cmd = [STRAINWAVE, "-q", "validate", "--out", str(out)] + (["--quick"] if mode == "quick" else []) \
        + (["--params", params] if params else [])
    t0, busy0 = time.perf_counter(), busy_cpu_s()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall, busy = time.perf_counter() - t0, busy_cpu_s() - busy0
    row = {"mode": mode + (" (second gear)" if params else ""), "wall_s": wall, "status": proc.returncode,
           "stderr": proc.stderr.strip()[-400:], "load": load_average(), "busy_cpu_s": busy,
           "busy_share": busy / (wall * (os.cpu_count() or 1))}
    results = out / "results.json"
    if results.exists():
        data = json.loads(results.read_text())
        meta = data["metadata"]
        row["stages_s"] = meta.get("timings_s", {})
        row["cases_s"] = sorted(((c["label"], c["seconds"], c.get("cached", False), c.get("cpu_s"))
                                 for c in meta.get("cases", [])), key=lambda c: -c[1])
        checks = data.get("checks", [])
        row["checks"] = (sum(1 for c in checks if c.get("passed")), len(checks))
    return row


def show(row: dict) -> None:
    verdict = {0: "every check passes", 1: "a check failed", 2: "bad input"}.get(row["status"], f"status {row['status']}")
    checks = row.get("checks")
    print(f"validate {row['mode']}: {row['wall_s']:.1f} s wall, exit {row['status']} ({verdict}"
          + (f", {checks[0]}/{checks[1]} checks pass" if checks else "") + f"), load {row['load']}", flush=True)
    print(f"  machine busy {row['busy_cpu_s']:.1f} CPU s over the run: {100 * row['busy_share']:.0f} % of "
          f"{os.cpu_count()} cores (the floor of this run's wall time is its CPU s over the cores)")
    if row["status"] not in (0, 1):
        print(f"  stderr: {row['stderr']}")
    if "stages_s" in row:
        print("  stages: " + ", ".join(f"{k} {v:.1f} s" for k, v in row["stages_s"].items()))
        # CPU time too: the wall time of a case grows with whatever else shares the cores, its CPU time hardly
        print("  FEA cases (2 at a time), wall / CPU: " + ", ".join(
            f"{label} {s:.1f}" + ("" if cpu is None else f" / {cpu:.1f}") + " s" + (" (cached)" if cached else "")
            for label, s, cached, cpu in row["cases_s"]))


def goal_line(mode: str, times_s: list[float], ok: bool, floors_s: list[float]) -> str:
    goal = GOALS_S[mode]
    median = statistics.median(times_s)
    what = "validate --quick" if mode == "quick" else "make validate (both gears)"
    return (f"goal {what} <= {goal:.0f} s after set-up: median {median:.1f} s of {len(times_s)} "
            f"({', '.join(f'{t:.1f}' for t in times_s)}): {'PASS' if median <= goal and ok else 'MISS'} "
            f"(load {load_average()}; busy CPU s over the cores, the wall time's floor: median "
            f"{statistics.median(floors_s):.1f} s)")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", choices=sorted(GOALS_S))
    ap.add_argument("--repeat", type=int, default=1, help="runs per mode, alternating the modes")
    args = ap.parse_args()
    print(f"validate wall time, empty output folder each run ({os.cpu_count()} cores, load {load_average()})", flush=True)
    modes = [args.only] if args.only else ["quick", "full"]
    times = {m: [] for m in modes}
    floors = {m: [] for m in modes}
    ok = {m: True for m in modes}
    with tempfile.TemporaryDirectory(prefix="bench-validate-") as tmp:
        for k in range(max(1, args.repeat)):
            for mode in modes:
                rows = []
                for gear in GEARS[mode]:
                    rows.append(one_run(mode, Path(tmp) / str(k), gear))
                    show(rows[-1])
                times[mode].append(sum(r["wall_s"] for r in rows))
                floors[mode].append(sum(r["busy_cpu_s"] for r in rows) / (os.cpu_count() or 1))
                ok[mode] &= all(r["status"] in (0, 1) for r in rows)
    for mode in modes:
        print(goal_line(mode, times[mode], ok[mode], floors[mode]), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
