"""strainwave and CalculiX side by side on ONE discrete frictional tooth-contact problem, on the same P2 mesh.

The problem (decision 070-ccx2pct48; benchmarks/mesh_ccx_band.py): a sector of the flexspline's toothed rim on the
study's finest mesh (0.30 m), its bore clamped, one rigid punch per +theta-flank pair of a lobe at the study's
unloaded clearances, friction mu = the study's; each flank's contact is strainwave's band (CalculiX: a reference
node tied to the band by *EQUATION, node-to-surface contact with *FRICTION on the punch). The lobe's rated torque
(half the drive's) on the first loading, then back down to half of it (the reversal: the flanks stick, then slide
back). strainwave: its band flexibility of that mesh and its true-slip frictional contact (fea/mesh_friction.py)
find the twists; CalculiX runs those twists. Printed: both codes' load per tooth and share, the teeth in contact,
CalculiX's torque at that twist, and, ``--repeats`` times alternating, each code's time (strainwave: sector mesh,
assembly, factorisation, band loads, flexibility, contact solve; CalculiX: its run of the written deck) with
medians, the load average and the ratio. Then, once and untimed (``--no-extras`` skips them): the study's
torque-only friction (fea/mesh_contact.py) against CalculiX at its own twists, and the geometric contact (a rigid
flat punch on the flank facets, node-to-surface, decision 069-ccx48) at the true-slip twists: what each of the two
modelling differences moves. Goal (issue 48 item 8): the peak tooth share within 2 %.

    python benchmarks/bench_mesh_calculix.py [--h-over-m 0.30] [--repeats 3] [--ccx-threads 1] [--no-extras]
    python benchmarks/bench_mesh_calculix.py --full-loop [--h-over-m 0.42]   # both flanks, the -T leg, once
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import calculix_job as cj  # noqa: E402
import mesh_ccx_band as mb  # noqa: E402
import mesh_ccx_job as mj  # noqa: E402


UNLOAD_TO = 0.5                # the reversal's second step: back down to half the lobe's rated torque


def load_average() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def strainwave_once(params, h_mm: float) -> tuple[mj.Problem, dict, float]:
    """strainwave end to end on the problem: build (mesh, assembly, factorisation, band loads, flexibility) and
    the true-slip solve along 0 -> T -> T/2."""
    pairs = mj.pairs_for(params)                 # the kinematics are both codes' input: not timed
    t1 = time.perf_counter()
    problem = mj.build(params, pairs, h_mm, on_involute=True)
    sw = mb.strainwave_true_slip(problem, params.flexspline_cup.module_mm, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    return problem, sw, time.perf_counter() - t1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--h-over-m", type=float, default=0.30, help="element size over the module (study finest 0.30)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--ccx-threads", type=int, default=1)
    ap.add_argument("--no-extras", action="store_true", help="skip the two untimed modelling comparisons")
    ap.add_argument("--study", action="store_true",
                    help="instead: the study's own friction solve (torque_path, its steps) against CalculiX, once")
    ap.add_argument("--full-loop", action="store_true",
                    help="instead: both flanks of the lobe along 0 -> +T -> -T -> +T, once, untimed")
    a = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    ccx = cj.ensure_ccx()
    if ccx is None:
        print("ccx is not installed and cannot be installed here: MISS (not run)")
        return 0
    from strainwave.params import load_params
    params = load_params()
    h = a.h_over_m * params.flexspline_cup.module_mm
    if a.full_loop:
        return full_loop(params, h, ccx, a.ccx_threads)
    if a.study:
        return study_line(params, h, ccx, a.ccx_threads)
    print(f"tooth-mesh band contact, strainwave vs CalculiX, h = {h:.3f} mm, load average {load_average()}", flush=True)
    sw_t, ccx_t, first = [], [], None
    with tempfile.TemporaryDirectory(prefix="sw-mesh-ccx-") as tmp:
        for r in range(a.repeats):
            problem, sw, dt = strainwave_once(params, h)
            sw_t.append(dt)
            if first is None:
                first = (problem, sw)
                nodes, pinned = problem.model.basis.N, float(problem.model.basis.doflocs.sum())
            elif (problem.model.basis.N, float(problem.model.basis.doflocs.sum())) != (nodes, pinned):
                raise RuntimeError("the sector's mesh changed between runs: not the same problem")
            res = mb.run_band(first[0], params, [first[1]["twist_rad"], first[1]["unloaded"]["twist_rad"]],
                              Path(tmp) / f"r{r}", ccx=ccx, threads=a.ccx_threads)
            ccx_t.append(res["wall_s"])
            print(f"  run {r + 1}: strainwave {dt:.2f} s, CalculiX {res['wall_s']:.2f} s "
                  f"(load {load_average()})", flush=True)
    problem, sw = first
    verdicts = [_report(problem, nodes, ref, got, label) for ref, got, label in
                ((sw, res["steps"][0], "first loading to rated"),
                 (sw["unloaded"], res["steps"][1], f"after the reversal, down to {UNLOAD_TO:g} x rated"))]
    if not a.no_extras:
        _extras(problem, params, sw, ccx, a.ccx_threads)
    ms, mc = statistics.median(sw_t), statistics.median(ccx_t)
    print(f"time (medians of {a.repeats} alternating runs): strainwave {ms:.2f} s, CalculiX {mc:.2f} s "
          f"({a.ccx_threads} thread), strainwave / CalculiX = {ms / mc:.3f}; load average {load_average()}")
    for label, ag in verdicts:
        print(f"peak tooth share, {label}: strainwave {ag['peak_share_strainwave']:.4f}, CalculiX "
              f"{ag['peak_share_calculix']:.4f} ({100 * ag['peak_share_rel']:+.3f} %, goal within "
              f"{100 * mj.PEAK_SHARE_REL_TOL:.0f} %), teeth in contact {ag['teeth_in_contact'][0]} / "
              f"{ag['teeth_in_contact'][1]}: {'PASS' if ag['passes'] else 'MISS'}")
    return 0


def full_loop(params, h_mm: float, ccx: str, threads: int) -> int:
    """The study's load on both flanks of the lobe: +theta pairs carry +T, -theta pairs -T; the -T leg."""
    problem, pairs = mj.problem_for(params, h_mm, on_involute=True, sides=(1, -1))
    T = pairs["torque_Nmm"]
    legs = mb.strainwave_true_slip_path(problem, params.flexspline_cup.module_mm, [T, -T, T])
    print(f"tooth-mesh band contact, both flanks, 0 -> +T -> -T -> +T, h = {h_mm:.3f} mm, load average "
          f"{load_average()}", flush=True)
    with tempfile.TemporaryDirectory(prefix="sw-mesh-ccx-") as tmp:
        res = mb.run_band(problem, params, [r["twist_rad"] for r in legs], Path(tmp), ccx=ccx, threads=threads)
    print(f"  CalculiX {res['wall_s']:.1f} s (load {load_average()})")
    labels = ("first loading to +T", "reversed to -T (the -T leg)", "back to +T")
    verdicts = [_report(problem, problem.model.basis.N, r, g, lb) for r, g, lb in zip(legs, res["steps"], labels)]
    for label, ag in verdicts:
        print(f"peak tooth share, both flanks, {label}: strainwave {ag['peak_share_strainwave']:.4f}, CalculiX "
              f"{ag['peak_share_calculix']:.4f} ({100 * ag['peak_share_rel']:+.3f} %, goal within "
              f"{100 * mj.PEAK_SHARE_REL_TOL:.0f} %), teeth in contact {ag['teeth_in_contact'][0]} / "
              f"{ag['teeth_in_contact'][1]}: {'PASS' if ag['passes'] else 'MISS'}")
    return 0


def study_line(params, h_mm: float, ccx: str, threads: int) -> int:
    """The tooth-mesh STUDY's model on the problem (decision 073-slipstudy48): its friction on the true slip solved
    as the study solves it (fea/mesh_friction.torque_path, 40 torque steps to the lobe's rated, 20 back down to
    half, tooth_mesh.INCREMENTS increments a step); CalculiX runs the study's twists. Once, untimed."""
    problem, pairs = mj.problem_for(params, h_mm, on_involute=True)
    t0 = time.process_time()
    study = mb.strainwave_study_path(problem, params.flexspline_cup.module_mm, pairs["torque_Nmm"], unload_to=UNLOAD_TO)
    print(f"the study's model (true slip, torque_path) on the band problem, h = {h_mm:.3f} mm: "
          f"{time.process_time() - t0:.2f} CPU-s; load average {load_average()}", flush=True)
    with tempfile.TemporaryDirectory(prefix="sw-mesh-ccx-") as tmp:
        res = mb.run_band(problem, params, [study["twist_rad"], study["unloaded"]["twist_rad"]], Path(tmp),
                          ccx=ccx, threads=threads)
    print(f"  CalculiX {res['wall_s']:.1f} s (load {load_average()})")
    labels = ("first loading to rated", f"after the reversal, down to {UNLOAD_TO:g} x rated")
    verdicts = [_report(problem, problem.model.basis.N, r, g, lb)
                for r, g, lb in zip((study, study["unloaded"]), res["steps"], labels)]
    for label, ag in verdicts:
        print(f"peak tooth share, the study's model, {label}: strainwave {ag['peak_share_strainwave']:.4f}, CalculiX "
              f"{ag['peak_share_calculix']:.4f} ({100 * ag['peak_share_rel']:+.3f} %, goal within "
              f"{100 * mj.PEAK_SHARE_REL_TOL:.0f} %), teeth in contact {ag['teeth_in_contact'][0]} / "
              f"{ag['teeth_in_contact'][1]}: {'PASS' if ag['passes'] else 'MISS'}")
    return 0


def _extras(problem, params, sw: dict, ccx: str, threads: int) -> None:
    """Untimed, not goal lines: the study's torque-only friction against CalculiX's band contact at the study's
    own twists (the friction model's part), and CalculiX's geometric contact (a flat punch seated on the facet at
    the study's radius, decision 069-ccx48) against strainwave's true slip on that seat (the load shape's part)."""
    study = mj.strainwave_solve(problem, sw["torque_Nmm"], unload_to=UNLOAD_TO)
    m = params.flexspline_cup.module_mm
    seated = mj.build(params, mj.pairs_for(params), problem.model.h_mm)
    sw_seat = mb.strainwave_true_slip(seated, m, sw["torque_Nmm"], unload_to=UNLOAD_TO)
    with tempfile.TemporaryDirectory(prefix="sw-mesh-ccx-") as tmp:
        band = mb.run_band(problem, params, [study["twist_rad"], study["unloaded"]["twist_rad"]], Path(tmp),
                           ccx=ccx, threads=threads)
        geo = mj.run_calculix(seated, params, [sw_seat["twist_rad"], sw_seat["unloaded"]["twist_rad"]],
                              Path(tmp) / "g", ccx=ccx, threads=threads)
    for name, refs, got in (("the study's torque-only friction (mesh_contact) vs CalculiX's band contact",
                             (study, study["unloaded"]), band["steps"]),
                            ("true slip vs CalculiX's geometric contact (flat punch on the facet)",
                             (sw_seat, sw_seat["unloaded"]), geo["steps"])):
        rel = [mj.agreement(r, g)["peak_share_rel"] for r, g in zip(refs, got)]
        print(f"{name}: peak share {100 * rel[0]:+.2f} % first loading, {100 * rel[1]:+.2f} % after the "
              "reversal (not a goal line)", flush=True)


def _report(problem, nodes: int, sw: dict, res: dict, label: str) -> tuple[str, dict]:
    ag = mj.agreement(sw, res)
    print(f"{label}: {problem.teeth.size} flank pairs, {2 * nodes} dofs (P2), twist {sw['twist_rad']:.6e} rad at "
          f"{sw['torque_Nmm']:.6g} N mm; CalculiX's torque at that twist {res['torque_Nmm']:.6g} N mm "
          f"(x{ag['torque_ratio']:.5f})")
    print("  pair  tooth  clearance_um  strainwave_N  share   tangential_N  CalculiX_N  share   tangential_N")
    for k in np.flatnonzero((sw["forces_N"] > 0) | (res["forces_N"] > 1e-3 * res["forces_N"].max())):
        print(f"  {k:4d}  {problem.teeth[k]:5d}  {1e3 * problem.clearance_mm[k]:12.3f}  {sw['forces_N'][k]:12.2f}"
              f"  {sw['share'][k]:.4f}  {sw['tangential_N'][k]:12.2f}  {res['forces_N'][k]:10.2f}"
              f"  {res['share'][k]:.4f}  {-res['tangential_N'][k]:12.2f}")
    return label, ag


if __name__ == "__main__":
    sys.exit(main())
