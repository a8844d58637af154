"""NAFEMS LE1, LE10 and LE11 on their fine mesh families through the solver core (``fea/nafems``).

Each line ends in PASS when the finest value's whole GCI band lies within 1 % of the NAFEMS target
(|error| + GCI <= 1 %, issue 37), else MISS. The record goes to reports/bench/nafems.json, which the
validate report's NAFEMS appendix quotes beside its own coarse runs.

    python benchmarks/bench_nafems.py            # every case
    python benchmarks/bench_nafems.py LE11       # the named cases, merged into the existing record
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
    return (f"NAFEMS {r.bench.id} sigma_{r.bench.component}({r.bench.point_name}) = {r.value_MPa:.4f} MPa, "
            f"target {r.bench.target_MPa:g}, "
            f"error {100 * r.error_rel:+.3f} %, {r.points[0].dofs} dofs, GCI {100 * c.gci_fine:.3f} % "
            f"({c.basis}; observed p {c.observed_order:.3g}), {seconds:.0f} s: "
            f"goal |error| + GCI <= 1 %: {'PASS' if r.passed else 'MISS'}")


def main(ids: list[str]) -> int:
    unknown = sorted(set(ids) - set(nafems.BENCHMARKS))
    if unknown:
        print(f"bench_nafems: unknown case {unknown[0]!r}; allowed: {', '.join(nafems.BENCHMARKS)}", file=sys.stderr)
        return 2
    results = []
    for bench in (nafems.BENCHMARKS[i] for i in (ids or nafems.BENCHMARKS)):
        t0 = time.perf_counter()
        r = nafems.run(bench, nafems.FINE_SIZES_MM[bench.id], "fine")
        results.append(r)
        print(line(r, time.perf_counter() - t0), flush=True)
    doc = nafems.results_document(results)
    if ids and OUT.exists():        # a subset replaces its own cases in the record and keeps the others
        doc["cases"] = [c for c in json.loads(OUT.read_text())["cases"] if c["id"] not in ids] + doc["cases"]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(OUT) as tmp:
        tmp.write_text(json.dumps(doc, indent=1))
    print(f"wrote {OUT}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
