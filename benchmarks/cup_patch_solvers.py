"""The cup crack patch's solver per patch: PARDISO against p-multigrid CG at several CG residuals.

Validate's cup patches (``cup_torsion.local_patch_mesh``, Bueckner on the section's field: ``crack_local.local_release``)
on their three refinements, each solved by every configuration given ("direct", or "amg:RTOL"). Printed per
patch and configuration: dofs, CPU s of the release (assembly and solve, ``time.process_time``), CG
iterations and the released energy dU, whose difference from the direct solve is the CG residual's error.

    python benchmarks/cup_patch_solvers.py --depth 0.1 0.396 0.7 1.12 --solvers direct amg:1e-7 amg:1e-4 amg:1e-3
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}


def release_by(md, lame, field, config: str) -> dict:
    """dU, dofs, CPU s and CG iterations of one patch solved by ``config`` ("direct" or "amg:RTOL")."""
    import strainwave.fea.solver as solver
    from strainwave.fea import cup_torsion as ct
    from strainwave.fea.crack_local import local_release
    method, _, rtol = config.partition(":")
    seen, solve = {}, solver.solve_elasticity

    def counted(*args, **kwargs):           # the iterations of the patch's solve
        u, info = solve(*args, **kwargs)
        seen["iterations"] = info.iterations
        return u, info
    solver.solve_elasticity = counted
    try:
        c0 = time.process_time()
        local = local_release(md, lame, field, study=ct.STUDY, method=method, rtol=float(rtol) if rtol else None)
        cpu = time.process_time() - c0
    finally:
        solver.solve_elasticity = solve
    return {"dofs": local.dofs, "cpu_s": round(cpu, 2), "iterations": seen.get("iterations"),
            "released_Nmm": local.released_Nmm}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gear", choices=sorted(GEARS), default="default")
    ap.add_argument("--depth", type=float, nargs="+", default=[0.1], help="crack depths a, mm")
    ap.add_argument("--solvers", nargs="+", default=["direct", "amg:1e-7", "amg:1e-3"])
    args = ap.parse_args()
    from strainwave.api import load_params
    from strainwave.fea import cup_torsion as ct
    from strainwave.fea.assembly import Lame
    from strainwave.fea.cup_axisym import section_displacement, section_fine_mm, solve_cup_section
    from strainwave.fea.refinement import DEFAULT_RATIO, refinement_sizes
    from strainwave.fea.studies import with_crack
    base = load_params(GEARS[args.gear])
    for depth in args.depth:
        params = with_crack("cup-torsion", base, depth)
        part, mat = ct._build(params, depth, False), params.material
        lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)
        span_over_wall = 2 * ct.PATCH_HALF_OVER_A * depth / params.flexspline_cup.wall_thickness_mm
        sizes = refinement_sizes(section_fine_mm(params, False), DEFAULT_RATIO)
        for k in (2, 1, 0):
            field = section_displacement(solve_cup_section(params, sizes[k], keep_fields=True).fields["section"])
            md, _ = ct.local_patch_mesh(part, depth, DEFAULT_RATIO ** k)
            for config in args.solvers:
                print(json.dumps({"gear": args.gear, "depth_mm": depth, "span_over_wall": round(span_over_wall, 1),
                                  "refinement": k, "solver": config, **release_by(md, lame, field, config),
                                  "load": round(os.getloadavg()[0], 2)}), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
