"""`diagnose --baseline fea` for a drive (specimen "gear"): the tooth-mesh model's predicted curve, not a line.

The drive's predicted loop (analytic/drive_curve: the mesh's frictional contact in series with the cup and the
output shaft, item 4 of issue 48) stiffens and has a loop. The diagnosis works against a linear baseline, so
the curve enters as a correction of the recording: each sample's twist less the curve's departure from its own
secant line at that torque and direction (loading or unloading branch). A recording of the predicted drive is
then exactly linear (it "agrees"); what remains is what the model lacks, e.g. more lost motion than predicted.
"""
from __future__ import annotations

import dataclasses
import numpy as np

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.context import find_segments, reversal_threshold
from strainwave.compare.diagnose.recording import Recording

__all__ = ["predicted_drive_curve", "drive_series_flexibility_rad_per_Nmm", "curve_baseline"]

def drive_series_flexibility_rad_per_Nmm(params) -> float:
    """The parts in series with the mesh: the cup (tube + diaphragm + hub) and the output shaft (corrected)."""
    from strainwave.analytic import torsion as tor
    from strainwave.analytic.seed000 import cup_series_model
    from strainwave.analytic.variant import Variant
    G = params.material.implied_shear_modulus_MPa
    sh = params.output_shaft
    shaft = tor.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G, Variant.CORRECTED)
    return cup_series_model(params, G).total + shaft


def predicted_drive_curve(params):
    """The drive's predicted curve at its rated torque (about 0.2 CPU-s)."""
    from strainwave.analytic.drive_curve import predict_curve
    from strainwave.analytic.mesh_drive import design_from_params
    return predict_curve(design_from_params(params), drive_series_flexibility_rad_per_Nmm(params),
                         1e-3 * params.gear.rated_output_torque_Nmm, with_te=False)


def _directions(load: np.ndarray) -> np.ndarray:
    u = load / max(float(np.max(np.abs(load))), 1e-300)
    d = np.ones(len(u))
    for start, stop, sgn in find_segments(u, reversal_threshold(u)):
        d[start:stop] = sgn
    return d


def curve_baseline(rec: Recording, params) -> tuple[Baseline, Recording]:
    """(the curve's secant as the linear baseline, the recording less the curve's departure from it)."""
    curve = predicted_drive_curve(params)
    T = curve.loop_torque_Nm
    k0 = int(np.argmax(T))
    c0_Nm = float(np.polyfit(T[k0:], curve.loop_twist_rad[k0:], 1)[0])       # rad per N m, over the steady loop
    T_rec = 1e-3 * rec.load                                                     # N mm -> N m
    departure = curve.twist_rad(T_rec, _directions(rec.load)) - c0_Nm * T_rec
    corrected = dataclasses.replace(rec, response=rec.response - departure)
    base = Baseline(1e-3 * c0_Nm, "rad/(N*mm)", rec.baseline_uncertainty,
                    f"tooth-mesh drive curve (K1 {curve.K1_Nm_per_rad:.4g}, K3 {curve.K3_Nm_per_rad:.4g} N m/rad, "
                    f"lost motion {curve.lost_motion_rad:.3g} rad): its stiffening and loop taken out of the "
                    f"recording, its secant the baseline", {})
    return base, corrected
