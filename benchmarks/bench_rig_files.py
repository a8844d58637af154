"""Parsing cost of large rig exports: is it linear in the rows, and where is a million-row file refused?

Each file holds a linear spring (50 N m sine, K = 1.9e3 N m/rad) behind a metadata preamble, written as a
comma file and as a German semicolon file with decimal commas. Prints rows, MB, CPU and wall seconds, and
whether the file was accepted or refused (a million rows: at row MAX_ROWS + 1) with the load average.

    OMP_NUM_THREADS=1 nice -n 10 .venv/bin/python benchmarks/bench_rig_files.py
"""
from __future__ import annotations

import os
import time

import numpy as np

from strainwave.compare.diagnose.recording import TestFlags, parse_bytes
from strainwave.errors import InputError

FLAGS = TestFlags("torsion", "output_shaft", "1.9e3 Nm/rad")


def _file(n: int, german: bool) -> bytes:
    T = 50.0 * np.sin(np.linspace(0.0, 20.0 * np.pi, n))
    angle = np.degrees(T / 1.9e3)
    sep = ";" if german else ","
    rows = (f"{t:.4f}{sep}{a:.7f}" for t, a in zip(T, angle))
    body = "\n".join(r.replace(".", ",") for r in rows) if german else "\n".join(rows)
    return f"Date: 2026-11-28\nOperator: bench\nTorque [Nm]{sep}Angle [deg]\n{body}\n".encode()


def main() -> None:
    for n in (50_000, 100_000, 200_000, 1_000_000):
        for german in (False, True):
            raw = _file(n, german)
            c0, w0 = time.process_time(), time.perf_counter()
            try:
                outcome = f"accepted, {parse_bytes(raw, 'big.csv', FLAGS).n} rows"
            except InputError as exc:
                outcome = f"refused: {exc}"
            print(f"{n:>9} rows {'semicolon' if german else 'comma':9s} {len(raw) / 1e6:5.1f} MB  "
                  f"cpu {time.process_time() - c0:5.2f} s  wall {time.perf_counter() - w0:5.2f} s  {outcome}")
    print("load average:", " ".join(f"{x:.2f}" for x in os.getloadavg()))


if __name__ == "__main__":
    main()
