"""Decision 068 (cat48c): two probes of the compliance the catalogue chain misses, on the design rules' drives.

1. ``fe``: the tooth-mesh FE (fea/tooth_mesh.py ``influences``, called as the study calls it, three meshes)
   against the reduced model's compliance (analytic/mesh_compliance.py) on the SAME flank pairs (the study's
   kinematics, analytic/mesh_engagement.py) and the SAME support: the bore held radially ("held"), or on the
   balls' Winkler bed with the WG lobe rigid and no outer ring ("bed"). The rules' drive at d = 160 mm (i = 100 is
   the shipped gear; i = 30 by Z_f = 60, m = w0 = 2.667 mm), zero backlash. The FE's CS sector is replaced by
   ISO's solid pair minus the FE's solid FS tooth: at the major pair the contact radius is the CS root, where the
   sector's influence does not converge (decision 068).
2. ``coning``: K1/K3/T1/T2 and the secant at rated over the catalogue at size 25 against the face slices, with
   decision 067's chain (cup series + the cup-zone FE term of decision 067's table, held fixed).
Run: .venv/bin/python benchmarks/catalogue_mesh_probes.py fe 30   (or: fe 100, coning 30, coning 100)
"""
from __future__ import annotations

import json
import sys
import time
from dataclasses import replace

import numpy as np

from strainwave.analytic import mesh_compliance as mc
from strainwave.analytic.catalogue_rules import MeshRules, RimRule
from strainwave.analytic.mesh_drive import pair_compliance_mm_per_N
from strainwave.analytic.mesh_engagement import study_loads
from strainwave.fea import tooth_mesh as tm
from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path
from strainwave.params import load_params

D_MM = 160.0
CATALOGUE_25 = {30: (10e3, 21e3, 14, 48), 50: (25e3, 44e3, 14, 48), 100: (31e3, 57e3, 14, 48)}   # K1 K3 T1 T2
CUP_ZONE_25 = {30: 1.875e-9, 50: 1.808e-9, 100: 1.752e-9}     # decision 067's finest values, rad/(N mm)


def _read(paths, rated):
    v = tm.loop_values(paths, rated)
    return {k: float(v[k]) for k in ("secant_stiffness_rated_Nmm_per_rad", "K3_Nmm_per_rad", "K1_Nmm_per_rad",
                                     "teeth_in_contact_rated")}


def _reduced(design, pairs, support: str) -> np.ndarray:
    if support == "held":      # the bore rigid: the pair's own springs only (ISO c' + the tilt beam)
        return pair_compliance_mm_per_N(design) * np.eye(len(pairs["side"]))
    g = design.geometry
    return mc.mesh_compliance_matrix(
        pairs["phi_rad"], np.arange(len(pairs["side"])), psi_rad=0.0, wave_number=2, radius_mm=g.neutral_radius_mm,
        alpha_deg=g.pressure_angle_deg, pair_compliance_mm_per_N=pair_compliance_mm_per_N(design),
        E_MPa=design.E_MPa, rim_I_mm4=design.rim_I_mm4, foundation_N_per_mm2=design.foundation_N_per_mm2,
        K_G_N_per_mm=design.K_G_N_per_mm, tooth_height_mm=g.pitch_radius_mm - g.neutral_radius_mm,
        flank_sign=pairs["side"].astype(float))


def fe_against_reduced(ratio: int) -> None:
    z = 2 * ratio
    m = D_MM / z
    params = load_params(None, {"flexspline_cup": {"teeth": z, "module_mm": m, "wall_thickness_mm": 2.24},
                                "gear": {"radial_deformation_mm": m}, "circular_spline": {"backlash_mm": 0.0}})
    mesh = study_loads(params)["mesh"]
    rated, hist = mesh["rated_torque_Nmm"], np.asarray(mesh["torque_history_Nmm"])
    rules = MeshRules(rim_rule=RimRule.BLANK)
    design = rules.design(D_MM / rules.pitch_diameter_per_size_mm, ratio)
    bed = design.foundation_N_per_mm2
    design = replace(design, bearing_outer_ring_mm=1e-9, K_G_N_per_mm=1e12)     # the FE's support: the bed only
    a0 = mesh["angles"][0]
    for support in ("held", "bed"):
        s = MeshSystem(a0["clearance_mm"], _reduced(design, a0, support), a0["lever_mm"], a0["slide_mm_per_rad"],
                       mesh["friction_coefficient"], mesh["rim_radius_mm"])
        print(json.dumps({"ratio": ratio, "model": "reduced", "support": support, "bed_N_per_mm2": bed,
                          "pair_mm_per_N": pair_compliance_mm_per_N(design)} | _read([solve_torque_path(s, hist)], rated)))
        for h in tm.refinements(m, False):
            t0 = time.process_time()
            infl, _ = tm.influences(params, mesh, h, bed_N_per_mm2=None if support == "held" else bed)
            w = tm._interp_weights(infl["fs_radii"], np.array([mesh["major_fs_radius_mm"]]))[0]
            sector = tm.major_pair(infl, mesh)["cs_tooth_compliance_major_mm_per_N"]    # the FE's own CS tooth
            raw = _read([solve_torque_path(tm.systems(infl, {**mesh, "angles": [a0]})[0], hist)], rated)
            fs_solid = float(w @ infl["fs_solid"][0] @ w)
            iso = mc.tooth_pair_compliance_mm_per_N(
                mc.iso6336_single_pair_stiffness_N_per_mm_um(z, None, alpha_deg=20.0), infl["face_width_mm"])
            infl["cs"] = np.zeros_like(infl["cs"])
            infl["cs"][tm.CS_NEIGHBOURS] = iso - fs_solid
            v = _read([solve_torque_path(tm.systems(infl, {**mesh, "angles": [a0]})[0], hist)], rated)
            print(json.dumps({"ratio": ratio, "model": "fe", "support": support, "h_mm": h,
                              "fs_tooth_mm_per_N": float(w @ infl["fs_same"][0] @ w),
                              "fs_next_mm_per_N": float(w @ infl["fs_same"][1] @ w), "cs_mm_per_N": iso - fs_solid,
                              "cs_sector_mm_per_N": float(sector),
                              "secant_with_cs_sector": raw["secant_stiffness_rated_Nmm_per_rad"],
                              "cpu_s": time.process_time() - t0} | v), flush=True)


def coning(ratio: int, size: float = 25.0) -> None:
    k1, k3, t1, t2 = CATALOGUE_25[ratio]
    for n in (1, 2, 4, 8):
        rules = replace(MeshRules(rim_rule=RimRule.BLANK), face_slices=n)
        from strainwave.analytic.drive_curve import predict_curve
        c = predict_curve(rules.design(size, ratio), rules.cup_flexibility_rad_per_Nmm(size) + CUP_ZONE_25[ratio],
                          rules.rated_torque_Nm(size), with_te=False)
        k = int(np.argmax(c.loop_torque_Nm))
        print(json.dumps({"ratio": ratio, "slices": n, "K1": c.K1_Nm_per_rad / k1, "K3": c.K3_Nm_per_rad / k3,
                          "T1": c.T1_Nm / t1, "T2": c.T2_Nm / t2,
                          "secant_rated": c.loop_torque_Nm[k] / c.loop_twist_rad[k] / k3,
                          "pairs_in_contact": int(c.teeth_in_contact.max())}), flush=True)


if __name__ == "__main__":
    {"fe": fe_against_reduced, "coning": coning}[sys.argv[1]](int(sys.argv[2]))
