"""`make bench`: run every benchmark script in this folder, one process each, and stop on the first failure.

Benchmarks measure speed and memory on this machine; tests never time anything.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path


def main() -> int:
    here = Path(__file__).parent
    for script in sorted(here.glob("bench_*.py")):
        print(f"== {script.name}", flush=True)
        status = subprocess.call([sys.executable, str(script)])
        if status != 0:
            print(f"{script.name} failed with status {status}", file=sys.stderr)
            return status
    return 0


if __name__ == "__main__":
    sys.exit(main())
