"""Cup crack compliance: the whole-cup seam (old) against global-local (new), on validate's cup cases.

For each shipped gear and each cup case of the full validation plan (the headline depth at the study's mesh,
the sweep depths at the --quick mesh), both methods solve delta lambda_f on three meshes; printed per case:
CPU seconds of each (time.process_time, which the machine's other jobs hardly change; the wall time and the
load beside it), delta lambda_f and
its GCI, and the accuracy rule of issue 36: |new - old| <= RSS of the two GCIs. Also lambda_f and its GCI
(the headline flexibility check's value). ``--patch`` instead sweeps the local patch's half size L/a at one
depth, to show the fixed-grip error O((a/L)^2).

    python benchmarks/crack_compliance_methods.py [--gear default|second] [--method both|seam|global-local]
    python benchmarks/crack_compliance_methods.py --patch 4 8 12 16 --depth 1.12
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}
QUANTITIES = ("delta_flexibility_rad_per_Nmm", "flexibility_rad_per_Nmm")


def solve(params, method: str, depth_mm: float, mesh_size_mm: float | None) -> dict:
    from strainwave.fea import cup_torsion
    c0, w0 = time.process_time(), time.perf_counter()
    r = cup_torsion.run(params, crack_depth_mm=depth_mm, mesh_size_mm=mesh_size_mm, crack_method=method)
    row = {"method": method, "depth_mm": depth_mm, "cpu_s": round(time.process_time() - c0, 1),
           "wall_s": round(time.perf_counter() - w0, 1), "load": round(os.getloadavg()[0], 2)}
    for name in QUANTITIES:
        q = r.quantities[name]
        row[name] = [q.value, q.uncertainty]
    return row


def agreement(old: dict, new: dict, name: str = QUANTITIES[0]) -> str:
    (v0, u0), (v1, u1) = old[name], new[name]
    rss = math.hypot(u0, u1)
    return (f"|new - old| = {abs(v1 - v0):.3g} vs RSS(GCI) {rss:.3g}: {'agree' if abs(v1 - v0) <= rss else 'DISAGREE'}; "
            f"GCI {100 * u0 / v0:.2f} % -> {100 * u1 / v1:.2f} %")


def cases(params):
    from strainwave.compare.validate.plan import make_plan
    plan = make_plan(params, quick=False)
    return [plan.headline["cup"], *plan.sweeps["cup"]]


def compare_methods(gear: str, methods: list[str]) -> None:
    from strainwave.params import load_params
    params = load_params(GEARS[gear])
    for case in cases(params):
        rows = {m: solve(params, m, case.crack_depth_mm, case.mesh_size_mm) for m in methods}
        for row in rows.values():
            print(json.dumps({"gear": gear, "case": case.label, **row}), flush=True)
        if len(rows) == 2:
            print(f"# {gear} {case.label}: CPU {rows['seam']['cpu_s']} -> {rows['global-local']['cpu_s']} s; "
                  f"delta lambda_f {agreement(rows['seam'], rows['global-local'])}; "
                  f"lambda_f {agreement(rows['seam'], rows['global-local'], QUANTITIES[1])}", flush=True)


def patch_sweep(gear: str, depth_mm: float, halves: list[float]) -> None:
    from strainwave.fea import cup_torsion
    from strainwave.params import load_params
    params = load_params(GEARS[gear])
    h = cup_torsion.default_size_mm(params, True)
    for half in halves:
        cup_torsion.PATCH_HALF_OVER_A = half
        row = solve(params, "global-local", depth_mm, h)
        print(json.dumps({"gear": gear, "patch_half_over_a": half, **row}), flush=True)


def main() -> int:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    ap = argparse.ArgumentParser()
    ap.add_argument("--gear", choices=sorted(GEARS), default="default")
    ap.add_argument("--method", choices=("both", "seam", "global-local"), default="both")
    ap.add_argument("--patch", type=float, nargs="+", help="patch half sizes L/a to sweep (global-local only)")
    ap.add_argument("--depth", type=float, default=1.12, help="crack depth of --patch, mm")
    args = ap.parse_args()
    print(f"# load {' '.join(f'{v:.2f}' for v in os.getloadavg())}", flush=True)
    if args.patch:
        patch_sweep(args.gear, args.depth, args.patch)
    else:
        compare_methods(args.gear, ["seam", "global-local"] if args.method == "both" else [args.method])
    print(f"# load {' '.join(f'{v:.2f}' for v in os.getloadavg())}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
