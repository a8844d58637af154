import math, sys, time
import numpy as np
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.mesh_drive import mesh_system
from strainwave.analytic.mesh_kinematics import teeth_on_neutral_line
from strainwave.analytic import mesh_compliance as mc
from strainwave.fea.mesh_contact import solve_torque_path
from strainwave.fea import drive_assembled as da, cup_zone_load as cz
from strainwave.fea.assembly import Lame

rules = MeshRules()
n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
for ratio in (30, 50, 100):
    t0 = time.process_time()
    d = rules.design(25, ratio); g = d.geometry
    T = 1e3 * rules.rated_torque_Nm(25)
    system, tooth = mesh_system(d, 0.0)
    F = solve_torque_path(system, np.linspace(0, T, 11)).forces_N[-1]
    on = F > 0
    ang = teeth_on_neutral_line(g, 0.0).angle_rad[tooth]
    L = system.lever_mm
    Ff, Lf, af = F[on], L[on], ang[on]
    sgn = np.sign(Lf)
    geo = cz.tube_of_design(d)
    lame = Lame.from_young(d.E_MPa, 0.3)
    H = 6
    wall = da.wall_modes(geo, n, lame, g.w0_mm, H)
    g2 = da.annulus_modes(geo.r_i_mm, geo.r_o_mm, g.face_width_mm, 0.5 * geo.wall_mm, lame, H)
    P = da.mode_map(af, -Lf / geo.r_o_mm, H)
    Tq = float(Lf @ Ff)
    work = lambda G: float(Ff @ G @ Ff) / Tq ** 2
    uni3 = wall["g"][0, 0] / (2 * math.pi * geo.r_o_mm) ** 2
    uni2 = g2[0, 0] / (2 * math.pi * geo.r_o_mm) ** 2
    gross = work(P.T @ wall["g"] @ P) - uni3
    ann = work(P.T @ g2 @ P) - uni2
    # reduced model's rim moment term on the loaded pairs, and under a uniform load on every tooth
    alpha = math.radians(g.pressure_angle_deg)
    hc = (g.pitch_radius_mm - g.neutral_radius_mm) * math.cos(alpha)
    def Mwork(a, s, f):
        dd = np.abs(a[:, None] - a[None, :]); arc = g.neutral_radius_mm * np.minimum(dd, 2 * math.pi - dd)
        M = mc.rim_moment_green_rad_per_Nmm(arc, d.E_MPa, d.rim_I_mm4, d.foundation_N_per_mm2)
        G = hc * hc * np.outer(s, s) * M
        lev = s * g.pitch_radius_mm * math.cos(alpha)
        return float(f @ G @ f) / float(lev @ f) ** 2
    red = Mwork(af, sgn, Ff)
    Z = g.teeth_flexspline
    au = 2 * math.pi * np.arange(Z) / Z
    redu = Mwork(au, np.ones(Z), np.ones(Z))
    # the reduced model's whole work on its loaded pairs
    Cfull = system.compliance if hasattr(system, "compliance") else None
    print(f"i={ratio} n={n} teeth={on.sum()} rim={g.rim_thickness_mm:.3f} m={g.module_mm:.3f} hc={hc:.3f} "
          f"gross={gross:.3e} annulus_net={ann:.3e} net={gross-ann:.3e} red_moment={red:.3e} red_uniform={redu:.3e} "
          f"red_net={red-redu:.3e} uni3={uni3:.3e} uni2={uni2:.3e} held={wall['held_fraction']:.3f} cpu={time.process_time()-t0:.1f}", flush=True)
