"""The cup junction calibration: the smooth cup's exact (r, z) section FEA against the series shell model.

For each cup (d1, delta, L) the section's lambda_f on three meshes (GCI) and the series model
(``analytic.seed000.cup_series_model``, G = E/2(1+nu)) are printed with their difference, the junction
compliance. In units of 1/(G d1^3) it depends on delta/d1 alone (``analytic/cup_junction.py``): the FIT cups
give its straight line and scatter; the HELD-OUT cups test it: PASS when the residual is within the scatter
plus 3 GCI. The printed FIT_CUPS table is ``analytic/cup_junction.py``'s.

    python benchmarks/cup_calibration.py
"""
from __future__ import annotations

import os
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

# (d1, delta, L) mm, cylindrical cups; fit: delta/d1 0.010-0.020 x L/d1 0.8-1.3 at d1 = 120 mm
FIT = ((120.0, 1.2, 96.0), (120.0, 1.2, 156.0), (120.0, 1.8, 120.0), (120.0, 2.4, 96.0), (120.0, 2.4, 156.0))
# held out: the shipped gears, the former fit cups and proportions between and beside the fit grid
HELD_OUT = ((160.0, 2.24, 160.0), (100.0, 1.4, 100.0), (120.0, 1.8, 110.0), (200.0, 3.0, 240.0),
            (80.0, 1.0, 100.0), (140.0, 2.6, 125.0))


def ratio(d1: float, delta: float, length: float) -> tuple[float, float, float, float]:
    """(FEA, its GCI, series model, FEA / model - 1) of one cup."""
    from strainwave.analytic.seed000 import cup_series_model
    from strainwave.fea.cup_axisym import section_flexibility
    from strainwave.params import load_params
    params = load_params(None, {"flexspline_cup": {"pitch_diameter_mm": d1, "wall_thickness_mm": delta,
                                                   "length_mm": length, "shape": "cylindrical", "cup": True,
                                                   "teeth": 200, "module_mm": d1 / 200}})
    q = section_flexibility(params)
    model = cup_series_model(params, params.material.implied_shear_modulus_MPa).total
    return q.value, q.uncertainty, model, q.value / model - 1.0


def label(cup) -> str:
    return f"d1 {cup[0]:g} / delta {cup[1]:g} / L {cup[2]:g} mm"


def main() -> int:
    import warnings
    warnings.simplefilter("ignore")
    from strainwave.analytic.cup_junction import FIT_G_MPa, junction_fit
    t0 = time.perf_counter()
    fit_runs = {c: ratio(*c) for c in FIT}
    fit = junction_fit({c: (v[0], v[2]) for c, v in fit_runs.items()})
    print("fit cups: FEA (section), GCI, series model, FEA/model - 1, G d1^3 (FEA - model)")
    for c, (fea, gci, model, r) in fit_runs.items():
        print(f"  {label(c):32s} {fea:.6e} {100 * gci / fea:7.4f} % {model:.6e} {100 * r:+7.3f} % "
              f"{(fea - model) * FIT_G_MPa * c[0] ** 3:8.4f}")
    print(f"junction: G d1^3 Delta lambda = {fit.intercept:.4f} + ({fit.slope:.2f}) delta/d1 on delta/d1 "
          f"{fit.wall_ratio_range[0]:.3g}..{fit.wall_ratio_range[1]:.3g}; scatter {100 * fit.scatter:.3f} % of lambda_f")
    ok = True
    print("held out: residual = FEA / (model + junction) - 1, allowed = scatter + 3 GCI")
    for cup in HELD_OUT:
        fea, gci, model, _ = ratio(*cup)
        junction = fit.dimensionless(cup[1] / cup[0]) / (FIT_G_MPa * cup[0] ** 3)
        residual = fea / (model + junction) - 1.0
        allowed = fit.scatter + 3 * gci / fea
        verdict = "PASS" if abs(residual) <= allowed else "MISS"
        ok &= verdict == "PASS"
        print(f"  {label(cup):32s} delta/d1 {cup[1] / cup[0]:.4f} {fea:.6e} residual {100 * residual:+7.4f} % "
              f"allowed {100 * allowed:.4f} % {verdict}")
    print("FIT_CUPS = {" + ", ".join(f"{c}: ({v[0]:.6e}, {v[2]:.6e})" for c, v in fit_runs.items()) + "}")
    print(f"({time.perf_counter() - t0:.0f} s; load {os.getloadavg()[0]:.1f})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
