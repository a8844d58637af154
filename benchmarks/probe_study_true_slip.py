"""What the tooth-mesh STUDY's outputs become with friction on the true slip (decision 072-slip48).

The study (fea/tooth_mesh.py) solves each WG angle with fea/mesh_contact.py: friction as a torque mu |slide| F
along the rigid kinematic slide, no tangential load on the teeth. Here the same study's systems get their
tangential band loads and Coulomb's law on the true relative slip (fea/mesh_friction.py), on the study's finest
validate mesh, and every loop output is printed before (shipped) and after (true slip).

The flexibility of the true-slip system, per WG angle, 2n x 2n [[Cff, Cfg], [Cgf, Cgg]]:
- Cff: the study's own pair compliance (fs rim + CS teeth, tooth_mesh.pair_compliance), unchanged;
- the FS rim's Cfg / Cgg: direct FE on the study's whole rim (the pairs' bands f and their turned twins g, each
  balanced by the bore's shear, as tooth_mesh_fe.influence balances its loads), C = B^T K^-1 B;
- the CS teeth's Cfg / Cgg: each pair's own CS tooth (the study's sector, tooth 0, at the pair's CS radius, the
  flank the FS flank presses), its 2x2 self block; CS coupling of tangential loads between teeth is left out.
- the pairs: those the shipped path loads anywhere or brings within KEEP_GAP of closing (cost: each kept pair's
  bands go through the rim's factor); the left-out pairs' gaps are checked along the true-slip path and printed;
- w (the counter-tooth's slide along the FS flank's tangent t = rot90(n) per unit twist) = P . n = +R sin(alpha):
  the study's ``slide_mm_per_rad`` with its sign (both flanks: the FS flank's outward normal leans outward).

    python benchmarks/probe_study_true_slip.py [PARAMS.toml] [--increments N ...] [--angles K] [--steps-per-leg S]

Since decision 073-slipstudy48 the study itself solves the true slip (its blocks by translation symmetry, within
1 % of this probe's direct FE); this probe stays as decision 072's record.

Cost: ~85-220 CPU-s per gear (the tangential blocks by direct FE); decision 072-slip48 has its tables.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np


def _balanced(rim, F: np.ndarray, r_bore_mm: float) -> np.ndarray:
    """Loads balanced in moment by the bore's uniform shear (so B^T u is free of the rim's rigid rotation)."""
    from strainwave.fea import tooth_mesh_fe as fe
    x, y = rim.basis.doflocs
    full = rim.T @ F                                   # u~ -> full dofs for the moment
    M = (x[:, None] * full[1::2] - y[:, None] * full[0::2]).sum(0)
    return F - fe.bore_shear(rim, r_bore_mm)[:, None] * M[None, :]


def band_system(mesh: dict, infl: dict, pairs: dict, rim, sector, keep: np.ndarray):
    """The study's system at one WG angle with the tangential blocks, on the pairs ``keep`` (those the shipped path
    loads, and those it nearly closes): a mesh_friction.BandSystem, and the FS rim's Cfg of EVERY pair on the kept
    pairs' tangential loads (the left-out pairs' gaps are checked with it afterwards)."""
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea import tooth_mesh_fe as fe
    from strainwave.fea.mesh_friction import BandSystem
    band = tm.BAND_OVER_M * mesh["module_mm"]
    sub = {k: np.asarray(v)[keep] for k, v in pairs.items()}
    n = keep.size
    Cff = tm.pair_compliance(infl, sub, mesh["z_f"], mesh["z_c"])
    # FS rim: direct, on the study's rim (flank_loads returns u~ columns)
    F_all = _balanced(rim, _fs_bands(rim, pairs, band)[0], infl["r_bore_mm"])
    G = _balanced(rim, _turn(rim, _fs_bands(rim, sub, band)[0]), infl["r_bore_mm"])
    B = np.column_stack([F_all[:, keep], G])
    U = fe.displacements(rim, B)
    flex_fs = B.T @ U
    flex_fs = 0.5 * (flex_fs + flex_fs.T)
    cross = F_all.T @ U[:, n:]                         # (n_all, n): Cfg of every pair on the kept pairs' Q
    fs_only = tm.pair_compliance(infl | {"cs": np.zeros_like(infl["cs"])}, sub, mesh["z_f"], mesh["z_c"])
    d = np.diag(flex_fs[:n, :n]) / np.diag(fs_only) - 1
    print(f"  {n} of {len(pairs['clearance_mm'])} pairs kept; FS normal compliance, direct FE over the study's "
          f"interpolated influence - 1: {100 * d.min():+.2f} .. {100 * d.max():+.2f} %", flush=True)
    flex = np.zeros((2 * n, 2 * n))
    flex[:n, :n] = Cff
    flex[:n, n:], flex[n:, :n], flex[n:, n:] = flex_fs[:n, n:], flex_fs[n:, :n], flex_fs[n:, n:]
    # CS: each pair's own tooth, the flank the FS flank presses (-side), self 2x2 blocks
    for i in range(n):
        Fc, Gc = _cs_bands(sector, float(sub["cs_radius_mm"][i]), band, -int(sub["side"][i]))
        c2 = fe.compliance(sector, np.column_stack([Fc, Gc]))
        flex[i, n + i] += c2[0, 1]
        flex[n + i, i] += c2[1, 0]
        flex[n + i, n + i] += c2[1, 1]
    flex = 0.5 * (flex + flex.T)
    return BandSystem(sub["clearance_mm"].astype(float), flex, sub["lever_mm"].astype(float),
                      sub["slide_mm_per_rad"].astype(float), float(mesh["friction_coefficient"])), cross


def kept_pairs(shipped, system) -> np.ndarray:
    """The pairs the shipped path loads anywhere, and those whose gap on it comes within KEEP_GAP of closing."""
    gaps = shipped.gaps_mm(system)
    near = gaps.min(axis=0) <= KEEP_GAP * float(np.max(system.clearance_mm))
    return np.flatnonzero(shipped.contact.any(axis=0) | near)


def left_out_min_gap(path, Q: np.ndarray, pairs: dict, infl: dict, mesh: dict, keep: np.ndarray, cross) -> float:
    """The smallest gap of a left-out pair along the true-slip path (< 0 would mean the restriction is wrong)."""
    from strainwave.fea import tooth_mesh as tm
    out = np.setdiff1d(np.arange(len(pairs["clearance_mm"])), keep)
    if out.size == 0:
        return float("inf")
    C = tm.pair_compliance(infl, pairs, mesh["z_f"], mesh["z_c"])
    g = (np.asarray(pairs["clearance_mm"])[out][None, :] - path.twist_rad[:, None] * np.asarray(pairs["lever_mm"])[out]
         + path.forces_N @ C[np.ix_(out, keep)].T + Q @ cross[out].T)
    return float(g.min())


def _fs_bands(rim, pairs: dict, band: float) -> tuple[np.ndarray, np.ndarray]:
    from strainwave.fea import tooth_mesh_fe as fe
    n = len(pairs["clearance_mm"])
    F = np.zeros((rim.T.shape[1], n))
    for s in (1, -1):
        on = np.flatnonzero(pairs["side"] == s)
        if on.size:
            F[:, on] = fe.flank_loads(rim, pairs["tooth"][on], pairs["fs_radius_mm"][on], band, s)[0]
    return F, _turn(rim, F)


def _cs_bands(sector, r_mm: float, band: float, side: int) -> tuple[np.ndarray, np.ndarray]:
    from strainwave.fea import tooth_mesh_fe as fe
    F = fe.flank_loads(sector, np.array([0]), np.array([r_mm]), band, side)[0]
    return F, _turn(sector, F)


def _turn(model, F: np.ndarray) -> np.ndarray:
    """The bands as tangential tractions along t = rot90(n), n the flank's outward normal (-resultant of F)."""
    from strainwave.fea.mesh_friction import turned_bands
    Tm = model.T
    full = Tm @ F          # T is orthogonal (a rotation at each bore node, else the identity): u~ loads -> full
    res = np.stack([full[0::2].sum(0), full[1::2].sum(0)], axis=1)
    n = -res / np.hypot(res[:, 0], res[:, 1])[:, None]
    t = np.column_stack([-n[:, 1], n[:, 0]])
    return Tm.T @ turned_bands(full, t)


KEEP_GAP = 0.1           # of the largest clearance: a pair the shipped path brings this close is kept
ZERO_AIM = 1e-9          # of the amplitude: how far past a zero torque a leg aims (the dead band's far edge)


def true_slip_path(system, history_Nmm: np.ndarray, increments: int):
    """The study's torque history on the true-slip system: each history step a leg of ``increments`` increments
    ending at its torque (false position), as a mesh_contact.MeshPath (work: trapezoids between the legs' ends)."""
    from strainwave.fea.mesh_contact import MeshPath
    from strainwave.fea.mesh_friction import twists_for_torques
    T = np.asarray(history_Nmm, float)
    # a zero torque inside the loop lies in the backlash's dead band (any twist there carries it): the study's tracker
    # crosses the band to its far edge (where the other flanks touch). Both edges are solved (a hair either side of
    # zero) so that the trapezoids see the band's zero torque; the far edge is the history's point
    eps = ZERO_AIM * float(np.max(np.abs(T)))
    targets, keep = [], []
    for k in range(1, T.size):
        if T[k] == 0.0:
            targets.append(np.sign(T[k - 1]) * eps)
            T_k = -np.sign(T[k - 1]) * eps
        else:
            T_k = T[k]
        targets.append(T_k)
        keep.append(len(targets))              # index in [0] + records
    recs = twists_for_torques(system, targets, increments)            # T[0] = 0: the unloaded start
    theta = np.concatenate([[0.0], [r["twist_rad"] for r in recs]])
    Tr = np.concatenate([[0.0], [r["torque_Nmm"] for r in recs]])
    work_all = np.concatenate([[0.0], 0.5 * (Tr[1:] + Tr[:-1]) * np.diff(theta)])
    idx = np.array([0] + keep)
    work = np.array([work_all[i0 + 1:i1 + 1].sum() for i0, i1 in zip(idx[:-1], idx[1:])])
    F = np.vstack([np.zeros(len(system.clearance_mm))] + [recs[i - 1]["forces_N"] for i in keep])
    Q = np.vstack([np.zeros(len(system.clearance_mm))] + [recs[i - 1]["tangential_N"] for i in keep])
    return MeshPath(T, theta[idx], F, F > 0.0, np.zeros(T.size, int), np.concatenate([[0.0], work])), Q


def _sector(params, h_mm: float):
    """The study's CS sector on this mesh size (tooth_mesh.influences builds the same one)."""
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea import tooth_mesh_fe as fe
    from strainwave.fea.assembly import Lame
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    m = params.material
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)
    depth = geo.cs_outer_radius_mm - geo.cs_tooth.root_radius_mm
    wide = max(tm.CS_NEIGHBOURS + 2, int(math.ceil(2 * depth / (math.pi * geo.cs_tooth.module_mm))) + 2)
    return fe.sector_model(geo.cs_tooth, geo.cs_outer_radius_mm, wide, tm.SECTOR_H_RATIO * h_mm, lame,
                           geo.face_width_mm)


KEYS = ("K1_Nmm_per_rad", "K2_Nmm_per_rad", "K3_Nmm_per_rad", "T1_Nmm", "T2_Nmm", "secant_stiffness_rated_Nmm_per_rad",
        "lost_motion_arcmin", "friction_loss_per_cycle_Nmm", "friction_loss_trapezoid_Nmm", "transmission_error_pp_rad", "teeth_in_contact_rated",
        "peak_tooth_share", "peak_tooth_load_N", "engagement_edge_rated_rad", "ratcheting_torque_Nmm")


def readings(paths, mesh: dict) -> dict:
    from strainwave.fea import tooth_mesh as tm
    v = tm.loop_values(paths, mesh["rated_torque_Nmm"]) | tm.engagement_edge(paths[0], mesh["angles"][0])
    v |= tm.ratcheting(paths[0], mesh["angles"][0], mesh)
    k = int(np.argmax(paths[0].torque_Nmm))
    # the loop's work on the history's points alone (trapezoids): what the true-slip path's loss is read with
    p, k0 = paths[0], int(np.argmax(paths[0].torque_Nmm))
    v["friction_loss_trapezoid_Nmm"] = float(np.sum(0.5 * (p.torque_Nmm[k0 + 1:] + p.torque_Nmm[k0:-1])
                                                    * np.diff(p.twist_rad[k0:])))
    v["shares_at_rated"] = (paths[0].forces_N[k] / paths[0].forces_N[k].sum()).tolist()
    return v


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("params", nargs="?", default=None)
    ap.add_argument("--increments", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--angles", type=int, default=None, help="only the first K WG angles (default: all)")
    ap.add_argument("--json", default=None)
    ap.add_argument("--steps-per-leg", type=int, default=None,
                    help="the true-slip runs' history steps per leg (default: the study's own history)")
    a = ap.parse_args(argv)
    from strainwave.analytic.mesh_engagement import study_loads
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import MeshPath, solve_torque_path
    from strainwave.params import load_params
    params = load_params(a.params)
    mesh = study_loads(params, quick=False)["mesh"]
    if a.angles:
        mesh["angles"] = mesh["angles"][:a.angles]
    h = tm.refinements(params.flexspline_cup.module_mm, False)[0]
    c0 = time.process_time()
    infl, _ = tm.influences(params, mesh, h)
    sector = _sector(params, h)
    c1 = time.process_time()
    history = np.asarray(mesh["torque_history_Nmm"])
    study_systems = tm.systems(infl, mesh)
    shipped = [solve_torque_path(s, history) for s in study_systems]
    c2 = time.process_time()
    out = {"gear": a.params or "default", "h_mm": h, "influence_cpu_s": c1 - c0, "load": os.getloadavg(),
           "shipped": readings(shipped, mesh) | {"contact_cpu_s": c2 - c1}}
    keeps = [kept_pairs(p, s) for p, s in zip(shipped, study_systems)]
    built = [band_system(mesh, infl, p, infl["rim"], sector, k) for p, k in zip(mesh["angles"], keeps)]
    c3 = time.process_time()
    out["tangential_blocks_cpu_s"] = c3 - c2
    if a.steps_per_leg:           # a finer history for the true-slip runs: the loss's trapezoids checked
        from strainwave.fea.mesh_contact import torque_history
        history = torque_history(mesh["rated_torque_Nmm"], steps_per_leg=a.steps_per_leg)
        out["true_slip_steps_per_leg"] = a.steps_per_leg
    for N in a.increments:
        t0 = time.process_time()
        paths, worst = [], float("inf")
        for (system, cross), pairs, keep in zip(built, mesh["angles"], keeps):
            sub, Q = true_slip_path(system, history, N)
            worst = min(worst, left_out_min_gap(sub, Q, pairs, infl, mesh, keep, cross))
            F = np.zeros((history.size, len(pairs["clearance_mm"])))
            F[:, keep] = sub.forces_N
            paths.append(MeshPath(sub.torque_Nmm, sub.twist_rad, F, F > 0.0, sub.iterations, sub.work_Nmm))
        out[f"true_slip_N{N}"] = readings(paths, mesh) | {"contact_cpu_s": time.process_time() - t0,
                                                          "left_out_min_gap_mm": worst}
    _print(out, a.increments)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1, default=float)
    return 0


def _print(out: dict, incs) -> None:
    cols = ["shipped"] + [f"true_slip_N{N}" for N in incs]
    print(f"# {out['gear']}  h = {out['h_mm']:.4g} mm  load {out['load'][0]:.2f}  "
          f"influences {out['influence_cpu_s']:.1f} CPU-s, tangential blocks {out['tangential_blocks_cpu_s']:.1f} CPU-s")
    print("| output | " + " | ".join(cols) + " | true slip / shipped - 1 |")
    # friction_loss_trapezoid_Nmm: trapezoids on the history's points alone, crossing the dead band in one step
    # (not a result: it shows why the true-slip loss is read with both of the band's edges solved)
    for k in KEYS + ("contact_cpu_s",):
        vals = [out[c][k] for c in cols]
        rel = vals[-1] / vals[0] - 1 if vals[0] else float("nan")
        print(f"| {k} | " + " | ".join(f"{v:.6g}" for v in vals) + f" | {100 * rel:+.2f} % |")
    for c in cols[1:]:
        print(f"{c}: smallest gap of a left-out pair along the path {out[c]['left_out_min_gap_mm']:.3g} mm (>= 0: "
              "the restriction holds)")
    on = np.flatnonzero(np.asarray(out["shipped"]["shares_at_rated"]) > 0)
    print("shares at rated, loaded pairs of the headline angle " + str(on.tolist()))
    for c in cols:
        print(f"  {c} " + " ".join(f"{out[c]['shares_at_rated'][i]:.4f}" for i in on))


if __name__ == "__main__":
    sys.exit(main())
