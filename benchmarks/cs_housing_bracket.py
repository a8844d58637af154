"""Decision 070 (cshousing48): the circular spline body with its bolted face, measured in 3D
(fea/cs_housing_fe.py) and put in the catalogue chain under each restraint of the bracket.

Run: .venv/bin/python benchmarks/cs_housing_bracket.py [terms|bolts|scaling|table RESTRAINT]
- terms: the body's twist at size 25, i = 30 / 50 / 100, free / face / a band of the face / bolt footprints
- bolts: 4, 8, 16 bolt footprints (radius 0.25 h, mid-body) at i = 30, three lattices
- housing: the face bonded to a housing flange (the same annulus, 0.5 / 1 / 2 b thick, steel or aluminium),
  clamped at its far face, at i = 30
- scaling: the same body at size 25 and 50 (similitude: x 1/8) and E halved (x 2)
- table RESTRAINT: `strainwave catalogue` on the CHA table with the body clamped ("face"), free ("free") or left
  out ("none")
"""
from __future__ import annotations

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cs_housing import body_case_of_design
from strainwave.fea.cs_housing_fe import Restraint, cs_housing_twist_rad_per_Nmm

TABLE = Path("/work/shared/data/cha_torsional_stiffness.csv")
RULES = MeshRules()


def case(size, ratio, restraint="face", **kw):
    d = RULES.pitch_diameter_mm(size)
    return replace(body_case_of_design(RULES.design(size, ratio), RULES.cs_outer_over_d * d, restraint), **kw)


def run(c, levels):
    out = []
    for k in levels:
        t0 = time.process_time()
        r, n = cs_housing_twist_rad_per_Nmm(c, k)
        out.append({"k": k, "dofs": int(n), "tangential": r["tangential"], "radial": r["radial"],
                    "total": r["tangential"] + r["radial"], "cpu_s": time.process_time() - t0})
        print(json.dumps({"restraint": c.restraint.value, "clamp_r": c.clamp_r, "n_bolts": c.n_bolts, **out[-1]}),
              flush=True)
    return out


def main(what):
    if what == "terms":
        for ratio in (30, 50, 100):
            for kw in ({"restraint": Restraint.FREE}, {}, {"clamp_r": (0.25, 0.75)}, {"clamp_r": (0.75, 1.0)},
                       {"restraint": Restraint.BOLTS, "n_bolts": 16}):
                print("ratio", ratio, end=" ")
                run(case(25, ratio, **kw), (3,))
    elif what == "bolts":
        for n in (4, 8, 16):
            run(case(25, 30, restraint=Restraint.BOLTS, n_bolts=n), (1, 2, 3))
    elif what == "housing":
        b = case(25, 30).b_mm
        for t in (0.5, 1.0, 2.0):
            for E in (2.1e5, 7.0e4):
                run(case(25, 30, restraint=Restraint.HOUSING, housing_mm=t * b, housing_E_MPa=E), (1, 2, 3))
    elif what == "scaling":
        a, b = run(case(25, 50), (2,))[0]["total"], run(case(50, 50), (2,))[0]["total"]
        c = run(case(25, 50, E_MPa=1.05e5), (2,))[0]["total"]
        print(f"size 50 / size 25: {b / a:.5f} (similitude 0.125); E halved: {c / a:.5f} (2)")
    elif what == "table":
        from strainwave.analytic.catalogue_predict import predict_table
        r = sys.argv[2]
        p = predict_table(TABLE, replace(RULES, cs_body_restraint=None if r == "none" else r))
        print(p.summary())


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "terms")
