"""The flexspline's buckling check (cup.buckling_torque): its CPU seconds per gear against the 15 CPU-s goal, and the
FE's convergence on a fourth, finer mesh than validate's (80 elements around) on the default gear: the three
validate meshes' GCI against the distance of the finer value from the closed form.

    python benchmarks/bench_buckling.py
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from shipped_gears import shipped_params  # noqa: E402

GOAL_CPU_S = 15.0


def main() -> int:
    from strainwave.compare.validate import buckling_checks as bc
    from strainwave.fea.assembly import Lame
    from strainwave.fea.cup_buckling import buckling_torque

    for gear, p in shipped_params():
        t0 = time.process_time()
        check = bc.buckling_check(p)
        cpu = time.process_time() - t0
        print(f"{gear}: FE {check.fea:.6g} N mm +- {check.fea_uncertainty:.3g}, closed form "
              f"{check.analytic['corrected']:.6g}, error {100 * check.rel_error['corrected']:+.3f} %, tolerance "
              f"{100 * check.tolerance.relative:.3g} %: {'pass' if check.passed else 'FAIL'}")
        print(f"cup.buckling_torque CPU {cpu:.1f} s on the {gear} gear, goal <= {GOAL_CPU_S:g} s: "
              f"{'PASS' if cpu <= GOAL_CPU_S else 'MISS'}")
        if gear == "default":
            m = p.material
            from strainwave.fea.wg_band import tube_geometry
            fine = buckling_torque(tube_geometry(p), Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio), 80)
            ref = check.analytic["corrected"]
            print(f"  80 around ({fine.dofs} dofs, {fine.n_waves} waves): {fine.torque_Nmm:.6g} N mm, "
                  f"{100 * (fine.torque_Nmm / ref - 1):+.3f} % from the closed form; validate's finest "
                  f"{100 * (check.fea / ref - 1):+.3f} % with GCI {100 * check.fea_uncertainty / check.fea:.3g} %")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
