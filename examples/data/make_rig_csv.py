"""Writes examples/rig.csv, the sample recording the README's `diagnose` and `size-crack` lines read: a torsion
test of the output shaft, two load cycles of +/-1e6 N*mm, whose twist is 8 % more compliant than the uncracked
shaft's Saint-Venant flexibility (as a crack would make it), plus encoder noise of 2 urad.

    python examples/data/make_rig_csv.py [OUT.csv]
"""
import sys
from pathlib import Path

import numpy as np

import strainwave as sw
from strainwave.analytic.torsion import shaft_flexibility
from strainwave.analytic.variant import Variant

EXTRA_COMPLIANCE = 0.08   # the specimen's flexibility over the uncracked shaft's
NOISE_RAD = 2e-6


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[1] / "rig.csv")
    params = sw.load_params()
    shaft = params.output_shaft
    # the hollow shaft's Saint-Venant flexibility at the FEA's own shear modulus E/(2(1+nu))
    flexibility = shaft_flexibility(shaft.length_mm, shaft.outer_diameter_mm, shaft.inner_diameter_mm,
                                    params.material.implied_shear_modulus_MPa, Variant.CORRECTED)
    t = np.linspace(0.0, 2.0, 600)
    torque = 1e6 * np.sin(2 * np.pi * t)
    twist = (1 + EXTRA_COMPLIANCE) * flexibility * torque + np.random.default_rng(52).normal(0.0, NOISE_RAD, t.size)
    header = ('# [test]\n# kind = "torsion"\n# specimen = "output_shaft"\n'
              f'# description = "sample: output shaft, {100 * EXTRA_COMPLIANCE:g} % more compliant than uncracked '
              '(examples/data/make_rig_csv.py)"\n')
    rows = "\n".join(f"{T:.6g},{y:.6g},{s:.4f}" for T, y, s in zip(torque, twist, t))
    out.write_text(header + "torque_Nmm,twist_rad,time_s\n" + rows + "\n", encoding="utf-8")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
