"""`diagnose --baseline fea` for a drive (specimen "gear"): the tooth-mesh study's predicted curve, not a line.

The drive's predicted loop (``fea_drive_curve``: the FE tooth-mesh study's frictional contact on its quick
meshes, in series with the cup, the output shaft and the wave generator; ``predicted_drive_curve`` is the
closed-form mesh of analytic/drive_curve, item 4 of issue 48) stiffens and has a loop. The diagnosis works against a linear baseline, so
the curve enters as a correction of the recording: each sample's twist less the curve's departure from its own
secant line at that torque and direction (loading or unloading branch). A recording of the predicted drive is
then exactly linear (it "agrees"); what remains is what the model lacks, e.g. more lost motion than predicted.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.context import find_segments, reversal_threshold
from strainwave.compare.diagnose.recording import Recording
from threadpoolctl import threadpool_limits

__all__ = ["predicted_drive_curve", "fea_drive_curve", "drive_series_flexibility_rad_per_Nmm", "curve_baseline",
           "study_loop"]

def drive_series_flexibility_rad_per_Nmm(params) -> float:
    """The parts in series with the mesh: the cup (tube + diaphragm + hub) and the output shaft (corrected)."""
    from strainwave.analytic import torsion as tor
    from strainwave.analytic.seed000 import cup_series_model
    from strainwave.analytic.variant import Variant
    G = params.material.implied_shear_modulus_MPa
    sh = params.output_shaft
    shaft = tor.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G, Variant.CORRECTED)
    return cup_series_model(params, G).total + shaft


def predicted_drive_curve(params, *, exact: bool = True):
    """The drive's predicted curve at its rated torque (about 0.3 CPU-s). ``exact``: the mesh's exact loop on the
    fixed reading grid, the knees read with the backlash's dead band out (decision 076); False: the solve's steps."""
    from strainwave.analytic.drive_curve import predict_curve
    from strainwave.analytic.mesh_drive import design_from_params
    with threadpool_limits(limits=1):       # the reader's small dense solves: BLAS threads only spin (decision 071)
        return predict_curve(design_from_params(params), drive_series_flexibility_rad_per_Nmm(params),
                             1e-3 * params.gear.rated_output_torque_Nmm, with_te=False, exact=exact)


def fea_drive_curve(params, *, exact: bool = True, result=None):
    """(the drive's curve from the FE tooth-mesh study, its relative discretization uncertainty): the study's
    loop on its finest quick mesh (the flexspline's toothed rim and the circular spline's teeth in frictional
    contact, wave generator rigid) in series with the cup, the output shaft and the wave generator's radial
    spring (lambda_H of seed 000's form, K_G from Stribeck-Hertz), as gear.catalogue_stiffness's chain.
    ``exact``: the study's exact loop with its knees read past the backlash band (``study_loop``); ``result``: the
    study's result when already run."""
    from strainwave.analytic import torsion
    from strainwave.analytic.drive_curve import ARCMIN, DriveCurve, read_catalogue_numbers
    from strainwave.compare.validate.wg_bearing_checks import stribeck_radial_stiffness_N_per_mm
    from strainwave.fea.studies import run_study
    result = run_study("tooth-mesh", params, quick=True) if result is None else result
    g, cup = params.gear, params.flexspline_cup
    lam_H = torsion.wave_generator_flexibility(g.force_coefficient, stribeck_radial_stiffness_N_per_mm(params),
                                               cup.pitch_diameter_mm, g.wave_number, g.radial_deformation_mm,
                                               g.gear_ratio)
    T_Nmm, mesh_twist, band = study_loop(result.meta, exact)
    twist = mesh_twist + T_Nmm * (drive_series_flexibility_rad_per_Nmm(params) + lam_H)
    rated = 1e-3 * params.gear.rated_output_torque_Nmm
    with threadpool_limits(limits=1):       # the reader's small dense solves: BLAS threads only spin (decision 071)
        v = read_catalogue_numbers(1e-3 * T_Nmm, twist, rated, band)
    q = result.quantities["secant_stiffness_rated_Nmm_per_rad"]
    k_peak = int(np.argmax(T_Nmm))
    mesh_share = (T_Nmm[k_peak] / q.value) / twist[k_peak]        # the mesh's part of the drive's twist at rated
    curve = DriveCurve(v["K1"][0], v["K2"][0], v["K3"][0], v["T1"][0], v["T2"][0],
                       v["lost_motion_arcmin"][0] * ARCMIN, v["hysteresis_loss_arcmin"][0] * ARCMIN, rated,
                       1e-3 * T_Nmm, twist, source="FE study tooth-mesh (quick meshes) + cup + shaft + wave generator",
                       dead_band_rad=band)
    return curve, mesh_share * (q.uncertainty or 0.0) / q.value


def study_loop(meta: dict, exact: bool = True) -> tuple[np.ndarray, np.ndarray, tuple]:
    """(torque N mm, mesh twist rad, backlash band) of the tooth-mesh study's headline loop: its exact loop (the
    solver's knots) on the fixed reading grid, so no reading follows the study's torque step (decision 076); the
    history's own steps, raw twist, where the study gave no knots or ``exact`` is False (the reading before)."""
    from strainwave.fea import mesh_loop
    knots = meta.get("loop_knots")
    if not exact or knots is None:
        return np.asarray(meta["loop"]["torque_Nmm"], float), np.asarray(meta["loop"]["twist_rad"], float), (0.0, 0.0)
    knots = np.asarray(knots, float)
    T, th = mesh_loop.resample(knots[:, 0], knots[:, 1], mesh_loop.READ_STEPS_PER_LEG)
    return T, th, tuple(float(b) for b in meta.get("dead_band_rad", (0.0, 0.0)))


def _directions(load: np.ndarray) -> np.ndarray:
    u = load / max(float(np.max(np.abs(load))), 1e-300)
    d = np.ones(len(u))
    for start, stop, sgn in find_segments(u, reversal_threshold(u)):
        d[start:stop] = sgn
    return d


def curve_baseline(rec: Recording, params, source: str = "analytic") -> tuple[Baseline, Recording]:
    """(the curve's secant as the linear baseline, the recording less the curve's departure from it); ``source``
    "fea": the FE tooth-mesh study's curve (``fea_drive_curve``), "analytic": the closed-form mesh's."""
    curve, unc = fea_drive_curve(params) if source == "fea" else (predicted_drive_curve(params), 0.0)
    T = curve.loop_torque_Nm
    k0 = int(np.argmax(T))
    c0_Nm = float(np.polyfit(T[k0:], curve.loop_twist_rad[k0:], 1)[0])       # rad per N m, over the steady loop
    T_rec = 1e-3 * rec.load                                                     # N mm -> N m
    departure = curve.twist_rad(T_rec, _directions(rec.load)) - c0_Nm * T_rec
    corrected = dataclasses.replace(rec, response=rec.response - departure)
    base = Baseline(1e-3 * c0_Nm, "rad/(N*mm)", math.hypot(rec.baseline_uncertainty, unc),
                    f"{curve.source}: drive curve (K1 {curve.K1_Nm_per_rad:.4g}, K3 {curve.K3_Nm_per_rad:.4g} N m/rad, "
                    f"lost motion {curve.lost_motion_rad:.3g} rad): its stiffening and loop taken out of the "
                    f"recording, its secant the baseline", {})
    return base, corrected
