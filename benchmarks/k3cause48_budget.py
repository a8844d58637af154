"""Decision 073 (k3cause48): the catalogue chain's compliance budget over the K3 window at size 25.

For each ratio: the K3-window compliance (phi(A) - phi(T2)) / (A - T2) of the full chain, and what each member
contributes (the member stiffened 1e6x, the difference), against what the CHA row needs; then the candidates.
Run: .venv/bin/python benchmarks/k3cause48_budget.py [candidates | sourced | mesh-split | preload | kappa]
"""
from __future__ import annotations

import sys
import time
from dataclasses import replace

import numpy as np

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import _loop, mean_twist_rad

CATALOGUE_K3 = {30: 21e3, 50: 44e3, 100: 57e3}     # CHA-25 K3, N m/rad (../shared/data)
T2 = 48.0                                          # CHA-25 T2, N m


def window_compliance(design, series, rated):
    T, tw, _ = _loop(design, series, rated, 0.0)
    phi = mean_twist_rad(T, tw, np.array([T2, rated]))
    return 1e-3 * (phi[1] - phi[0]) / (rated - T2)          # rad/(N mm)


def budget(rules: MeshRules, ratio: float) -> dict:
    size = rules.cup_zone_reference_size
    d = rules.pitch_diameter_mm(size)
    design, rated = rules.design(size, ratio), rules.rated_torque_Nm(size)
    cup = rules.cup_flexibility_rad_per_Nmm(size)
    zone = rules.cup_zone_term(ratio).at(d)
    body = rules.cs_body_term(ratio).at(d, rules.E_MPa)
    series = cup + zone + body
    full = window_compliance(design, series, rated)
    out = {"full": full, "cup series": cup, "cup zone": zone, "CS body (face)": body}
    out["mesh + WG (no series)"] = window_compliance(design, 0.0, rated)
    stiff_kg = replace(design, K_G_N_per_mm=1e6 * design.K_G_N_per_mm)
    out["WG lobe K_G"] = full - window_compliance(stiff_kg, series, rated)
    stiff_b = replace(design, foundation_N_per_mm2=1e6 * design.foundation_N_per_mm2, bearing=None)
    out["balls (bed + Hertz remainder)"] = full - window_compliance(stiff_b, series, rated)
    out["catalogue"] = 1e-3 / CATALOGUE_K3[int(ratio)]
    out["miss"] = out["catalogue"] - full
    return out


def main(argv):
    rules = MeshRules()
    t0 = time.process_time()
    for ratio in (30.0, 50.0, 100.0):
        b = budget(rules, ratio)
        print(f"ratio {ratio:g}: " + "; ".join(f"{k} {v:.3e}" for k, v in b.items()))
    print(f"CPU {time.process_time() - t0:.1f} s")



# ---- the candidates of decision 073 ----------------------------------------------------------------------------

def cam_ring_fe_twist(R_o, R_i, E, b, r_p, alpha_deg, wrap_deg, nr, nt):
    """The WG cam (with its inner ring bonded on) as a plane-stress annulus R_i..R_o, loaded by the two lobes'
    radial loads F_r = T tan(alpha) / (2 r_p) (inward pressure over +-wrap_deg at the major axes), bore free:
    the output twist per N mm its squeeze gives (mean radial give under the lobe x tan(alpha) / r_p), by work."""
    import math
    from skfem import Basis, ElementTriP2, ElementVector, FacetBasis, asm, condense, solve
    from skfem.models.elasticity import lame_parameters, linear_elasticity
    from strainwave.fea.cs_body_fe import annulus, traction_forms
    m = annulus(R_i, R_o, nr, nt)
    e = ElementVector(ElementTriP2())
    ib = Basis(m, e)
    lam, mu = lame_parameters(E, 0.3)
    lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    K = b * asm(linear_elasticity(lam, mu), ib)
    tol = 0.5 * (R_o - R_i) / nr
    outer = FacetBasis(m, e, facets=m.facets_satisfying(lambda x: np.hypot(x[0], x[1]) > R_o - tol))
    s = math.sin(math.radians(wrap_deg))
    _, rad = traction_forms(lambda x: (np.abs(np.sin(np.arctan2(x[1], x[0]))) < s).astype(float))
    fr = asm(rad, outer)
    ux, uy = ib.split_indices()
    x, y = ib.doflocs[0], ib.doflocs[1]
    radial = np.zeros(ib.N)
    radial[ux], radial[uy] = x[ux] / np.hypot(x[ux], y[ux]), y[uy] / np.hypot(x[uy], y[uy])
    F_r = math.tan(math.radians(alpha_deg)) / (2.0 * r_p)
    f = -fr / (fr @ radial) * 2.0 * F_r                     # inward, F_r per lobe
    pA = np.argmin(np.hypot(m.p[0], m.p[1] - R_o))          # statically determinate: the minor axis's nodes
    pB = np.argmin(np.hypot(m.p[0], m.p[1] + R_o))
    D = np.array([ib.nodal_dofs[0][pA], ib.nodal_dofs[1][pA], ib.nodal_dofs[0][pB]])
    u = solve(*condense(K, f, D=D))
    return float(f @ u) / (2.0 * F_r) * math.tan(math.radians(alpha_deg)) / r_p, ib.N


def cam_envelope(rules, size, ratio):
    """(outer radius of cam + inner ring, pitch radius) from the rules' envelope: the cup's bore less the outer ring,
    the balls and an inner ring as thick as the shipped one (3.0 / 160 d)."""
    d = rules.pitch_diameter_mm(size)
    g = rules.design(size, ratio).geometry
    bore = 0.5 * d - 1.25 * g.module_mm - g.rim_thickness_mm
    R_race = bore - rules.outer_ring_over_d * d - rules.ball_diameter_over_d * d
    return R_race, g.pitch_radius_mm, g.face_width_mm


def pair_factor_window(rules, ratio, factor):
    """The K3-window compliance with every flank pair's own compliance x factor (plane strain / stress / 3D)."""
    from strainwave.analytic import mesh_drive
    size = rules.cup_zone_reference_size
    d = rules.pitch_diameter_mm(size)
    series = (rules.cup_flexibility_rad_per_Nmm(size) + rules.cup_zone_term(ratio).at(d)
              + rules.cs_body_term(ratio).at(d, rules.E_MPa))
    orig = mesh_drive.pair_compliance_mm_per_N
    mesh_drive.pair_compliance_mm_per_N = lambda design: factor * orig(design)
    try:
        return window_compliance(rules.design(size, ratio), series, rules.rated_torque_Nm(size))
    finally:
        mesh_drive.pair_compliance_mm_per_N = orig


def candidates(rules: MeshRules, ratio: float) -> dict:
    import math
    from strainwave.analytic import mesh_compliance as mc
    from strainwave.analytic.mesh_drive import pair_compliance_mm_per_N
    size = rules.cup_zone_reference_size
    d, E = rules.pitch_diameter_mm(size), rules.E_MPa
    out = {}
    # (b) the cam: solid (bore 0.02 R) and hollow (bore 0.5 / 0.7 R: a hollow-shaft unit; unsourced), lobes spread
    # over +-15 deg (the wrap) and +-5 deg; three polar lattices for the GCI
    R_o, r_p, b = cam_envelope(rules, size, ratio)
    for frac in (0.02, 0.5, 0.7):
        for wrap in (15.0, 5.0):
            vals = [cam_ring_fe_twist(R_o, frac * R_o, E, b, r_p, 20.0, wrap, k * (4 if frac > 0.1 else 8),
                                      k * 72)[0] for k in (1, 2, 4)]
            out[f"cam bore {frac:g} R wrap {wrap:g}"] = vals
    # (c) the FS boss's bolted joint: interface tangential stiffness per area k_t (unsourced) over the hub annulus
    from strainwave.geometry.flexspline_cup import HUB_BORE_RATIO, HUB_RATIO
    J = 0.5 * math.pi * ((HUB_RATIO * d) ** 4 - (HUB_BORE_RATIO * d) ** 4)
    for kt in (1e3, 1e4, 1e5):
        out[f"boss joint k_t {kt:g} N/mm3"] = 1.0 / (kt * J)
    # (d) the pair's own compliance x 0.91 / x 1.10 (plane strain / plane stress, decision 064's spread)
    base = pair_factor_window(rules, ratio, 1.0)
    for f in (0.91, 1.10):
        out[f"pairs x {f:g}"] = pair_factor_window(rules, ratio, f) - base
    dd = rules.design(size, ratio)
    g = dd.geometry
    c = mc.iso6336_single_pair_stiffness_N_per_mm_um(g.teeth_flexspline, None, alpha_deg=g.pressure_angle_deg)
    out["pair ISO part / pair"] = mc.tooth_pair_compliance_mm_per_N(c, g.face_width_mm) / pair_compliance_mm_per_N(dd)
    return out


def main_candidates():
    rules = MeshRules()
    t0 = time.process_time()
    for ratio in (30.0, 50.0, 100.0):
        for k, v in candidates(rules, ratio).items():
            print(f"ratio {ratio:g}: {k}: {v}")
    print(f"CPU {time.process_time() - t0:.1f} s")



def main_sourced():
    """(a): the rules' drive with one printed proportion changed at a time: the CJME 2021 ring flexspline's face
    width b/d = 10/60 (one research unit), and a cup length L = lambda R_m at the web calculator's lambda 0.8 (0.4: the shell's closed form only)."""
    base = MeshRules()
    t0 = time.process_time()
    for label, rules in (("b/d 10/60", replace(base, face_width_over_d=10.0 / 60.0)),
                         ("L 0.4 d", replace(base, length_over_d=0.4))):   # L 0.2 d: refused (decision 075)
        for ratio in (30.0, 50.0, 100.0):
            b = budget(rules, ratio)
            print(f"{label} ratio {ratio:g}: full {b['full']:.3e} miss {b['miss']:.3e} cup {b['cup series']:.3e} "
                  f"zone {b['cup zone']:.3e}")
    print(f"CPU {time.process_time() - t0:.1f} s")



def main_mesh_split():
    """Where the mesh's own K3-window compliance sits: the rim + outer ring's bending (EI x 1e6), and the pairs
    (x 1e-6), one at a time, at size 25."""
    from strainwave.analytic import mesh_drive
    from strainwave.analytic.mesh_drive import MeshDesign
    rules = MeshRules()
    size = rules.cup_zone_reference_size
    rated = rules.rated_torque_Nm(size)
    orig_I, orig_pair = MeshDesign.rim_I_mm4, mesh_drive.pair_compliance_mm_per_N
    for ratio in (30.0, 50.0, 100.0):
        design = rules.design(size, ratio)
        base = window_compliance(design, 0.0, rated)
        try:
            MeshDesign.rim_I_mm4 = property(lambda self: 1e6 * orig_I.fget(self))
            rigid_rim = window_compliance(design, 0.0, rated)
        finally:
            MeshDesign.rim_I_mm4 = orig_I
        try:
            mesh_drive.pair_compliance_mm_per_N = lambda d: 1e-6 * orig_pair(d)
            rigid_pairs = window_compliance(design, 0.0, rated)
        finally:
            mesh_drive.pair_compliance_mm_per_N = orig_pair
        print(f"ratio {ratio:g}: mesh {base:.3e}; rim bending {base - rigid_rim:.3e}; pairs {base - rigid_pairs:.3e}")



def preloaded_path(system, torque_Nmm, c0):
    """``fea.mesh_contact.solve_torque_path`` started from a preloaded state: clearances ``c0`` (negative where the
    teeth interfere at zero torque); the initial contact set is the LCP's at theta = 0 (pairs with F <= 0 dropped,
    pairs whose gap closes added, until both hold)."""
    from strainwave.fea.mesh_contact import MeshPath, _Tracker
    tr = _Tracker(system)
    tr.c = np.asarray(c0, float)        # MeshSystem refuses negative gaps; the tracker itself does not need them >= 0
    A = c0 < 0.0
    for _ in range(200):
        tr.active = A.copy()
        a, _b = tr.linear()
        gap = c0 + tr.C @ a
        drop = A & (a <= 0.0)
        add = ~A & (gap < 0.0)
        if not drop.any() and not add.any():
            break
        A = (A & ~drop) | add
    else:
        raise RuntimeError("the preload's contact set did not settle")
    T = np.asarray(torque_Nmm, float)
    theta, forces, work = np.zeros(len(T)), np.zeros((len(T), len(c0))), np.zeros(len(T))
    for k, Tk in enumerate(T):
        tr.work = 0.0
        up, down = tr.torque(tr.theta, 1.0), tr.torque(tr.theta, -1.0)
        if Tk > up:
            tr.move_to(Tk, 1.0)
        elif Tk < down:
            tr.move_to(Tk, -1.0)
        theta[k], forces[k], work[k] = tr.theta, tr.forces(), tr.work
    return MeshPath(T, theta, forces, forces > 0.0, np.zeros(len(T), int), work), int(A.sum())


def main_preload():
    """(e): the teeth preloaded at the major axis by a radial over-deflection dw (the wave's amplitude w0 + dw):
    every flank's gap falls by dw cos(2 phi) sin(alpha); dw / m = 0 / 0.02 / 0.05 / 0.1 (unsourced: a bracket)."""
    import math
    from strainwave.analytic.catalogue_loss import hysteresis_loss_rad
    from strainwave.analytic.drive_curve import LOOP_STEPS_PER_LEG, catalogue_secants
    from strainwave.analytic.mesh_drive import bearing_twist_rad, mesh_system
    from strainwave.analytic.mesh_kinematics import sliced_clearances
    from strainwave.fea.mesh_contact import torque_history
    rules = MeshRules()
    size = rules.cup_zone_reference_size
    d, rated = rules.pitch_diameter_mm(size), rules.rated_torque_Nm(size)
    cat = {30: (10e3, 13e3, 21e3), 50: (25e3, 34e3, 44e3), 100: (31e3, 50e3, 57e3)}
    t0 = time.process_time()
    for ratio in (30.0, 50.0, 100.0):
        design = rules.design(size, ratio)
        g = design.geometry
        series = (rules.cup_flexibility_rad_per_Nmm(size) + rules.cup_zone_term(ratio).at(d)
                  + rules.cs_body_term(ratio).at(d, rules.E_MPa))
        system, tooth = mesh_system(design)
        _, _, _, _, angles = sliced_clearances(g, 0.0)
        angles = np.asarray(angles)[tooth]
        T = torque_history(1e3 * rated, LOOP_STEPS_PER_LEG)
        for dw in (0.0, 0.02, 0.05, 0.1):
            c0 = np.asarray(system.clearance_mm) - dw * g.module_mm * np.cos(2.0 * np.asarray(angles)) * math.sin(
                math.radians(g.pressure_angle_deg))
            path, n0 = preloaded_path(system, T, c0)
            tw = path.twist_rad + T * series + bearing_twist_rad(design, T)
            sec = catalogue_secants(1e-3 * T, tw, 14.0, 48.0)
            k1, _, k3 = cat[int(ratio)]
            print(f"ratio {ratio:g} dw {dw:g} m: pairs preloaded {n0}; K1 {sec['K1_Nm_per_rad'] / k1:.2f} "
                  f"K3 {sec['K3_Nm_per_rad'] / k3:.2f} of the catalogue; hysteresis at 0 N m "
                  f"{hysteresis_loss_rad(1e-3 * T, tw) * 180 * 60 / math.pi:.3f} arcmin")
    print(f"CPU {time.process_time() - t0:.1f} s")



def main_kappa():
    """A sensitivity, not a candidate for adoption (no source gives kappa): the wave's amplitude w0 = kappa m at
    kappa 0.8 / 1.25, and at 1.25 split into its two routes (the fatigue rim sized for kappa 1.25 with the kappa-1
    kinematics, and the kappa-1.25 kinematics on the kappa-1 rim)."""
    from dataclasses import dataclass

    @dataclass(frozen=True)
    class RimOf(MeshRules):
        rim_kappa: float = 1.0

        def rim_mm(self, size, ratio):
            return replace(MeshRules(), kappa=self.rim_kappa).rim_mm(size, ratio)

    cases = (("kappa 0.8", replace(MeshRules(), kappa=0.8)), ("kappa 1.25", replace(MeshRules(), kappa=1.25)),
             ("kappa 1 kinematics, kappa-1.25 rim", RimOf(kappa=1.0, rim_kappa=1.25)),
             ("kappa 1.25 kinematics, kappa-1 rim", RimOf(kappa=1.25, rim_kappa=1.0)))
    t0 = time.process_time()
    for label, rules in cases:
        for ratio in (30.0, 50.0, 100.0):
            b = budget(rules, ratio)
            print(f"{label} ratio {ratio:g}: rim {rules.rim_mm(25, ratio):.3f} mm; K3 window compliance "
                  f"{b['full']:.3e}; predicted K3 / catalogue {b['catalogue'] / b['full']:.2f}")
    print(f"CPU {time.process_time() - t0:.1f} s")


def main_joint_table():
    """The CHA table at the ends of candidate c's bracket (the FS boss's bolted joint, interface tangential stiffness
    k_t = 1e3 / 1e4 N/mm^3 over the hub annulus, 1 / (k_t pi/2 (r_o^4 - r_i^4)): it scales as 1 / d^4, not d^3)."""
    import math
    from pathlib import Path
    from strainwave.analytic.catalogue_predict import GOALS, predict_table
    from strainwave.geometry.flexspline_cup import HUB_BORE_RATIO, HUB_RATIO

    class WithJoint(MeshRules):
        def cup_flexibility_rad_per_Nmm(self, size):
            d = self.pitch_diameter_mm(size)
            J = 0.5 * math.pi * ((HUB_RATIO * d) ** 4 - (HUB_BORE_RATIO * d) ** 4)
            return MeshRules.cup_flexibility_rad_per_Nmm(self, size) + 1.0 / (self.k_t * J)

    table = Path(__file__).resolve().parents[2] / "shared" / "data" / "cha_torsional_stiffness.csv"
    table = table if table.exists() else Path("/work/shared/data/cha_torsional_stiffness.csv")
    from strainwave.analytic import catalogue_predict
    similar = catalogue_predict.is_similar
    catalogue_predict.is_similar = lambda rules: False      # the joint is not similar (1 / d^4): solve every row
    try:
        preds = {}
        for kt in (1e3, 1e4):
            rules = WithJoint()
            object.__setattr__(rules, "k_t", kt)
            preds[kt] = predict_table(table, rules)
    finally:
        catalogue_predict.is_similar = similar
    for kt, pred in preds.items():
        counts = {n: sum(1 for rp in pred.rows if rp.ratio_of(n) is not None and abs(rp.ratio_of(n) - 1) <= g)
                  for n, g in GOALS.items()}
        k3 = [rp.ratio_of("K3_Nm_per_rad") for rp in pred.rows]
        print(f"k_t {kt:g} N/mm3: within goal {counts} of {len(pred.rows)}; K3 {min(k3):.2f}-{max(k3):.2f}; "
              f"trend {[round(t['ratio'], 2) for t in pred.trend()]}; CPU {pred.cpu_s:.1f} s")


MODES = {"": lambda: main([]), "candidates": main_candidates, "sourced": main_sourced, "mesh-split": main_mesh_split,
         "preload": main_preload, "kappa": main_kappa, "joint-table": main_joint_table}

if __name__ == "__main__":
    mode = " ".join(sys.argv[1:])
    if mode not in MODES:
        print(f"k3cause48_budget: mode {mode!r} is not one of {sorted(MODES)}", file=sys.stderr)
        sys.exit(2)
    MODES[mode]()
