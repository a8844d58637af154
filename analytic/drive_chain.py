"""K_HD as the drive carries torque (issue 48, item 4): the tooth mesh, the flexspline cup, the wave generator
and the output shaft in series.

The wave generator's radial springs (its lobe K_G and the bearing under the rim) sit inside the mesh model: a
flank force's radial part lifts the flexspline off the CS teeth, so they are not a separate lambda_H term (seed
000's lambda_H, whose relation the seed never derives, is replaced). The mesh is nonlinear: its compliance is
read as the secant of the mesh twist between T2 and the rated torque (the catalogue's K3 range) and at 0..T1 (K1).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.analytic.drive_curve import DriveCurve, predict_curve
from strainwave.analytic.mesh_drive import design_from_params

__all__ = ["DriveChain", "drive_chain"]


@dataclass(frozen=True)
class DriveChain:
    """Flexibilities in rad/(N mm); K in N mm/rad."""

    mesh_working: float          # secant of the mesh alone from T2 to the rated torque
    mesh_low_torque: float          # secant of the mesh alone from 0 to T1 (after the clearance)
    cup: float                    # tube + diaphragm + hub (series shell model, corrected)
    shaft: float                  # hollow output shaft (corrected)
    curve: DriveCurve             # the whole drive's curve (mesh + cup + shaft), read as the catalogue reads

    @property
    def K_HD_Nmm_per_rad(self) -> float:
        """The drive at working torque (the K3 range): 1 / (lambda_mesh + lambda_cup + lambda_shaft)."""
        return 1.0 / (self.mesh_working + self.cup + self.shaft)

    def shares(self) -> dict:
        total = self.mesh_working + self.cup + self.shaft
        return {"mesh": self.mesh_working / total, "cup": self.cup / total, "shaft": self.shaft / total}


def _secant(T: np.ndarray, twist: np.ndarray, lo: float, hi: float) -> float:
    """d(twist)/dT by least squares on the first loading between torques lo and hi (rad per unit T)."""
    k0 = int(np.argmax(T))
    sel = (T[:k0 + 1] >= lo) & (T[:k0 + 1] <= hi)
    return float(np.polyfit(T[:k0 + 1][sel], twist[:k0 + 1][sel], 1)[0])


def drive_chain(params, *, exact: bool = True) -> DriveChain:
    """The shipped drive's chain at its rated torque. ``exact``: the mesh's exact loop on the fixed reading grid,
    its knees read with the backlash's dead band out (decisions 073, 074, 076-exactdrive48), so no reading follows the solve's step;
    False: the solve's own steps (the reading before decision 076, kept for the comparison)."""
    from strainwave.compare.diagnose.drive_baseline import drive_series_flexibility_rad_per_Nmm
    from strainwave.analytic import torsion as tor
    from strainwave.analytic.seed000 import cup_series_model
    from strainwave.analytic.variant import Variant
    G = params.material.implied_shear_modulus_MPa
    sh = params.output_shaft
    shaft = tor.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G, Variant.CORRECTED)
    cup = cup_series_model(params, G).total
    rated = 1e-3 * params.gear.rated_output_torque_Nmm
    design = design_from_params(params)
    from threadpoolctl import threadpool_limits
    with threadpool_limits(limits=1):       # the reader's small dense solves: BLAS threads only spin (decision 071)
        mesh_only = predict_curve(design, 0.0, rated, with_te=False, exact=exact)
        curve = predict_curve(design, drive_series_flexibility_rad_per_Nmm(params), rated, with_te=False,
                              exact=exact)
    T, tw = 1e3 * mesh_only.loop_torque_Nm, mesh_only.loop_twist_rad
    k3 = _secant(T, tw, 1e3 * mesh_only.T2_Nm, 1e3 * rated)
    k1 = _secant(T, tw, 0.02 * 1e3 * rated, 1e3 * max(mesh_only.T1_Nm, 0.1 * rated))
    return DriveChain(k3, k1, cup, shaft, curve)
