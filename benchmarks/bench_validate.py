"""Wall time of ``strainwave validate`` (embedded default parameters) after set-up, --quick and full.

Each run starts in an empty output folder, so no FEA case or STEP file comes from a cache, exactly as a
fresh clone's first ``make validate``. Printed: the wall time, the verdict (exit status, checks passed),
the time of each pipeline stage and of each FEA case (from results.json; cases run two at a time, so
their sum exceeds the FEA stage; with each case's CPU time, which other jobs on the machine hardly
change), and PASS/MISS against issue 15's goals: --quick <= 20 s, full <= 45 s.
``make validate`` also validates strainwave/data/second_gear.toml; the goals are per run, as here.

    python benchmarks/bench_validate.py [--only quick|full]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

GOALS_S = {"quick": 20.0, "full": 45.0}
STRAINWAVE = str(Path(sys.executable).with_name("strainwave"))


def load_average() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def one_run(mode: str, root: Path) -> dict:
    out = root / mode
    cmd = [STRAINWAVE, "-q", "validate", "--out", str(out)] + (["--quick"] if mode == "quick" else [])
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    row = {"mode": mode, "wall_s": wall, "status": proc.returncode, "stderr": proc.stderr.strip()[-400:]}
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
    goal = GOALS_S[row["mode"]]
    verdict = {0: "every check passes", 1: "a check failed", 2: "bad input"}.get(row["status"], f"status {row['status']}")
    checks = row.get("checks")
    print(f"validate {row['mode']}: {row['wall_s']:.1f} s wall, exit {row['status']} ({verdict}"
          + (f", {checks[0]}/{checks[1]} checks pass" if checks else "") + ")", flush=True)
    if row["status"] not in (0, 1):
        print(f"  stderr: {row['stderr']}")
    if "stages_s" in row:
        print("  stages: " + ", ".join(f"{k} {v:.1f} s" for k, v in row["stages_s"].items()))
        # CPU time too: the wall time of a case grows with whatever else shares the cores, its CPU time hardly
        print("  FEA cases (2 at a time), wall / CPU: " + ", ".join(
            f"{label} {s:.1f}" + ("" if cpu is None else f" / {cpu:.1f}") + " s" + (" (cached)" if cached else "")
            for label, s, cached, cpu in row["cases_s"]))
    ok = row["wall_s"] <= goal and row["status"] in (0, 1)
    print(f"goal validate {row['mode']} <= {goal:.0f} s after set-up: {row['wall_s']:.1f} s: "
          f"{'PASS' if ok else 'MISS'} (load {load_average()})", flush=True)


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", choices=sorted(GOALS_S))
    args = ap.parse_args()
    print(f"validate wall time, empty output folder each run ({os.cpu_count()} cores, load {load_average()})", flush=True)
    with tempfile.TemporaryDirectory(prefix="bench-validate-") as tmp:
        for mode in ([args.only] if args.only else ["quick", "full"]):
            show(one_run(mode, Path(tmp)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
