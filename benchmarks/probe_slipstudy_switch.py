"""The tooth-mesh study on the true slip by the study's own route (decision 073-slipstudy48): its outputs with the
torque-only friction (fea/mesh_contact.py, shipped) and on the true slip (tooth_mesh.band_systems: the 2 x 2 band
flexibility by translation symmetry; fea/mesh_friction.torque_path, N torque increments per history step), on the
study's finest validate mesh, all WG angles; the contact solve's CPU beside each.

    python benchmarks/probe_slipstudy_switch.py [PARAMS.toml] [--increments 1 2 4] [--steps-per-leg S] [--json FILE]
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

KEYS = ("K1_Nmm_per_rad", "K2_Nmm_per_rad", "K3_Nmm_per_rad", "T1_Nmm", "T2_Nmm", "secant_stiffness_rated_Nmm_per_rad",
        "lost_motion_arcmin", "friction_loss_per_cycle_Nmm", "transmission_error_pp_rad", "teeth_in_contact_rated",
        "peak_tooth_share", "peak_tooth_load_N", "engagement_edge_rated_rad", "ratcheting_torque_Nmm")
RULE = ("K1_Nmm_per_rad", "K2_Nmm_per_rad", "K3_Nmm_per_rad", "T1_Nmm", "T2_Nmm", "lost_motion_arcmin",
        "friction_loss_per_cycle_Nmm", "transmission_error_pp_rad", "peak_tooth_share")


def readings(paths, mesh: dict) -> dict:
    from strainwave.fea import tooth_mesh as tm
    v = tm.loop_values(paths, mesh["rated_torque_Nmm"]) | tm.engagement_edge(paths[0], mesh["angles"][0])
    return v | tm.ratcheting(paths[0], mesh["angles"][0], mesh)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("params", nargs="?", default=None)
    ap.add_argument("--increments", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--json", default=None)
    ap.add_argument("--steps-per-leg", type=int, default=None, help="the history's steps a leg (default: the study's)")
    a = ap.parse_args(argv)
    from strainwave.analytic.mesh_engagement import study_loads
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import solve_torque_path
    from strainwave.fea.mesh_friction import torque_path
    from strainwave.params import load_params
    params = load_params(a.params)
    mesh = study_loads(params, quick=False)["mesh"]
    h = tm.refinements(params.flexspline_cup.module_mm, False)[0]
    infl, _ = tm.influences(params, mesh, h)
    history = np.asarray(mesh["torque_history_Nmm"])
    if a.steps_per_leg:
        from strainwave.fea.mesh_contact import torque_history
        history = torque_history(float(mesh["rated_torque_Nmm"]), a.steps_per_leg)
    c0 = time.process_time()
    shipped = [solve_torque_path(s, history) for s in tm.systems(infl, mesh)]
    c1 = time.process_time()
    out = {"gear": a.params or "default", "h_mm": h, "load": os.getloadavg(),
           "shipped": readings(shipped, mesh) | {"contact_cpu_s": c1 - c0}}
    bands = tm.band_systems(infl, mesh)
    out["band_systems_cpu_s"] = time.process_time() - c1
    for N in a.increments:
        t0 = time.process_time()
        paths = [torque_path(s, history, N)[0] for s in bands]
        out[f"N{N}"] = readings(paths, mesh) | {"contact_cpu_s": time.process_time() - t0}
    cols = ["shipped"] + [f"N{N}" for N in a.increments]
    print(f"# {out['gear']}  h = {h:.4g} mm  load {out['load'][0]:.2f}; "
          f"band systems {out['band_systems_cpu_s']:.2f} CPU-s")
    print("| output | " + " | ".join(cols) + " | last / shipped - 1 |")
    for k in KEYS + ("contact_cpu_s",):
        vals = [out[c][k] for c in cols]
        rel = vals[-1] / vals[0] - 1 if vals[0] else float("nan")
        print(f"| {k} | " + " | ".join(f"{v:.6g}" for v in vals) + f" | {100 * rel:+.2f} % |")
    for n1, n2 in zip(a.increments[:-1], a.increments[1:]):
        moves = {k: out[f"N{n2}"][k] / out[f"N{n1}"][k] - 1 for k in RULE}
        worst = max(moves, key=lambda k: abs(moves[k]))
        print(f"N {n1} -> {n2}: largest move {100 * moves[worst]:+.4f} % ({worst})")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1, default=float)
    return 0


if __name__ == "__main__":
    sys.exit(main())
