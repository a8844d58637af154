"""Issue 48 item 2: the tooth-mesh FE's ratcheting torque on the design rules' drives against the Harmonic Drive CSF
catalogue's Table 4 (tooth-mesh-references.md s. 3), and the closed form's beside it. Nothing is fitted to the table.

The rules' drives are similar bodies (analytic/catalogue_rules.MeshRules: every length over d, w0 = m = d/(2 i),
K_G ~ d, rated ~ d^3), so the FE's ratcheting torque scales exactly as d^3 at one ratio: the FE runs at size 25 for
each CSF ratio (and at sizes 14 and 58 at i = 80 to show the scaling), each CSF row is that value times
(size/25)^3. One mesh (the quick study's finest, h = 0.3 m): the default gear's GCI is 0.6 %, the second's 1.9 %.
Run: nice .venv/bin/python benchmarks/ratcheting_csf.py [--json out.json]
     nice .venv/bin/python benchmarks/ratcheting_csf.py --rim [PARAMS.toml]: the shipped gear's FE ratcheting torque
     with the closed form's rim-on-the-balls lift (Hetenyi's beam on the bearing's foundation, analytic/
     mesh_compliance.py) added to the lobe's, on the FE's own loads: how much of the gap that compliance closes.
"""
from __future__ import annotations

import json
import sys
import time
from types import SimpleNamespace

import numpy as np

from strainwave.analytic.catalogue import overrides_for
from strainwave.analytic.catalogue_rules import MeshRules, RimRule
from strainwave.analytic.drive_curve import ratcheting_torque_Nm
from strainwave.analytic.mesh_engagement import study_loads
from strainwave.compare.validate.ratcheting import CSF_RATCHETING_NM
from strainwave.fea import tooth_mesh as tm
from strainwave.fea.mesh_contact import solve_torque_path
from strainwave.params import load_params

RATIOS = (30, 50, 80, 100, 120, 160)
# decision 069-ratchet48's drives: the blank rim 0.014 d (the catalogue's default became the fatigue rim, 069-cat48d)
RULES = MeshRules(rim_rule=RimRule.BLANK)


def rules_params(size: float, ratio: int, rules: MeshRules = RULES):
    """The parameter set of MeshRules' drive (the closed form's MeshRules.design, as a parameter file)."""
    d = rules.pitch_diameter_mm(size)
    o = overrides_for(SimpleNamespace(size=size, gear_ratio=ratio))
    o["flexspline_cup"] |= {"wall_thickness_mm": rules.rim_over_d * d}
    o["gear"] |= {"rated_output_torque_Nmm": 1e3 * rules.rated_torque_Nm(size)}
    o["wave_generator"] |= {"uncracked_radial_stiffness_N_per_mm": rules.K_G_per_d_N_per_mm2 * d}
    o["circular_spline"] |= {"face_width_mm": rules.face_width_over_d * d, "backlash_mm": 0.0}
    return load_params(None, o)


def fe_ratcheting_Nm(size: float, ratio: int) -> tuple[float, float]:
    params = rules_params(size, ratio)
    mesh = study_loads(params, quick=True)["mesh"]
    t0 = time.process_time()
    infl, _ = tm.influences(params, mesh, tm.refinements(params.flexspline_cup.module_mm, True)[0])
    system = tm.systems(infl, {**mesh, "angles": mesh["angles"][:1]})[0]
    path = solve_torque_path(system, np.asarray(mesh["torque_history_Nmm"]))
    r = tm.ratcheting(path, mesh["angles"][0], mesh)
    return 1e-3 * r["ratcheting_torque_Nmm"], time.process_time() - t0


def with_rim(params_file: str | None) -> None:
    import math
    from strainwave.analytic import mesh_compliance as mc
    from strainwave.analytic.mesh_drive import design_from_params
    params = load_params(params_file)
    mesh = study_loads(params, quick=True)["mesh"]
    infl, _ = tm.influences(params, mesh, tm.refinements(params.flexspline_cup.module_mm, True)[0])
    path = solve_torque_path(tm.systems(infl, {**mesh, "angles": mesh["angles"][:1]})[0],
                             np.asarray(mesh["torque_history_Nmm"]))
    pairs, k = mesh["angles"][0], int(np.argmax(path.torque_Nmm))
    F, T = path.forces_N[k], float(path.torque_Nmm[k])
    alpha = np.arccos(np.abs(pairs["lever_mm"]) / pairs["cs_radius_mm"])
    base = tm.ratcheting_torque_Nmm(F, alpha, pairs["phi_rad"], pairs["depth_mm"], mesh["wg_radial_stiffness_N_per_mm"], T)
    d = design_from_params(params)
    dphi = np.abs(pairs["phi_rad"][:, None] - pairs["phi_rad"][None, :])
    arc = d.geometry.neutral_radius_mm * np.minimum(dphi, 2 * math.pi - dphi)
    rim = mc.rim_on_foundation_green_mm_per_N(arc, d.E_MPa, d.rim_I_mm4, d.foundation_N_per_mm2) @ (F * np.sin(alpha))
    lift = base["ratcheting_lift_rated_mm"] + float(F @ rim / F.sum())
    print(json.dumps({"fe_Nm": 1e-3 * base["ratcheting_torque_Nmm"], "lobe_lift_mm": base["ratcheting_lift_rated_mm"],
                      "rim_lift_mm": lift - base["ratcheting_lift_rated_mm"],
                      "fe_with_rim_Nm": 1e-3 * T * base["ratcheting_overlap_mm"] / lift,
                      "closed_form_Nm": ratcheting_torque_Nm(d)}))


def main(argv: list[str]) -> None:
    if "--rim" in argv:
        rest = argv[argv.index("--rim") + 1:]
        return with_rim(rest[0] if rest else None)
    rules = RULES
    at25 = {}
    for i in RATIOS:
        at25[i], cpu = fe_ratcheting_Nm(25, i)
        print(json.dumps({"size": 25, "ratio": i, "fe_Nm": at25[i], "cpu_s": cpu}), flush=True)
    scaling = []
    for size in (14, 58):
        v, cpu = fe_ratcheting_Nm(size, 80)
        scaling.append({"size": size, "ratio": 80, "fe_Nm": v, "by_d3_Nm": at25[80] * (size / 25) ** 3, "cpu_s": cpu})
        print(json.dumps(scaling[-1]), flush=True)
    rows = []
    for size, row in CSF_RATCHETING_NM.items():
        for i, csf in row.items():
            fe = at25[i] * (size / 25) ** 3
            cf = ratcheting_torque_Nm(rules.design(size, i))
            rows.append({"size": size, "ratio": i, "csf_Nm": csf, "fe_Nm": fe, "closed_form_Nm": cf,
                         "fe_over_csf": fe / csf, "closed_form_over_csf": cf / csf,
                         "rated_Nm": rules.rated_torque_Nm(size)})
    for r in rows:
        print(f"size {r['size']:>2} i {r['ratio']:>3}: CSF {r['csf_Nm']:>6g} N m  FE {r['fe_Nm']:>9.4g} "
              f"({r['fe_over_csf']:.3g} x)  closed form {r['closed_form_Nm']:>9.4g} ({r['closed_form_over_csf']:.3g} x)")
    if "--json" in argv:
        with open(argv[argv.index("--json") + 1], "w") as f:
            json.dump({"at_size_25": at25, "scaling": scaling, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
