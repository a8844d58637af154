"""The bearing ring's crack on its patch (a cache folder shared by the depths) against the whole ring's seam (no
folder), at validate's depths: each quantity, its GCI and |patch - whole| / RSS of the two uncertainties, the
patch's dofs and the CPU seconds of each route (imports and the gmsh children not counted).

    OMP_NUM_THREADS=1 python benchmarks/bearing_patch_accuracy.py [--gear second] [--over 4 3 6 8] [--depth 2.08]
"""
from __future__ import annotations

import argparse
import json
import math
import tempfile
import time
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}
NAMES = ("radial_compliance_mm_per_N", "delta_radial_compliance_mm_per_N")


def solve(params, case, cache_dir) -> tuple[dict, float, dict]:
    from strainwave.compare.validate.pipeline import ORDER
    from strainwave.fea.studies import run_study
    t0 = time.process_time()
    r = run_study(case.study, params, mesh_size_mm=case.mesh_size_mm, order=ORDER, crack_depth_mm=case.crack_depth_mm,
                  cache_dir=cache_dir)
    return r.quantities, time.process_time() - t0, r.solver


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gear", choices=sorted(GEARS), default="default")
    ap.add_argument("--over", type=float, nargs="+", default=None,
                    help="patch radius over max(a, c) (default: the code's)")
    ap.add_argument("--depth", type=float, nargs="+", default=None, help="only these depths of the plan")
    args = ap.parse_args()
    import strainwave.fea.bearing_ring as br
    from strainwave.api import load_params
    from strainwave.compare.validate.plan import make_plan
    params = load_params(GEARS[args.gear])
    cases = [c for c in make_plan(params, quick=False).all_cases() if c.study == br.STUDY
             and (args.depth is None or c.crack_depth_mm in args.depth)]
    cache = Path(tempfile.mkdtemp(prefix="bearing-patch-"))
    for case in cases:
        whole, cpu_whole, _ = solve(params, case, None)
        for over in args.over or [br.PATCH_OVER_CRACK]:
            br.PATCH_OVER_CRACK = over
            patch, cpu_patch, facts = solve(params, case, cache)
            row = {"gear": args.gear, "case": case.label, "over": over, "patch_dofs": facts.get("dofs"),
                   "seam_dofs": facts.get("dofs_total"), "cpu_whole_s": round(cpu_whole, 2),
                   "cpu_patch_s": round(cpu_patch, 2)}
            for name in NAMES:
                a, b = whole[name], patch[name]
                rss = math.hypot(a.uncertainty, b.uncertainty)
                row[name] = {"whole": a.value, "whole_gci": a.convergence.gci_fine, "patch": b.value,
                             "patch_gci": b.convergence.gci_fine, "diff_over_rss": abs(b.value - a.value) / rss,
                             "meshes_whole": list(a.convergence.values), "meshes_patch": list(b.convergence.values)}
            print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
