"""CPU seconds of single validate cases, solved as ``validate`` solves them.

Each case is taken from the gear's validation plan by its label, and run in validate's own child process
(``isolated.run_isolated``: forkserver, imports preloaded) with the runner's arguments. The cases of one
run share a fresh cache folder, as the cases of one validation do (no finished case is reused from it).
Printed per case: the child's CPU seconds (which the machine's other jobs hardly change), the wall time,
the load, the files written and the study's timings. Alternate two checkouts, one run each in turn, to
compare code.

    OMP_NUM_THREADS=1 python benchmarks/validate_case_cpu.py cup-a1.12 [cup-a0.396 ...] [--gear second] [--quick]
"""
from __future__ import annotations

import argparse
import inspect
import json
import os
import tempfile
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}


def run_one(case, params, quick: bool, out: Path) -> dict:
    """The case in validate's child process, with the arguments ``runner.run_case`` gives it."""
    from strainwave.compare.validate.isolated import run_isolated
    from strainwave.compare.validate.pipeline import ORDER
    from strainwave.fea.studies import run_study
    kwargs = {"mesh_size_mm": case.mesh_size_mm, "order": ORDER, "crack_depth_mm": case.crack_depth_mm,
              "vtu": out / f"{case.label}.vtu" if case.fields else None, "quick": quick}
    if case.fields and getattr(case, "crack_field_only", False):
        kwargs["crack_field_only"] = True
    if "cache_dir" in inspect.signature(run_study).parameters:     # an older checkout has none
        kwargs["cache_dir"] = out / "cache"
    load = os.getloadavg()[0]
    child = run_isolated(case.study, params, kwargs, timeout_s=900.0, progress=lambda m: None)
    if child.result is None:
        raise SystemExit(f"{case.label}: {child.error}")
    return {"case": case.label, "cpu_s": round(child.cpu_s, 2), "wall_s": round(child.seconds, 1),
            "load": round(load, 2),
            "fields": [Path(p).name for p in child.result["fields"]],
            "timings_s": {k: round(v, 2) for k, v in child.result["timings_s"].items()}}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("labels", nargs="+", help="the cases' labels in the plan, e.g. cup-a1.12, in the order to run")
    ap.add_argument("--gear", choices=sorted(GEARS), default="default")
    ap.add_argument("--quick", action="store_true", help="the --quick plan")
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    from strainwave.api import load_params
    from strainwave.compare.validate.plan import make_plan
    params = load_params(GEARS[args.gear])
    cases = {c.label: c for c in make_plan(params, quick=args.quick).all_cases()}
    missing = [label for label in args.labels if label not in cases]
    if missing:
        raise SystemExit(f"no case {missing} in the plan; cases: {', '.join(cases)}")
    for _ in range(args.repeat):
        out = Path(tempfile.mkdtemp(prefix="case-cpu-"))
        for label in args.labels:
            row = run_one(cases[label], params, args.quick, out)
            print(json.dumps({"gear": args.gear, "quick": args.quick, **row}), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
