"""A torsion recording diagnosed: a shaft test with backlash (lost motion) is written as a self-describing CSV
(docs/recordings.md), then diagnosed against the analytic baseline; the verdict names the effect.

    python examples/diagnose_recording.py [OUT_DIR]
"""
import sys
from pathlib import Path

import numpy as np

import strainwave as sw
from strainwave.analytic.torsion import shaft_flexibility
from strainwave.analytic.variant import Variant


def write_recording(path: Path) -> Path:
    """Two load cycles of +/-1e6 N*mm on the output shaft, its linear twist plus a keyed coupling's clearance of
    2e-4 rad (its flanks' Hertzian contact takes it up as torque^(2/3) within 3 % of the peak torque), noise."""
    params = sw.load_params()
    shaft = params.output_shaft
    # the hollow shaft's Saint-Venant flexibility at the FEA's own shear modulus E/(2(1+nu))
    compliance = shaft_flexibility(shaft.length_mm, shaft.outer_diameter_mm, shaft.inner_diameter_mm,
                                  params.material.implied_shear_modulus_MPa, Variant.CORRECTED)
    t = np.linspace(0.0, 2.0, 800)
    torque = 1e6 * np.sin(2 * np.pi * t)
    take_up = np.minimum(np.abs(torque) / 3e4, 1.0) ** (2.0 / 3.0)
    twist = compliance * torque + 1e-4 * np.sign(torque) * take_up + np.random.default_rng(1).normal(0.0, 2e-6, t.size)
    header = '# [test]\n# kind = "torsion"\n# specimen = "output_shaft"\n# description = "example: backlash"\n'
    rows = "\n".join(f"{T:.6g},{y:.6g},{s:.4f}" for T, y, s in zip(torque, twist, t))
    path.write_text(header + "torque_Nmm,twist_rad,time_s\n" + rows + "\n", encoding="utf-8")
    return path


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)
    recording = write_recording(out / "shaft_backlash.csv")
    diagnosis = sw.diagnose(recording)
    print(diagnosis.summary())
    # the example's claim, checked: a clearance is a lost motion, and the recording says so
    if diagnosis.verdict.value != "explained" or diagnosis.named != ("lost_motion",):
        raise SystemExit(f"expected 'explained (lost_motion)', got {diagnosis.verdict.value} {diagnosis.named}")


if __name__ == "__main__":
    main()
