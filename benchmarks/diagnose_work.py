"""The work of one diagnosis in ONE process: CPU seconds (medians of repeats) and the deterministic counts of
effect evaluations, trust-region fits and scipy's SVDs, for the speed benchmark's CHA recording.

Run: OMP_NUM_THREADS=1 .venv/bin/python benchmarks/diagnose_work.py [--rows 10000] [--repeats 5] [--counts] [--workers 2]
CPU time does not depend on the other engineers' load as much as wall time does, the counts not at all; to
compare two versions of the code, alternate their runs (each with its own checkout's interpreter).
"""
from __future__ import annotations

import argparse
import collections
import os
import statistics
import time
import warnings

os.environ.setdefault("OMP_NUM_THREADS", "1")


def _counted() -> collections.Counter:
    """Count effect evaluations, trust-region fits and SVDs from here on (wrapping the library calls)."""
    import scipy.optimize._lsq.trf as trf
    from strainwave.compare.diagnose import fit
    from strainwave.compare.diagnose.effects import effects_for
    counts: collections.Counter = collections.Counter()

    def counting(name, fn):
        def wrapped(*args, **kwargs):
            counts[name] += 1
            return fn(*args, **kwargs)
        return wrapped
    trf.svd = counting("svds", trf.svd)
    fit.least_squares = counting("trust_region_fits", fit.least_squares)
    for e in {*effects_for("torsion"), *effects_for("ring_compression")}:
        object.__setattr__(e, "contribution", counting("effect_evaluations", e.contribution))
    return counts


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=10_000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--counts", action="store_true", help="count the work instead of timing it")
    ap.add_argument("--workers", type=int, default=1,
                    help="2: the fits shared with a forked copy; the parent's CPU (the wall time where the copy has a "
                         "core of its own) and the copies' CPU are timed apart")
    args = ap.parse_args()
    from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.recording import parse_text
    from strainwave.errors import RangeWarning
    from strainwave.params import load_params
    warnings.simplefilter("ignore", RangeWarning)
    params = load_params()
    text = cha_recording(cha_rows()[10], hysteresis=True, n=args.rows)
    diagnose(parse_text(cha_recording(cha_rows()[10], hysteresis=True, n=200)), params, workers=1)   # warm
    if args.counts:
        counts = _counted()
        diag, _ = diagnose(parse_text(text), params, workers=1)
        print(f"{args.rows:,} rows: {dict(sorted(counts.items()))}; verdict {diag.verdict.value} {list(diag.named)}")
        return
    cpu, copies = [], []
    for _ in range(args.repeats):
        t, c = time.process_time(), os.times()
        diagnose(parse_text(text), params, workers=args.workers)
        cpu.append(time.process_time() - t)
        after = os.times()            # a joined copy's CPU is counted among the children's
        copies.append(after.children_user + after.children_system - c.children_user - c.children_system)
    where = "one process" if args.workers == 1 else \
        f"{args.workers} workers (copies' CPU median {statistics.median(copies):.2f} s)"
    print(f"{args.rows:,} rows, {where}: median CPU {statistics.median(cpu):.2f} s of {args.repeats} "
          f"({', '.join(f'{x:.2f}' for x in cpu)}); load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
