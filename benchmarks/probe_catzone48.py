"""Decision 075-catzone48: how much of the catalogue's cup-zone term the reduced mesh model's rim already holds.

For the rules' size-25 drives at i = 30 / 50 / 100, under the mesh model's own flank loads at the rated torque:
the 3D wall's extra over the uniform shear (gross, decision 067's term), the plane annulus's extra (the rim's plane
body), and the reduced model's rim-rotation term on the same loads, with the kernel shipped until decision 077
(Hetenyi's D) and with Hetenyi's rotation under a couple (C, shipped since 077), each also net of a uniform load on
every tooth.
Usage: python benchmarks/probe_catzone48.py [ELEMENTS_ROUND_THE_QUARTER=10]   (~6 CPU-s at 10)
"""
import math
import sys
import time

import numpy as np

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cup_zone import teeth_rated_loads
from strainwave.fea import cup_zone_load as cz
from strainwave.fea import drive_assembled as da
from strainwave.fea.assembly import Lame


def rim_rotation_work(design, phi, sign, F, kernel: str) -> float:
    """W / T^2 of the reduced model's rim-rotation term (mesh_compliance) on pairs at ``phi`` with forces F."""
    g = design.geometry
    a = math.radians(g.pressure_angle_deg)
    hc = (g.pitch_radius_mm - g.neutral_radius_mm) * math.cos(a)
    k = design.foundation_N_per_mm2
    beta = (k / (4.0 * design.E_MPa * design.rim_I_mm4)) ** 0.25
    d = np.abs(phi[:, None] - phi[None, :])
    x = beta * g.neutral_radius_mm * np.minimum(d, 2.0 * math.pi - d)
    shape = np.exp(-x) * (np.cos(x) - (np.sin(x) if kernel == "C" else 0.0))
    G = hc * hc * np.outer(sign, sign) * beta ** 3 / k * shape
    lever = sign * g.pitch_radius_mm * math.cos(a)
    return float(F @ G @ F) / float(lever @ F) ** 2


def main(n: int) -> None:
    rules = MeshRules()
    for ratio in (30, 50, 100):
        t0 = time.process_time()
        d = rules.design(25, ratio)
        g = d.geometry
        phi, lever, F = teeth_rated_loads(d, 1e3 * rules.rated_torque_Nm(25))
        geo = cz.tube_of_design(d)
        lame = Lame.from_young(d.E_MPa, 0.3)
        out = da.zone_terms(geo, n, lame, g.w0_mm, phi, lever, F, g.face_width_mm)
        annulus = out["gross"] - out["net"]
        z = g.teeth_flexspline
        every = 2.0 * math.pi * np.arange(z) / z
        red = {kern: (rim_rotation_work(d, phi, np.sign(lever), F, kern),
                      rim_rotation_work(d, every, np.ones(z), np.ones(z), kern)) for kern in "DC"}
        line = ", ".join(f"rim term {kern} {w:.3e} (net of uniform {w - u:.3e}, {(w - u) / annulus:.2f} of the annulus)"
                         for kern, (w, u) in red.items())
        print(f"i = {ratio}: gross {out['gross']:.3e}, plane annulus {annulus:.3e}, net {out['net']:.3e}; {line} "
              f"({time.process_time() - t0:.1f} CPU-s)", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
