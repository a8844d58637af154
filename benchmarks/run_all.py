"""`make bench`: run every benchmark script in this folder, one process each, and stop on the first failure.

Benchmarks measure speed and memory on this machine; tests never time anything. Every goal line a
script prints (it ends in PASS or MISS) is repeated in one summary at the end, with the load average
at the start and at the end: on the shared 2-core machine the load says how far the times are inflated.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

GOAL_LINE = re.compile(r"\b(PASS|MISS)\b")


def load_average() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def main() -> int:
    here = Path(__file__).parent
    started = time.perf_counter()
    print(f"make bench: {os.cpu_count()} cores, load average {load_average()} (1, 5, 15 min)", flush=True)
    goals: list[tuple[str, str]] = []
    for script in sorted(here.glob("bench_*.py")):
        print(f"== {script.name}", flush=True)
        proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True, bufsize=1)
        for line in proc.stdout:
            print(line, end="", flush=True)
            if GOAL_LINE.search(line):
                goals.append((script.name, line.strip()))
        status = proc.wait()
        if status != 0:
            print(f"{script.name} failed with status {status}", file=sys.stderr)
            return status
    print(f"== summary: {len(goals)} goals, {sum('PASS' in g for _, g in goals)} PASS, "
          f"{sum('MISS' in g for _, g in goals)} MISS ({(time.perf_counter() - started) / 60:.1f} min, "
          f"load average now {load_average()})", flush=True)
    for name, line in goals:
        print(f"  {name}: {line}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
