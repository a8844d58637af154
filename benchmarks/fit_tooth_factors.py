"""Regenerate analytic/tooth_factors.FITTING_SET: toothed-ring FEA on the fitting rims, then the fit.

    .venv/bin/python benchmarks/fit_tooth_factors.py            # the fitting set (Z_R = 100), ~1 min
    .venv/bin/python benchmarks/fit_tooth_factors.py --held-out # rims the model was NOT fitted on
    .venv/bin/python benchmarks/fit_tooth_factors.py --extrapolate  # rims outside the fitted delta/m range

Each rim runs ``run_study("ring-compression", quick=True)`` (finest toothed mesh delta/1.5) and prints one
FitRow; the fitting set's constants are then printed next to the stored ones, and for --held-out the
model's error on each rim.
"""
from __future__ import annotations

import argparse
import warnings

from strainwave.analytic import tooth_factors as tf
from strainwave.fea.studies import run_study
from strainwave.params import load_params

FIT_RIMS = ((100, 0.75), (100, 1.1), (100, 1.5), (100, 2.0), (100, 3.0))
HELD_OUT_RIMS = ((72, 0.864), (72, 1.6), (72, 2.4), (72, 3.6), (64, 1.0), (80, 1.0))
# outside the fitted delta/m range (0.75 .. 3.0) on the fitting set's Z_R: analytic/tooth_factors.EXTRAPOLATION
EXTRAPOLATION_RIMS = ((100, 0.6), (100, 3.6))


def fea_row(teeth: int, delta_over_m: float, fillet: float = tf.MODEL_ROOT_FILLET_COEFFICIENT) -> tf.FitRow:
    p = load_params().with_value("ewg_drive.flexspline_teeth", teeth)
    p = p.with_value("ewg_drive.rim_thickness_ratio", delta_over_m / teeth)
    p = p.with_value("ewg_drive.root_fillet_coefficient", fillet)
    r = run_study("ring-compression", p, quick=True)
    e = p.ewg_drive
    return tf.FitRow(teeth, e.module_mm, delta_over_m, tf.tooth_height_mm(1.0, e.dedendum_coefficient),
                     r["toothed_force_for_W0_N"].value / r["force_for_W0_N"].value, r["tooth_influence"].value, r["root_stress_factor"].value)


def extrapolation_line(teeth: int, delta_over_m: float) -> None:
    """The model against the FEA at a rim outside the fitted range, with the FEA's GCI of each factor."""
    p = load_params().with_value("ewg_drive.flexspline_teeth", teeth)
    p = p.with_value("ewg_drive.rim_thickness_ratio", delta_over_m / teeth)
    r = run_study("ring-compression", p, quick=True)
    hd, md = tf.tooth_height_mm(1.0, p.ewg_drive.dedendum_coefficient) / delta_over_m, 1.0 / delta_over_m
    kd, ks = r["tooth_influence"], r["stress_concentration"]
    mkd, mks = tf.tooth_influence(hd, md, tf.FITTED), tf.stress_concentration(hd, md, tf.FITTED)
    print(f"Z_R {teeth} delta/m {delta_over_m}: K_delta FEA {kd.value:.4f} (GCI {100 * kd.convergence.gci_fine:.2g} %) "
          f"model {mkd:.4f} ({mkd / kd.value - 1:+.2%}); K_sigma FEA {ks.value:.4f} (GCI "
          f"{100 * ks.convergence.gci_fine:.2g} %) model {mks:.4f} ({mks / ks.value - 1:+.2%})", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--held-out", action="store_true")
    ap.add_argument("--extrapolate", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    if args.extrapolate:
        for z, d in EXTRAPOLATION_RIMS:
            extrapolation_line(z, d)
        return
    rows = [fea_row(z, d) for z, d in (HELD_OUT_RIMS if args.held_out else FIT_RIMS)]
    for r in rows:
        print(r)
    if args.held_out:
        for r in rows:
            hd, md = r.tooth_height_over_m / r.delta_over_m, 1.0 / r.delta_over_m
            kd, ks = tf.tooth_influence(hd, md, tf.FITTED), tf.stress_concentration(hd, md, tf.FITTED)
            print(f"Z_R {r.teeth} delta/m {r.delta_over_m}: K_delta FEA {r.tooth_influence:.4f} model {kd:.4f} "
                  f"({kd / r.tooth_influence - 1:+.2%}); K_sigma FEA {r.root_product / r.tooth_influence:.4f} "
                  f"model {ks:.4f} ({ks * r.tooth_influence / r.root_product - 1:+.2%})")
    else:
        print("fitted:", tf.fit_tooth_factors(rows), "stored:", tf.FITTED)


if __name__ == "__main__":
    main()
