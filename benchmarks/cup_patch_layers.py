"""The cup crack patch's through-wall layers: delta lambda_f, its GCI and the patch's CPU per layer rule.

The patch of validate's cup cases (``cup_torsion.local_patch_mesh``, Bueckner on the section's field) on its
three refinements, once with the shipped rule (the fewest cosine layers, up to 10, whose face layer is no
thicker than the a/4 tip: ``PlaneGrading.face_layer_to_tip``) and once per fixed finest layer count given
(``--layers``; 10 was the rule before decision 044). Printed per run: finest layers, dofs, CPU of the
patch (mesh, assembly, solve: ``time.process_time``, which the machine's other jobs hardly change), delta
lambda_f and its GCI. ``--finest-only`` solves the finest patch alone per layer count (the layers' own
convergence at fixed in-plane mesh); ``--half`` sets the patch half size L/a.

    python benchmarks/cup_patch_layers.py --gear default --depth 1.12 0.396 --layers 10
    python benchmarks/cup_patch_layers.py --depth 1.12 --finest-only --layers 2 3 4 5 6 8 10 14
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}


def patch_series(params, depth_mm: float, grading, half_over_a: float, levels: tuple[int, ...]) -> dict:
    """delta lambda_f per refinement level k (0: finest) of the cup's patch under ``grading``, with CPU s."""
    from strainwave.fea import cup_torsion as ct
    from strainwave.fea.assembly import Lame
    from strainwave.fea.crack_local import compliance_from_release, local_release, patch_solver
    from strainwave.fea.cup_axisym import section_displacement, section_fine_mm, solve_cup_section
    from strainwave.fea.refinement import DEFAULT_RATIO, refinement_sizes

    ct.PATCH_HALF_OVER_A = half_over_a
    part = ct._build(params, depth_mm, False)
    mat, wall = params.material, params.flexspline_cup.wall_thickness_mm
    lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)
    sizes = refinement_sizes(section_fine_mm(params, False), DEFAULT_RATIO)
    rows = {}
    for k in levels:
        field = section_displacement(solve_cup_section(params, sizes[k], keep_fields=True).fields["section"])
        c0 = time.process_time()
        md, _ = ct.local_patch_mesh(part, depth_mm, DEFAULT_RATIO ** k, grading)
        local = local_release(md, lame, field, study=ct.STUDY, method=patch_solver(2 * half_over_a * depth_mm, wall))
        rows[k] = {"h_mm": sizes[k], "layers": grading.sizes(depth_mm, DEFAULT_RATIO ** k, wall)[3],
                   "dofs": local.dofs, "cpu_s": round(time.process_time() - c0, 2),
                   "delta": compliance_from_release(local.released_Nmm, ct.SECTION_TORQUE_NMM)}
    return rows


def summary(rows: dict) -> dict:
    """The finest row with the GCI of the three (the crack delta's formal order, as the study reports it)."""
    from strainwave.fea.refinement import CRACK_FORMAL_ORDER, converged_quantity
    out = dict(rows[0], cpu_s=round(sum(r["cpu_s"] for r in rows.values()), 2))
    if len(rows) == 3:
        q = converged_quantity("delta_flexibility_rad_per_Nmm", "rad/(N*mm)", [rows[k]["h_mm"] for k in (0, 1, 2)],
                               [rows[k]["delta"] for k in (0, 1, 2)], order=CRACK_FORMAL_ORDER)
        out["gci_pct"] = round(100 * q.convergence.gci_fine, 3)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gear", choices=sorted(GEARS), default="default")
    ap.add_argument("--depth", type=float, nargs="+", default=[1.12], help="crack depths a, mm")
    ap.add_argument("--layers", type=int, nargs="*", default=[], help="fixed finest layer counts to compare")
    ap.add_argument("--finest-only", action="store_true", help="the finest patch alone per layer count")
    ap.add_argument("--half", type=float, default=32.0, help="patch half size L/a")
    args = ap.parse_args()
    from strainwave.api import load_params
    from strainwave.fea.cup_torsion import LOCAL_GRADING
    from strainwave.fea.studies import with_crack
    base = load_params(GEARS[args.gear])
    fixed = [(f"{n} layers", dataclasses.replace(LOCAL_GRADING, layers=n, face_layer_to_tip=False)) for n in args.layers]
    gradings = [("rule", LOCAL_GRADING)] + fixed
    for depth in args.depth:
        params = with_crack("cup-torsion", base, depth)
        for name, grading in gradings if not args.finest_only else gradings[1:]:
            rows = patch_series(params, depth, grading, args.half, (0,) if args.finest_only else (2, 1, 0))
            print(json.dumps({"gear": args.gear, "depth_mm": depth, "half_over_a": args.half, "grading": name,
                              **summary(rows), "load": round(os.getloadavg()[0], 2)}), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
