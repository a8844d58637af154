"""The drive's own torque-twist curve from its tooth mesh: the loop, K1/K2/K3, T1/T2, lost motion, loss,
transmission error and ratcheting torque.

The output twist of a drive with its wave generator locked is the mesh's twist (mesh_contact on the
system of mesh_drive) plus the twist of the parts in series with it (the cup's tube; the output shaft where
the drive has one), each linear: theta = theta_mesh(T) + T lambda_series. The catalogue's numbers are read
from the simulated loop by the same reader a recording goes through (compare/diagnose/catalogue_values.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.mesh_contact import MeshPath, solve_torque_path, torque_history
from strainwave.analytic.mesh_drive import MeshDesign, bearing_twist_rad, mesh_system

__all__ = ["DriveCurve", "predict_curve", "read_catalogue_numbers", "transmission_error_rad",
           "ratcheting_torque_Nm", "LOOP_STEPS_PER_LEG"]

LOOP_STEPS_PER_LEG = 60          # torque steps from 0 to the rated torque (the reader needs >= 20 steady rows)
ARCMIN = math.pi / (180.0 * 60.0)


@dataclass(frozen=True)
class DriveCurve:
    """A drive's predicted stiffness curve and loop (SI: N m, rad), field names as diagnose's DriveCurve."""

    K1_Nm_per_rad: float
    K2_Nm_per_rad: float
    K3_Nm_per_rad: float
    T1_Nm: float
    T2_Nm: float
    lost_motion_rad: float
    hysteresis_rad: float
    rated_torque_Nm: float
    loop_torque_Nm: np.ndarray
    loop_twist_rad: np.ndarray
    te_angle_rad: np.ndarray = None          # wave-generator angles of the transmission error
    te_rad: np.ndarray = None                # output twist at the rated torque minus its mean, per angle
    ratcheting_torque_Nm: float = float("nan")
    teeth_in_contact: np.ndarray = None      # pairs in contact along the loop
    source: str = "tooth-mesh closed form (analytic/drive_curve.py)"

    def twist_rad(self, T_Nm, direction) -> np.ndarray:
        """The loop's loading (+1) or unloading (-1) branch at torque ``T_Nm`` (steady loop, after the peak)."""
        T, th = self.loop_torque_Nm, self.loop_twist_rad
        k0 = int(np.argmax(T))
        T, th = T[k0:], th[k0:]
        rate = np.sign(np.gradient(T))
        T_in = np.asarray(T_Nm, float)
        d = np.broadcast_to(np.sign(np.asarray(direction, float)), T_in.shape)
        out = np.empty(T_in.shape)
        for sgn in (1.0, -1.0):
            on = rate == sgn
            order = np.argsort(T[on], kind="stable")
            sel = d == sgn if sgn > 0 else d <= 0
            out[sel] = np.interp(T_in[sel], T[on][order], th[on][order])
        return out


def _loop(design: MeshDesign, series_rad_per_Nmm: float, rated_Nm: float, psi_rad: float) -> tuple[np.ndarray, np.ndarray, MeshPath]:
    system, _ = mesh_system(design, psi_rad)
    T = torque_history(1e3 * rated_Nm, LOOP_STEPS_PER_LEG)
    path = solve_torque_path(system, T)
    return 1e-3 * T, path.twist_rad + T * series_rad_per_Nmm + bearing_twist_rad(design, T), path


def read_catalogue_numbers(T_Nm: np.ndarray, twist_rad: np.ndarray, rated_Nm: float) -> dict:
    """name -> (value, se, unit) read from a loop by compare/diagnose/catalogue_values (K in N m/rad)."""
    from strainwave.compare.diagnose.catalogue_values import catalogue_values
    from strainwave.compare.diagnose.context import find_segments, reversal_threshold
    from strainwave.compare.diagnose.effects.base import Context
    X = float(np.max(np.abs(T_Nm)))
    slope = X / max(float(np.ptp(twist_rad)), 1e-30)
    Y = X / slope
    u = np.asarray(T_Nm) / X
    segments = find_segments(u, reversal_threshold(u))
    direction = np.empty(len(u))
    for start, stop, d in segments:
        direction[start:stop] = d
    ctx = Context(u=u, y=np.asarray(twist_rad) / Y, t=np.linspace(0.0, 1.0, len(u)), X=X, Y=Y, c0=1.0 / slope,
                  load_unit="N*m", response_unit="rad", direction=direction, segments=tuple(segments))
    cv = catalogue_values(ctx, rated_Nm)
    if cv is None:
        raise ValueError("the simulated loop has no steady branch to read")
    return cv.values


def transmission_error_rad(design: MeshDesign, series_rad_per_Nmm: float, torque_Nm: float,
                           n_angles: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(wave-generator angles over one revolution, output twist at ``torque_Nm`` minus its mean there):
    the loaded transmission error the discrete teeth make as they pass through the engagement zone.
    Default: 4 angles per tooth passing (Z_f passings per revolution), so the mesh order is not aliased."""
    n_angles = 4 * design.geometry.teeth_flexspline if n_angles is None else n_angles
    psi = np.linspace(0.0, 2.0 * math.pi, n_angles, endpoint=False)
    T = 1e3 * torque_Nm * np.linspace(0.0, 1.0, 6)
    tw = np.array([solve_torque_path(mesh_system(design, p)[0], T).twist_rad[-1] for p in psi])
    tw = tw + T[-1] * series_rad_per_Nmm
    return psi, tw - tw.mean()


def ratcheting_torque_Nm(design: MeshDesign, psi_rad: float = 0.0) -> float:
    """The torque at which the teeth climb out: the flank forces' radial push F sin(alpha) lifts the flexspline
    inward against the wave generator's radial spring (lobe K_G and the rim on its bearing, the compliance's
    radial part) until the radial lift equals the tip overlap at the major axis (working depth 2 h_a m).

    The mesh forces at a unit torque give the radial lift per N mm (linear in the contact set reached at the
    rated torque); the ratcheting torque is overlap / lift-per-torque."""
    from strainwave.analytic import mesh_compliance as mc
    g = design.geometry
    system, tooth = mesh_system(design, psi_rad)
    T_probe = 1e3 * 0.25 * design.K_G_N_per_mm * g.module_mm * g.pitch_radius_mm * 1e-3
    path = solve_torque_path(system, np.linspace(0.0, T_probe, 8))
    F = path.forces_N[-1]
    from strainwave.analytic.mesh_kinematics import teeth_on_neutral_line
    ang = teeth_on_neutral_line(g, psi_rad).angle_rad[tooth]
    d = np.abs(ang[:, None] - ang[None, :])
    arc = g.neutral_radius_mm * np.minimum(d, 2.0 * math.pi - d)
    G = mc.rim_on_foundation_green_mm_per_N(arc, design.E_MPa, design.rim_I_mm4, design.foundation_N_per_mm2)
    sa = math.sin(math.radians(g.pressure_angle_deg))
    lift = G @ (sa * F) + sa * F.sum() / 2.0 / design.K_G_N_per_mm     # per lobe: half the teeth
    lift_per_Nmm = float(np.max(lift)) / T_probe
    overlap = 2.0 * g.addendum_coefficient * g.module_mm
    return 1e-3 * overlap / lift_per_Nmm if lift_per_Nmm > 0 else float("inf")


def predict_curve(design: MeshDesign, series_rad_per_Nmm: float, rated_Nm: float, *, psi_rad: float = 0.0,
                  with_te: bool = True) -> DriveCurve:
    """The drive's curve: the loop 0 -> +rated -> -rated -> +rated at wave-generator angle ``psi_rad`` read by
    the catalogue reader, the transmission error over a revolution and the ratcheting torque."""
    T, tw, path = _loop(design, series_rad_per_Nmm, rated_Nm, psi_rad)
    v = read_catalogue_numbers(T, tw, rated_Nm)
    te = transmission_error_rad(design, series_rad_per_Nmm, rated_Nm) if with_te else (None, None)
    return DriveCurve(v["K1"][0], v["K2"][0], v["K3"][0], v["T1"][0], v["T2"][0],
                      v["lost_motion_arcmin"][0] * ARCMIN, v["hysteresis_loss_arcmin"][0] * ARCMIN, rated_Nm,
                      T, tw, te[0], te[1], ratcheting_torque_Nm(design, psi_rad), path.contact.sum(axis=1))
