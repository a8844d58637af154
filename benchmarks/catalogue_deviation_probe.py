"""Decision 070 (engage48): the CHA table against the ISO 1328-1 class of the teeth's manufacturing deviations.

For each class, each row is predicted as `strainwave catalogue` does with `MeshRules(accuracy_grade=A,
deviation_units=N)` (the mean loop of N units, seeds 0..N-1, read by the catalogue's convention), and beside it the
spread over the units (each unit's own curve read alone). The cup's twist under the mesh zones (FE) is computed once
and shared by every class. Ideal teeth: class 'none'.

Run: .venv/bin/python benchmarks/catalogue_deviation_probe.py [CLASSES] [UNITS] [--rows] [--amplitude-over-T2=F]
     CLASSES comma-separated (default none,3,5,7), UNITS default 8; --rows prints every row; --amplitude-over-T2=F
     cycles each row to F x its catalogue T2 instead of the rules' rated torque (the knees move with it);
     --cs-ring=F adds the circular spline body's free-ring twist x F in series (decision 069's probe term).
"""
from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from strainwave.analytic.catalogue_predict import _with_secants, read_table
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import predict_curve, predict_mean_curve

TABLE = Path("/work/shared/data/cha_torsional_stiffness.csv")
NAMES = ("K1_Nm_per_rad", "K2_Nm_per_rad", "K3_Nm_per_rad", "T1_Nm", "T2_Nm")
GOALS = (0.35, None, 0.25, 0.35, 0.35)


def _ratios(row, curve) -> np.ndarray:
    rp = _with_secants(row, curve)
    return np.array([rp.ratio_of(n) for n in NAMES])


def row_result(rules: MeshRules, row, series: float, amplitude: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(predicted/catalogue of the mean curve, of every unit alone (units x 5)); ``amplitude``: x the row's T2."""
    rated = rules.rated_torque_Nm(row.size) if amplitude is None else amplitude * row.values["T2_Nm"]
    if rules.accuracy_grade is None:
        q = _ratios(row, predict_curve(rules.design(row.size, row.ratio), series, rated, with_te=False))
        return q, q[None, :]
    designs = [rules.design(row.size, row.ratio, u) for u in range(rules.deviation_units)]
    per = np.array([_ratios(row, predict_mean_curve([d], series, rated)) for d in designs])
    return _ratios(row, predict_mean_curve(designs, series, rated)), per


def summary(grade, Q: np.ndarray, P: list, cpu: float) -> str:
    parts = [f"class {grade}:"]
    for j, (name, tol) in enumerate(zip(NAMES, GOALS)):
        tag = name.split("_")[0]
        count = "" if tol is None else f" {int(np.sum(np.abs(Q[:, j] - 1.0) <= tol))}/{len(Q)}"
        parts.append(f"{tag}{count} [{Q[:, j].min():.2f}-{Q[:, j].max():.2f}]")
    shape = Q[:, 0] / Q[:, 2]
    spread = np.mean([p.std(axis=0) for p in P], axis=0)
    parts.append(f"(K1/K3)/cat [{shape.min():.2f}-{shape.max():.2f}] geo-mean {np.exp(np.mean(np.abs(np.log(shape)))):.2f};"
                 f" unit-to-unit sd K1 {spread[0]:.2f} T1 {spread[3]:.2f} T2 {spread[4]:.2f}; {cpu:.1f} CPU-s")
    return " ".join(parts)


def main(grades, units: int, show_rows: bool, amplitude: float | None = None, cs_ring: float = 0.0) -> None:
    rows = read_table(TABLE.read_text())
    base = MeshRules(deviation_units=units)
    t0 = time.process_time()
    zone = {r: base.cup_zone_term(r) for r in sorted({row.ratio for row in rows})}
    print(f"cup-zone FE {time.process_time() - t0:.1f} CPU-s")
    for grade in grades:
        rules = replace(base, accuracy_grade=grade)
        t0 = time.process_time()
        Q, P = [], []
        for row in rows:
            d = rules.pitch_diameter_mm(row.size)
            series = rules.cup_flexibility_rad_per_Nmm(row.size) + zone[row.ratio].at(d)
            if cs_ring:
                from strainwave.analytic.cs_ring import cs_body_twist_rad_per_Nmm
                series += cs_ring * cs_body_twist_rad_per_Nmm(rules.design(row.size, row.ratio), 1.25 * d)
            q, per = row_result(rules, row, series, amplitude)
            Q.append(q)
            P.append(per)
            if show_rows:
                sd = per.std(axis=0)
                print(f"  {row.size:4g} {row.ratio_label:>4} " + " ".join(f"{x:5.2f}" for x in q)
                      + "   units sd " + " ".join(f"{x:4.2f}" for x in sd), flush=True)
        print(summary(grade, np.array(Q), P, time.process_time() - t0), flush=True)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    classes = [None if g == "none" else float(g) for g in (args[0] if args else "none,3,5,7").split(",")]
    amp = [float(a.split("=", 1)[1]) for a in sys.argv[1:] if a.startswith("--amplitude-over-T2=")]
    ring = [float(a.split("=", 1)[1]) for a in sys.argv[1:] if a.startswith("--cs-ring=")]
    main(classes, int(args[1]) if len(args) > 1 else 8, "--rows" in sys.argv, amp[0] if amp else None,
         ring[0] if ring else 0.0)
