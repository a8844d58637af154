"""Fit the ONE coefficient of the tooth-mesh design rules (decision 065) on catalogue sizes 14-25 only.

eta (the wave-generator bearing's radial foundation modulus k = eta E b / d) is chosen on a log grid to make
the geometric mean of predicted/catalogue K3 over the fit rows 1; sizes 32-58 are then the confirmation.
Run: .venv/bin/python benchmarks/fit_mesh_foundation.py
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from strainwave.analytic.catalogue import read_catalogue
from strainwave.analytic.catalogue_rules import MeshRules, ratio_of_label
from strainwave.analytic.drive_curve import predict_curve

FIT_SIZES = (14, 17, 20, 25)
GRID = np.geomspace(0.001, 0.004, 7)      # 0.00252 chosen (decision 065)


def k3_log_ratios(rules: MeshRules, rows) -> np.ndarray:
    out = []
    for row in rows:
        dc = predict_curve(rules.design(row.size, ratio_of_label(row.ratio_label)),
                           rules.cup_flexibility_rad_per_Nmm(row.size), rules.rated_torque_Nm(row.size),
                           with_te=False)
        out.append(math.log(dc.K3_Nm_per_rad / row.K3_Nm_per_rad))
    return np.array(out)


def main() -> None:
    rows = read_catalogue()
    fit = [r for r in rows if r.size in FIT_SIZES]
    held = [r for r in rows if r.size not in FIT_SIZES]
    best = None
    for eta in GRID:
        lr = k3_log_ratios(replace(MeshRules(), foundation_coefficient=float(eta)), fit)
        print(f"eta {eta:.4g}: fit rows K3 geometric-mean ratio {math.exp(lr.mean()):.3f}, rms log {np.sqrt((lr ** 2).mean()):.3f}")
        if best is None or abs(lr.mean()) < abs(best[1]):
            best = (float(eta), lr.mean())
    eta = best[0]
    lr = k3_log_ratios(replace(MeshRules(), foundation_coefficient=eta), held)
    print(f"chosen eta {eta:.4g}; held-out sizes 32-58: K3 geometric-mean ratio {math.exp(lr.mean()):.3f}, "
          f"range {math.exp(lr.min()):.2f}..{math.exp(lr.max()):.2f}")


if __name__ == "__main__":
    main()
