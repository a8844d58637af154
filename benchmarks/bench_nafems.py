"""NAFEMS LE1 and LE10 on their fine mesh families through the solver core (``fea/nafems``).

Each line ends in PASS when the finest value's whole GCI band lies within 1 % of the NAFEMS target
(|error| + GCI <= 1 %, issue 37), else MISS. The record goes to reports/bench/nafems.json, which the
validate report's NAFEMS appendix quotes beside its own coarse runs.
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

from strainwave.fea import nafems  # noqa: E402
from strainwave.io_atomic import atomic_path  # noqa: E402

OUT = Path("reports/bench/nafems.json")


def line(r: nafems.NafemsResult, seconds: float) -> str:
    c = r.convergence
    return (f"NAFEMS {r.bench.id} sigma_{r.bench.component}(D) = {r.value_MPa:.4f} MPa, target {r.bench.target_MPa:g}, "
            f"error {100 * r.error_rel:+.3f} %, {r.points[0].dofs} dofs, GCI {100 * c.gci_fine:.3f} % "
            f"({c.basis}; observed p {c.observed_order:.3g}), {seconds:.0f} s: "
            f"goal |error| + GCI <= 1 %: {'PASS' if r.passed else 'MISS'}")


def main() -> int:
    results = []
    for bench in nafems.BENCHMARKS.values():
        t0 = time.perf_counter()
        r = nafems.run(bench, nafems.FINE_SIZES_MM[bench.id], "fine")
        results.append(r)
        print(line(r, time.perf_counter() - t0), flush=True)
    print(nafems.LE11_NOTE, flush=True)
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(OUT) as tmp:
        tmp.write_text(json.dumps(nafems.results_document(results), indent=1))
    print(f"wrote {OUT}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
