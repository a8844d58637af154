"""Decision 069, item 3: the circular spline body's closed form (analytic/cs_ring.py, a thin inextensible ring)
against a plane-stress FE of the same annulus (fea/cs_body_fe.py: scikit-fem, P2 triangles on a polar grid, four meshes).

Loads, per unit output torque (T = 1 N mm): (a) tangential: two tangential patches on the bore at the major axes
(+-PATCH_DEG each, the mesh zone) reacted by a uniform tangential shear on the outer surface (the bolts); (b)
radial: two outward radial patches F_r = tan(alpha) / (2 r_p) each. Compliance by work (f . u / T^2: the loads are
self-equilibrated, so rigid motions do no work). Twist: (a) the work itself; (b) u tan(alpha) / r_p with u the
patches' mean radial opening. Run: .venv/bin/python benchmarks/cs_ring_fe_check.py [RATIO]  (size 25)
"""
from __future__ import annotations

import json
import math
import sys
import time

from strainwave.fea.cs_body_fe import cs_body_fe_twist_rad_per_Nmm as solve_case
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cs_ring import ring_mesh_twist_rad_per_Nmm


def main(ratio: float) -> None:
    rules = MeshRules()
    design = rules.design(25, ratio)
    g = design.geometry
    d = rules.pitch_diameter_mm(25)
    ri, ro = g.pitch_radius_mm + 1.25 * g.module_mm, 0.5 * 1.25 * d
    h = ro - ri
    closed = ring_mesh_twist_rad_per_Nmm(ri + 0.5 * h, design.E_MPa * g.face_width_mm * h ** 3 / 12.0,
                                         g.pitch_radius_mm, g.pressure_angle_deg)
    print(json.dumps({"ratio": ratio, "h_mm": h, "h_over_R": h / (ri + 0.5 * h), "closed_tangential": closed[0],
                      "closed_radial": closed[1]}))
    for nr, nt in ((2, 144), (4, 288), (8, 576), (16, 1152)):
        t0 = time.process_time()
        fe, ndof = solve_case(ri, ro, design.E_MPa, g.face_width_mm, g.pitch_radius_mm, g.pressure_angle_deg, nr, nt)
        print(json.dumps({"nr": nr, "nt": nt, "dofs": int(ndof), "fe_tangential": fe["tangential"],
                          "fe_radial": fe["radial"], "cpu_s": time.process_time() - t0}))


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 30.0)
