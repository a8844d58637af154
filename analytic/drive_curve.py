"""The drive's own torque-twist curve from its tooth mesh: the loop, K1/K2/K3, T1/T2, lost motion, loss,
transmission error and ratcheting torque.

The output twist of a drive with its wave generator locked is the mesh's twist (mesh_contact on the
system of mesh_drive) plus the twist of the parts in series with it (the cup's tube; the output shaft where
the drive has one), each linear: theta = theta_mesh(T) + T lambda_series. The catalogue's numbers are read
from the simulated loop by the same reader a recording goes through (compare/diagnose/catalogue_values.py);
the catalogue's paths, the shipped gear's chain and diagnose's drive curve (``exact=True``) read the mesh's exact
loop on a fixed torque grid, so their numbers do not depend on the solve's torque step (decisions 074, 076).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea import mesh_loop
from strainwave.fea.mesh_contact import MeshPath, solve_torque_path, torque_history
from strainwave.analytic.mesh_drive import MeshDesign, bearing_twist_rad, mesh_system

__all__ = ["DriveCurve", "predict_curve", "branch_twist_rad", "mean_twist_rad", "catalogue_secants",
           "read_catalogue_numbers", "transmission_error_rad", "ratcheting_torque_Nm", "LOOP_STEPS_PER_LEG",
           "predict_mean_curve", "unit_curves", "mean_curve", "curve_from_loop", "READ_STEPS_PER_LEG"]

LOOP_STEPS_PER_LEG = 60          # torque steps from 0 to the rated torque (the reader needs >= 20 steady rows)
# the exact loop's fixed reading grid, a leg (decision 074: the study's, so neither reading follows the solve's step)
READ_STEPS_PER_LEG = mesh_loop.READ_STEPS_PER_LEG
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
    teeth_in_contact: np.ndarray = None      # pairs in contact at the solve's torque steps (path order)
    source: str = "tooth-mesh closed form (analytic/drive_curve.py)"
    dead_band_rad: tuple = (0.0, 0.0)        # the mesh's backlash band (theta-, theta+), out of the knees (decision 073)

    def twist_rad(self, T_Nm, direction) -> np.ndarray:
        """The loop's loading (+1) or unloading (-1) branch at torque ``T_Nm`` (steady loop, after the peak)."""
        return branch_twist_rad(self.loop_torque_Nm, self.loop_twist_rad, T_Nm, direction)


def branch_twist_rad(loop_T_Nm, loop_twist_rad, T_Nm, direction) -> np.ndarray:
    """A loop's loading (+1) or unloading (-1) branch at torque ``T_Nm`` (the steady loop after the first peak)."""
    T, th = np.asarray(loop_T_Nm, float), np.asarray(loop_twist_rad, float)
    k0 = int(np.argmax(T))
    T, th = T[k0:], th[k0:]
    step = np.sign(np.diff(T))
    T_in = np.asarray(T_Nm, float)
    d = np.broadcast_to(np.sign(np.asarray(direction, float)), T_in.shape)
    out = np.empty(T_in.shape)
    for sgn in (1.0, -1.0):
        # a reversal point ends one branch and starts the next: on both (the loop's tip is the curve's end)
        on = np.concatenate([[False], step == sgn]) | np.concatenate([step == sgn, [False]])
        order = np.argsort(T[on], kind="stable")
        sel = d == sgn if sgn > 0 else d <= 0
        out[sel] = np.interp(T_in[sel], T[on][order], th[on][order])
    return out


def mean_twist_rad(loop_T_Nm, loop_twist_rad, T_Nm) -> np.ndarray:
    """The catalogue's curve: the mean of the steady loop's loading and unloading branches at ``T_Nm``."""
    T_in = np.asarray(T_Nm, float)
    return 0.5 * (branch_twist_rad(loop_T_Nm, loop_twist_rad, T_in, np.ones(T_in.shape))
                  + branch_twist_rad(loop_T_Nm, loop_twist_rad, T_in, -np.ones(T_in.shape)))


def catalogue_secants(loop_T_Nm, loop_twist_rad, T1_Nm: float, T2_Nm: float) -> dict:
    """K1, K2, K3 (N m/rad) as the catalogue defines them (CHA manual 1018854 eq. 68.1-68.4, decision 069): the
    secant slopes of the mean curve over 0-T1, T1-T2 and T2 to the loop's amplitude, at the given limit torques."""
    A = float(np.max(loop_T_Nm))
    if not 0.0 < T1_Nm < T2_Nm < A:
        raise ValueError(f"the windows need 0 < T1 < T2 < amplitude: {T1_Nm:g}, {T2_Nm:g}, {A:g} N m")
    phi = mean_twist_rad(loop_T_Nm, loop_twist_rad, np.array([0.0, T1_Nm, T2_Nm, A]))
    return {"K1_Nm_per_rad": T1_Nm / (phi[1] - phi[0]), "K2_Nm_per_rad": (T2_Nm - T1_Nm) / (phi[2] - phi[1]),
            "K3_Nm_per_rad": (A - T2_Nm) / (phi[3] - phi[2])}


def _loop(design: MeshDesign, series_rad_per_Nmm: float, rated_Nm: float, psi_rad: float,
          exact: bool = False) -> tuple[np.ndarray, np.ndarray, MeshPath]:
    """(torque N m, twist rad, the mesh's path) of the loop 0 -> +rated -> -rated -> +rated. ``exact``: the mesh's
    exact piecewise-linear loop (its knots) sampled on ``READ_STEPS_PER_LEG`` torques a leg, the series members and
    the balls' twist (functions of the torque alone) added there: the loop no longer depends on the solve's step
    (decision 074); else the solve's own ``LOOP_STEPS_PER_LEG`` steps."""
    system, _ = mesh_system(design, psi_rad)
    T = torque_history(1e3 * rated_Nm, LOOP_STEPS_PER_LEG)
    path = solve_torque_path(system, T)
    tw = path.twist_rad
    if exact:
        T, tw = mesh_loop.resample(*mesh_loop.exact_loop(path), READ_STEPS_PER_LEG)
    return 1e-3 * T, tw + T * series_rad_per_Nmm + bearing_twist_rad(design, T), path


def read_catalogue_numbers(T_Nm: np.ndarray, twist_rad: np.ndarray, rated_Nm: float,
                           dead_band_rad: tuple = (0.0, 0.0)) -> dict:
    """name -> (value, se, unit) read from a loop by compare/diagnose/catalogue_values (K in N m/rad); with a
    backlash band the knees K1-K3, T1, T2 are read on the twist with the band taken out (decision 073), the rest
    on the raw twist."""
    if tuple(dead_band_rad) != (0.0, 0.0):
        knees = read_catalogue_numbers(T_Nm, mesh_loop.elastic_twist(twist_rad, dead_band_rad), rated_Nm)
        return {**read_catalogue_numbers(T_Nm, twist_rad, rated_Nm),
                **{k: knees[k] for k in ("K1", "K2", "K3", "T1", "T2")}}
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


def curve_from_loop(T_Nm: np.ndarray, twist_rad: np.ndarray, rated_Nm: float, *, dead_band_rad: tuple = (0.0, 0.0),
                    **fields) -> DriveCurve:
    """A loop read by the catalogue reader into a DriveCurve (``fields``: the DriveCurve's optional fields)."""
    v = read_catalogue_numbers(T_Nm, twist_rad, rated_Nm, dead_band_rad)
    return DriveCurve(v["K1"][0], v["K2"][0], v["K3"][0], v["T1"][0], v["T2"][0],
                      v["lost_motion_arcmin"][0] * ARCMIN, v["hysteresis_loss_arcmin"][0] * ARCMIN, rated_Nm,
                      T_Nm, twist_rad, dead_band_rad=tuple(dead_band_rad), **fields)


def predict_curve(design: MeshDesign, series_rad_per_Nmm: float, rated_Nm: float, *, psi_rad: float = 0.0,
                  with_te: bool = True, exact: bool = False) -> DriveCurve:
    """The drive's curve: the loop 0 -> +rated -> -rated -> +rated at wave-generator angle ``psi_rad`` read by
    the catalogue reader, the transmission error over a revolution and the ratcheting torque. ``exact``: the
    loop is the exact one on the fixed reading grid (decision 074; the catalogue's), else the solve's steps."""
    T, tw, path = _loop(design, series_rad_per_Nmm, rated_Nm, psi_rad, exact)
    te = transmission_error_rad(design, series_rad_per_Nmm, rated_Nm) if with_te else (None, None)
    return curve_from_loop(T, tw, rated_Nm, dead_band_rad=path.dead_band_rad if exact else (0.0, 0.0),
                           te_angle_rad=te[0], te_rad=te[1],
                           ratcheting_torque_Nm=ratcheting_torque_Nm(design, psi_rad),
                           teeth_in_contact=path.contact.sum(axis=1))


def unit_curves(designs, series_rad_per_Nmm: float, rated_Nm: float, *, psi_rad: float = 0.0,
                exact: bool = False) -> list[DriveCurve]:
    """Each unit's curve alone (its loop read by the catalogue reader; no transmission error or ratcheting)."""
    out = []
    for d in designs:
        T, tw, path = _loop(d, series_rad_per_Nmm, rated_Nm, psi_rad, exact)
        out.append(curve_from_loop(T, tw, rated_Nm, dead_band_rad=path.dead_band_rad if exact else (0.0, 0.0),
                                   teeth_in_contact=path.contact.sum(axis=1), source="one unit"))
    return out


def mean_curve(units: list[DriveCurve], ratcheting_Nm: float = float("nan")) -> DriveCurve:
    """The units' loops (same torque history) averaged twist by twist, read by the catalogue reader: the
    catalogue's values are averages of many tests (decision 070-engage48). The backlash band: the units'
    narrowest on each side (zero on every unit the catalogue's rules make)."""
    if not units:
        raise ValueError("mean_curve needs at least one unit")
    T, rated = units[0].loop_torque_Nm, units[0].rated_torque_Nm
    tw = np.mean([u.loop_twist_rad for u in units], axis=0)
    teeth = np.mean([u.teeth_in_contact for u in units], axis=0)
    band = (max(u.dead_band_rad[0] for u in units), min(u.dead_band_rad[1] for u in units))
    return curve_from_loop(T, tw, rated, dead_band_rad=band, ratcheting_torque_Nm=ratcheting_Nm,
                           teeth_in_contact=teeth,
                           source=f"tooth-mesh closed form, mean of {len(units)} units with tooth deviations")


def predict_mean_curve(designs, series_rad_per_Nmm: float, rated_Nm: float, *, psi_rad: float = 0.0,
                       exact: bool = False) -> DriveCurve:
    """The mean curve of several units of one design (each with its own tooth deviations, decision 070-engage48);
    no transmission error; the ratcheting torque of the first unit."""
    designs = list(designs)
    if not designs:
        raise ValueError("predict_mean_curve needs at least one design")
    units = unit_curves(designs, series_rad_per_Nmm, rated_Nm, psi_rad=psi_rad, exact=exact)
    return mean_curve(units, ratcheting_torque_Nm(designs[0], psi_rad))
