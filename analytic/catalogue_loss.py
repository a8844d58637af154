"""The catalogue's hysteresis loss and lost motion of a predicted drive, read as Harmonic Drive defines them.

Definitions (docs/decisions/070-loss48-hysteresis-and-lost-motion.md, with the pages searched):
- hysteresis loss: the drive, wave generator locked, is loaded 0 -> +T_N -> 0 -> -T_N -> 0 -> +T_N; the loss is
  the twist between the two points where the steady loop crosses zero torque (B - B' of the curve
  0-A-B-A'-B'-A): the unloading branch minus the loading branch at T = 0;
- lost motion: the same drive cycled at +/-4 % of T_N only (the manual's "measurement taken with an output
  torque of about +/-4 % of the rated torque"); the lost motion is the twist travelled between the two ends of
  that steady small loop, phi(+4 %) - phi(-4 %). On a loop cycled to +/-4 % the branches meet at its ends, so
  the end-to-end angle and the loop's centre-line angle at +/-4 % (the reading other makers state) are one number.
Bounds: the CHA table's own (HD AG 1018854, 8/2018 V03 p. 54, Tables 54.1-54.2; ../shared/tooth-mesh-references.md 1),
one rule for every size, keyed by the ratio (``cha_bounds``); a user's table may give its own per row.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.analytic.drive_curve import branch_twist_rad, mean_twist_rad
from strainwave.analytic.mesh_drive import MeshDesign, bearing_twist_rad, mesh_system
from strainwave.fea.mesh_contact import dead_band, solve_torque_path, torque_history
from strainwave.fea.mesh_loop import elastic_twist

__all__ = ["LOST_MOTION_FRACTION", "CHA_BOUNDS_SOURCE", "LossReading", "cha_bounds", "hysteresis_loss_rad",
           "lost_motion_rad", "loop_width_max_rad", "small_loop", "read_loss"]

ARCMIN = math.pi / (180.0 * 60.0)
LOST_MOTION_FRACTION = 0.04          # of the rated torque: the lost-motion test's torque (HD glossary)
SMALL_LOOP_STEPS = 20                # torque steps per leg of the +/-4 % loop (the path solve is exact at each)
CHA_BOUNDS_SOURCE = ("CHA accuracy table (HD AG 1018854, 8/2018 V03 p. 54 Tables 54.1-54.2; 12/2015 V01 p. 50 "
                     "Tables 50.1-50.2), every size: hysteresis loss < 3 arcmin at i = 30, < 1 arcmin at i >= 50; "
                     "lost motion < 1 arcmin")


def cha_bounds(ratio: float) -> tuple[float, float]:
    """(hysteresis loss, lost motion) upper bounds in arcmin the CHA table states for this ratio.
    The table lists i = 30 and i >= 50 only: a ratio below 50 takes the i = 30 bound (the looser one)."""
    return (3.0 if ratio < 50.0 else 1.0), 1.0


def _steady(T: np.ndarray) -> None:
    if not (np.any(np.diff(T) < 0.0) and np.min(T) < 0.0 < np.max(T)):
        raise ValueError("the loop needs a reversal through zero torque (0 -> +A -> -A -> +A)")


def hysteresis_loss_rad(loop_T_Nm, loop_twist_rad, dead_band_rad: tuple = (0.0, 0.0)) -> float:
    """The steady loop's width at zero torque: unloading branch (after +A) minus loading branch (after -A).
    With free play (the mesh's dead band theta- .. theta+) the unloading branch reaches 0 N m at theta+ and the
    loading one at theta-, but a path's exact zero torque sits at either edge (decision 072's far edge, or a
    round-off tie; decision 077-hetenyi48): the width is read with the band taken out and its width added once."""
    T = np.asarray(loop_T_Nm, float)
    _steady(T)
    lo, hi = dead_band_rad
    th = elastic_twist(loop_twist_rad, dead_band_rad)
    zero = np.zeros(1)
    down = branch_twist_rad(T, th, zero, -np.ones(1))[0]
    up = branch_twist_rad(T, th, zero, np.ones(1))[0]
    return float(down - up + (hi - lo))


def lost_motion_rad(loop_T_Nm, loop_twist_rad, test_torque_Nm: float) -> float:
    """The twist between +test_torque and -test_torque on the steady loop's centre line; on a loop cycled to
    +/-test_torque (the test), its end-to-end angle."""
    T = np.asarray(loop_T_Nm, float)
    _steady(T)
    if not 0.0 < test_torque_Nm <= min(np.max(T), -np.min(T)) * (1.0 + 1e-12):
        raise ValueError(f"the test torque {test_torque_Nm:g} N m lies outside the loop")
    phi = mean_twist_rad(T, loop_twist_rad, np.array([test_torque_Nm, -test_torque_Nm]))
    return float(phi[0] - phi[1])


def loop_width_max_rad(loop_T_Nm, loop_twist_rad, n: int = 201) -> tuple[float, float]:
    """(the steady loop's largest width, the torque where it is): where flank friction shows in this model."""
    T = np.asarray(loop_T_Nm, float)
    _steady(T)
    q = np.linspace(np.min(T), np.max(T), n)
    w = branch_twist_rad(T, loop_twist_rad, q, -np.ones(n)) - branch_twist_rad(T, loop_twist_rad, q, np.ones(n))
    k = int(np.argmax(w))
    return float(w[k]), float(q[k])


def small_loop(design: MeshDesign, series_rad_per_Nmm: float, amplitude_Nm: float,
               psi_rad: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(torque N m, twist rad) of the drive cycled 0 -> +A -> -A -> +A from rest: the same chain as the
    catalogue's loop (mesh contact with friction + series members + the balls' Hertz twist), at amplitude A."""
    system, _ = mesh_system(design, psi_rad)
    T = torque_history(1e3 * amplitude_Nm, SMALL_LOOP_STEPS)
    path = solve_torque_path(system, T)
    return 1e-3 * T, path.twist_rad + T * series_rad_per_Nmm + bearing_twist_rad(design, T)


@dataclass(frozen=True)
class LossReading:
    """A row's predicted hysteresis loss and lost motion (arcmin) beside the catalogue's bounds."""

    hysteresis_loss_arcmin: float
    lost_motion_arcmin: float
    loop_width_max_arcmin: float          # the rated loop's widest point (friction's footprint), not a catalogue number
    loop_width_max_at_Nm: float
    lost_motion_torque_Nm: float          # +/- this torque (4 % of the rated torque the loop was run at)
    hysteresis_bound_arcmin: float | None
    lost_motion_bound_arcmin: float | None
    bounds_from: str
    loop_amplitude_Nm: float = float("nan")   # the +/- torque of the loop the hysteresis loss is read on
    test_torque_from: str = "rules"           # whose rated torque the 4 % is of: the table's row or the rules'

    def within(self, name: str) -> bool | None:
        """True when the prediction is below the catalogue's bound (None: no bound)."""
        value, bound = {"hysteresis": (self.hysteresis_loss_arcmin, self.hysteresis_bound_arcmin),
                        "lost_motion": (self.lost_motion_arcmin, self.lost_motion_bound_arcmin)}[name]
        return None if bound is None else bool(value < bound)

    def to_dict(self) -> dict:
        return {"hysteresis_loss_arcmin_predicted": self.hysteresis_loss_arcmin,
                "hysteresis_loss_arcmin_catalogue": self.hysteresis_bound_arcmin,
                "hysteresis_loss_within_bound": self.within("hysteresis"),
                "lost_motion_arcmin_predicted": self.lost_motion_arcmin,
                "lost_motion_arcmin_catalogue": self.lost_motion_bound_arcmin,
                "lost_motion_within_bound": self.within("lost_motion"),
                "lost_motion_torque_Nm": self.lost_motion_torque_Nm,
                "loop_width_max_arcmin": self.loop_width_max_arcmin, "loop_width_max_at_Nm": self.loop_width_max_at_Nm,
                "loss_bounds_from": self.bounds_from, "hysteresis_loss_loop_amplitude_Nm": self.loop_amplitude_Nm,
                "lost_motion_torque_from": self.test_torque_from}


def read_loss(design: MeshDesign, series_rad_per_Nmm: float, rated_Nm: float, loop_T_Nm, loop_twist_rad,
              bounds: tuple[float | None, float | None], bounds_from: str,
              test_torque_from: str = "rules", small: tuple | None = None) -> LossReading:
    """The hysteresis loss on the rated loop given, and the lost motion on a loop cycled at +/-4 % of ``rated_Nm``
    (solved here on the same chain, or ``small``: that loop already solved, e.g. scaled by similitude)."""
    T_lm = LOST_MOTION_FRACTION * rated_Nm
    Ts, ths = small_loop(design, series_rad_per_Nmm, T_lm) if small is None else small
    w, at = loop_width_max_rad(loop_T_Nm, loop_twist_rad)
    band = dead_band(mesh_system(design)[0])
    return LossReading(hysteresis_loss_rad(loop_T_Nm, loop_twist_rad, band) / ARCMIN,
                       lost_motion_rad(Ts, ths, T_lm) / ARCMIN, w / ARCMIN, at, T_lm, bounds[0], bounds[1],
                       bounds_from, float(np.max(loop_T_Nm)), test_torque_from)
