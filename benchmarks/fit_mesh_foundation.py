"""The trial of decision 065 that was NOT adopted: a lumped rim support k = eta E b / d in series with the WG
bearing's Hertz balls, eta fitted on catalogue sizes 14-25 only (geometric mean of predicted/catalogue K3 = 1,
bisection in log eta), sizes 32-58 the confirmation; it prints eta's physical bounds (free ring .. ball bed) and
the ratio trend. Its K3 agreement is the reader's knee on the friction stick band (decision 065), which
tests/test_wg_bearing.py::test_the_readers_k3_is_the_curves_own_slope guards the rules against.
Run: .venv/bin/python benchmarks/fit_mesh_foundation.py
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from strainwave.analytic.catalogue import read_catalogue
from strainwave.analytic.catalogue_rules import MeshRules, RimRule, ratio_of_label
from strainwave.analytic.drive_curve import predict_curve

FIT_SIZES = (14, 17, 20, 25)


def k3_ratios(rules: MeshRules, rows) -> dict:
    out = {}
    for row in rows:
        dc = predict_curve(rules.design(row.size, ratio_of_label(row.ratio_label)),
                           rules.cup_flexibility_rad_per_Nmm(row.size), rules.rated_torque_Nm(row.size),
                           with_te=False)
        out[(row.size, row.ratio_label)] = dc.K3_Nm_per_rad / row.K3_Nm_per_rad
    return out


def main() -> None:
    rows = read_catalogue()
    fit = [r for r in rows if r.size in FIT_SIZES]
    blank = MeshRules(rim_rule=RimRule.BLANK)      # decision 065's drives (the blank rim 0.014 d)
    lo, hi = math.log(1e-4), math.log(1.0)
    for _ in range(12):
        mid = 0.5 * (lo + hi)
        q = k3_ratios(replace(blank, foundation_coefficient=math.exp(mid)), fit)
        lo, hi = (lo, mid) if np.mean(np.log(list(q.values()))) > 0 else (mid, hi)
    eta = math.exp(0.5 * (lo + hi))
    print("eta bounds (free ring n=2, Hertz ball bed) at size 25:",
          {i: tuple(f"{x:.3g}" for x in blank.foundation_bounds(25, i)) for i in (30, 50, 100)})
    q = k3_ratios(replace(blank, foundation_coefficient=eta), rows)
    held = [v for (s, _), v in q.items() if s not in FIT_SIZES]
    inside = sum(abs(v - 1.0) <= 0.25 for v in q.values())
    print(f"eta {eta:.4g}: held-out sizes 32-58 K3 geometric mean {math.exp(np.mean(np.log(held))):.3f}; "
          f"K3 within 25 % on {inside}/{len(q)} rows")
    for s in sorted({s for s, _ in q}):
        if (s, "30") in q:
            print(f"  size {s}: K3(>50)/K3(30) predicted over catalogue {q[(s, '>50')] / q[(s, '30')]:.2f}")


if __name__ == "__main__":
    main()
