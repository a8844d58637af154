"""The shipped gear's analytic drive chain against the solve's torque step, before and after decision 076.

Usage: python benchmarks/probe_chain_steps.py [PARAMS ...] [--steps 30,60,120] [--fea 20,40]

For each gear (default: the defaults and strainwave/data/second_gear.toml) and each base step a leg
(``drive_curve.LOOP_STEPS_PER_LEG``), prints the chain's readings read the old way (the solve's own steps) and on
the exact loop (decision 076), with the CPU-s of each chain and the load. ``--fea``: the same for
`diagnose --baseline fea`'s curve (the FE tooth-mesh study on its quick meshes, its torque history at each given
number of steps a leg; one study run per gear and step, ~13 CPU-s each).
"""
from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

from strainwave.analytic import drive_curve as dc
from strainwave.analytic.drive_chain import drive_chain
from strainwave.params import load_params

SECOND = Path(__file__).resolve().parents[1] / "strainwave" / "data" / "second_gear.toml"


def readings(params, exact: bool) -> dict:
    c = drive_chain(params, exact=exact)
    v = c.curve
    return {"K1": v.K1_Nm_per_rad, "K2": v.K2_Nm_per_rad, "K3": v.K3_Nm_per_rad, "T1": v.T1_Nm, "T2": v.T2_Nm,
            "LM_rad": v.lost_motion_rad, "K_HD": 1e-3 * c.K_HD_Nmm_per_rad, "mesh_low": 1.0 / c.mesh_low_torque * 1e-3,
            "mesh_work": 1.0 / c.mesh_working * 1e-3}


def fea_readings(params, steps_per_leg: int) -> tuple[dict, dict, float]:
    """(old reading, exact reading, CPU-s of the study) of diagnose's FE drive curve at a study torque step."""
    from strainwave.compare.diagnose.drive_baseline import fea_drive_curve
    from strainwave.fea import mesh_contact
    from strainwave.fea.studies import run_study
    base = mesh_contact.torque_history
    mesh_contact.torque_history = lambda A, n=steps_per_leg: base(A, n)
    try:
        t0 = time.process_time()
        result = run_study("tooth-mesh", params, quick=True)
        cpu = time.process_time() - t0
    finally:
        mesh_contact.torque_history = base
    out = []
    for exact in (False, True):
        c, unc = fea_drive_curve(params, exact=exact, result=result)
        out.append({"K1": c.K1_Nm_per_rad, "K2": c.K2_Nm_per_rad, "K3": c.K3_Nm_per_rad, "T1": c.T1_Nm,
                    "T2": c.T2_Nm, "LM_rad": c.lost_motion_rad, "unc": unc})
    return out[0], out[1], cpu


def report(title: str, rows: list) -> None:
    print(f"## {title}; load {os.getloadavg()[0]:.1f}")
    for n, r, cpu in rows:
        print(f"{n:4d} " + " ".join(f"{k} {v:.5g}" for k, v in r.items()) + f"  CPU {cpu:.2f} s")
    first = rows[0][1]
    print("  largest relative change over the steps: " + " ".join(
        f"{k} {max(abs(r[k] / first[k] - 1) for _, r, _ in rows):.2e}" for k in first if first[k]))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("params", nargs="*")
    ap.add_argument("--steps", default="30,60,120")
    ap.add_argument("--fea", default="", help="the FE study's steps a leg, e.g. 20,40 (its default is 40)")
    a = ap.parse_args()
    gears = a.params or [None, str(SECOND)]
    base = dc.LOOP_STEPS_PER_LEG
    for g in gears:
        params = load_params(g) if g else load_params()
        for exact in (False, True):
            rows = []
            for n in (int(s) for s in a.steps.split(",")):
                dc.LOOP_STEPS_PER_LEG = n
                t0 = time.process_time()
                r = readings(params, exact)
                rows.append((n, r, time.process_time() - t0))
            dc.LOOP_STEPS_PER_LEG = base
            report(f"{g or 'defaults'}, chain, {'exact loop (after)' if exact else 'solve steps (before)'}", rows)
        if a.fea:
            runs = [(int(n), *fea_readings(params, int(n))) for n in a.fea.split(",")]
            report(f"{g or 'defaults'}, diagnose --baseline fea, study steps (before)", [(n, o, c) for n, o, _, c in runs])
            report(f"{g or 'defaults'}, diagnose --baseline fea, exact loop (after)", [(n, e, c) for n, _, e, c in runs])


if __name__ == "__main__":
    main()
