"""Hertz at the flank (mesh.flank_hertz, mesh.flank_hertz_width): CPU seconds per gear (parent + gmsh children)
of the checks and of the rated record against the few-CPU-s goal, and on the default gear a mesh finer than
validate's finest (b/24 against b/17) beside the closed form: the FE settles on Hertz, not beside it.

    python benchmarks/bench_flank_hertz.py
"""
from __future__ import annotations

import sys
import resource
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from shipped_gears import shipped_params  # noqa: E402

RATED_FLANK_LOAD_N = {"default": 2467.0, "second": 973.0}   # the tooth-mesh study's largest flank load at rated
GOAL_CPU_S = 6.0                                             # checks + rated record, per gear


def _cpu() -> float:
    return sum(getattr(resource.getrusage(w), k) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
               for k in ("ru_utime", "ru_stime"))


def main() -> int:
    from strainwave.compare.validate import flank_hertz_checks as fhc
    from strainwave.fea.flank_hertz import solve_contact
    from strainwave.geometry.mesh_geometry import mesh_geometry

    for gear, p in shipped_params():
        t0 = _cpu()
        checks = fhc.hertz_checks(p)
        t1 = _cpu()
        rated = fhc.rated_record(p, RATED_FLANK_LOAD_N[gear] / mesh_geometry(p).face_width_mm)["rated"]
        t2 = _cpu()
        for c in checks:
            print(f"{gear} {c.id}: FE {c.fea:.6g} {c.unit}, Hertz {c.analytic['corrected']:.6g}, error "
                  f"{100 * c.rel_error['corrected']:+.3f} %, tolerance {100 * c.tolerance.relative:.3g} %: "
                  f"{'pass' if c.passed else 'FAIL'}")
        print(f"  rated: {rated['statement']}")
        cpu = t2 - t0
        print(f"  CPU: checks {t1 - t0:.1f} s, rated record {t2 - t1:.1f} s; total {cpu:.1f} s, goal <= {GOAL_CPU_S:g} s: "
              f"{'PASS' if cpu <= GOAL_CPU_S else 'MISS'}")
        if gear == "default":
            pair, h, _, _ = fhc.closed_form(p)
            b = h.half_width_mm
            for n in (24.0,):
                s = solve_contact(pair, fhc._lame(p), h.load_N_per_mm, fhc.ZONE_OVER_B * b, b / n,
                                  fhc.FAR_OVER_M * pair.module_mm, fhc.GRADE)
                print(f"  b/{n:g} ({s.dofs} dofs): p0 {100 * (s.peak_pressure_MPa / h.peak_pressure_MPa - 1):+.3f} %, "
                      f"b {100 * (s.half_width_mm / b - 1):+.3f} % from Hertz")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
