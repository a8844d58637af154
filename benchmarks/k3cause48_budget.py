"""Decision 073 (k3cause48): the catalogue chain's compliance budget over the K3 window at size 25.

For each ratio: the K3-window compliance (phi(A) - phi(T2)) / (A - T2) of the full chain, and what each member
contributes (the member stiffened 1e6x, the difference), against what the CHA row needs. Run:
    .venv/bin/python benchmarks/k3cause48_budget.py
"""
from __future__ import annotations

import sys
import time
from dataclasses import replace

import numpy as np

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import _loop, mean_twist_rad

CATALOGUE_K3 = {30: 21e3, 50: 44e3, 100: 57e3}     # CHA-25 K3, N m/rad (../shared/data)
T2 = 48.0                                          # CHA-25 T2, N m


def window_compliance(design, series, rated):
    T, tw, _ = _loop(design, series, rated, 0.0)
    phi = mean_twist_rad(T, tw, np.array([T2, rated]))
    return 1e-3 * (phi[1] - phi[0]) / (rated - T2)          # rad/(N mm)


def budget(rules: MeshRules, ratio: float) -> dict:
    size = rules.cup_zone_reference_size
    d = rules.pitch_diameter_mm(size)
    design, rated = rules.design(size, ratio), rules.rated_torque_Nm(size)
    cup = rules.cup_flexibility_rad_per_Nmm(size)
    zone = rules.cup_zone_term(ratio).at(d)
    body = rules.cs_body_term(ratio).at(d, rules.E_MPa)
    series = cup + zone + body
    full = window_compliance(design, series, rated)
    out = {"full": full, "cup series": cup, "cup zone": zone, "CS body (face)": body}
    out["mesh + WG (no series)"] = window_compliance(design, 0.0, rated)
    stiff_kg = replace(design, K_G_N_per_mm=1e6 * design.K_G_N_per_mm)
    out["WG lobe K_G"] = full - window_compliance(stiff_kg, series, rated)
    stiff_b = replace(design, foundation_N_per_mm2=1e6 * design.foundation_N_per_mm2, bearing=None)
    out["balls (bed + Hertz remainder)"] = full - window_compliance(stiff_b, series, rated)
    out["catalogue"] = 1e-3 / CATALOGUE_K3[int(ratio)]
    out["miss"] = out["catalogue"] - full
    return out


def main(argv):
    rules = MeshRules()
    t0 = time.process_time()
    for ratio in (30.0, 50.0, 100.0):
        b = budget(rules, ratio)
        print(f"ratio {ratio:g}: " + "; ".join(f"{k} {v:.3e}" for k, v in b.items()))
    print(f"CPU {time.process_time() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
