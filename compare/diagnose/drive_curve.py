"""A drive's torque-twist curve as a typed record: the catalogue's (or a prediction's) baseline for `diagnose`.

Harmonic Drive's definition (CHA manual 1018854, "Torsional stiffness", equations 68.1-68.4): the mean curve of
the loop is linearised in three regions, K1 from 0 to T1, K2 from T1 to T2, K3 above, odd in the torque. The
loop's branches sit either side of that mean curve: the hysteresis loss is their difference at zero torque of a
+/- rated torque cycle; the lost motion the twist between +4 % and -4 % of the rated torque on the loop.

``DriveCurve`` holds those numbers (SI: N*m, rad) and, where a study predicts it (the tooth-mesh study, issue 48),
a sampled loop. ``mean_twist_rad`` evaluates the mean curve, ``branch_twist_rad`` the loading or unloading branch.
``unit_curve`` reads a catalogue unit's row (``CHA-20A-100``) from the shipped table.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

ARCMIN = math.pi / (180.0 * 60.0)
LOST_MOTION_FRACTION = 0.04        # Harmonic Drive's lost-motion torque, fraction of the rated torque


@dataclass(frozen=True)
class DriveCurve:
    """A drive's stiffness curve and loop. ``loop_torque_Nm``/``loop_twist_rad``: an optional sampled closed loop
    in acquisition order (loading and unloading branches told apart by the torque's direction)."""

    K1_Nm_per_rad: float
    K2_Nm_per_rad: float
    K3_Nm_per_rad: float
    T1_Nm: float
    T2_Nm: float
    lost_motion_rad: float = 0.0
    hysteresis_rad: float = 0.0
    rated_torque_Nm: float | None = None
    loop_torque_Nm: np.ndarray | None = None
    loop_twist_rad: np.ndarray | None = None
    source: str = ""

    def __post_init__(self):
        ks = (self.K1_Nm_per_rad, self.K2_Nm_per_rad, self.K3_Nm_per_rad)
        if min(ks) <= 0.0 or not 0.0 <= self.T1_Nm <= self.T2_Nm:
            raise ValueError(f"a drive curve needs K1, K2, K3 > 0 and 0 <= T1 <= T2 (got {ks}, {self.T1_Nm}, "
                             f"{self.T2_Nm})")
        if (self.loop_torque_Nm is None) != (self.loop_twist_rad is None):
            raise ValueError("a sampled loop needs both its torque and its twist")

    def mean_twist_rad(self, T_Nm) -> np.ndarray:
        """The catalogue's three-slope mean curve (equations 68.1-68.4), odd in the torque."""
        T = np.asarray(T_Nm, dtype=float)
        m = np.abs(T)
        phi = (np.minimum(m, self.T1_Nm) / self.K1_Nm_per_rad
               + np.clip(m - self.T1_Nm, 0.0, self.T2_Nm - self.T1_Nm) / self.K2_Nm_per_rad
               + np.maximum(m - self.T2_Nm, 0.0) / self.K3_Nm_per_rad)
        return np.sign(T) * phi

    def departure_rad(self, T_Nm) -> np.ndarray:
        """The mean curve minus its first slope's line: what makes the baseline a curve, not a line."""
        T = np.asarray(T_Nm, dtype=float)
        return self.mean_twist_rad(T) - T / self.K1_Nm_per_rad

    def branch_twist_rad(self, T_Nm, direction) -> np.ndarray:
        """The loading (direction +1) or unloading (-1) branch; 0 gives the mean curve.

        With a sampled loop: that branch of the loop, interpolated in the torque. Otherwise the mean curve
        shifted by half the loop's width, the width falling as 1 - (T/T_amp)^2 to close at the cycle's ends
        (T_amp the rated torque, else the largest torque asked for): the twist lags the torque."""
        T = np.asarray(T_Nm, dtype=float)
        d = np.broadcast_to(np.sign(np.asarray(direction, dtype=float)), T.shape)
        if self.loop_torque_Nm is not None:
            return np.where(d > 0, self._sampled(T, 1.0), np.where(d < 0, self._sampled(T, -1.0),
                                                                 self.mean_twist_rad(T)))
        amp = self.rated_torque_Nm or float(np.max(np.abs(T))) or 1.0
        half = 0.5 * self.hysteresis_rad * np.clip(1.0 - (T / amp) ** 2, 0.0, 1.0)
        return self.mean_twist_rad(T) - d * half

    def _sampled(self, T: np.ndarray, direction: float) -> np.ndarray:
        tq = np.asarray(self.loop_torque_Nm, dtype=float)
        tw = np.asarray(self.loop_twist_rad, dtype=float)
        on = np.sign(np.gradient(tq)) == direction
        order = np.argsort(tq[on])
        return np.interp(T, tq[on][order], tw[on][order])

    def slope_at(self, T_Nm: float) -> float:
        """The curve's stiffness at torque ``T_Nm`` (N*m/rad)."""
        m = abs(T_Nm)
        return self.K1_Nm_per_rad if m <= self.T1_Nm else self.K2_Nm_per_rad if m <= self.T2_Nm \
            else self.K3_Nm_per_rad


# CHA actuator part numbers: CHA-<size>A-<ratio>; the shipped table's ratio column says 30, 50 or >50 (80-160)
_UNIT = re.compile(r"^(CHA)-(\d+)A?-(\d+)$", re.IGNORECASE)
_CHA_RATIOS = (30, 50, 80, 100, 120, 160)
CHA_HYSTERESIS_LIMIT_ARCMIN = {"30": 3.0, "50": 1.0, ">50": 1.0}    # CHA manual 1018854 Table 50.1-50.2
CHA_LOST_MOTION_LIMIT_ARCMIN = 1.0
CHA_SOURCE = ("Harmonic Drive AG, CHA manual 1018854 (Tables 50.1-50.4: T1, T2, K1, K2, K3; hysteresis loss, "
              "lost motion limits)")


def known_units() -> list[str]:
    """Every unit the shipped table names, e.g. CHA-20A-100."""
    from strainwave.analytic.catalogue import read_catalogue
    out = []
    for row in read_catalogue():
        ratios = [r for r in _CHA_RATIOS if _label(r) == row.ratio_label]
        out += [f"CHA-{row.size}A-{r}" for r in ratios]
    return out


def _label(ratio: int) -> str:
    return "30" if ratio == 30 else "50" if ratio == 50 else ">50"


def unit_curve(name: str) -> DriveCurve | None:
    """The catalogue curve of unit ``name`` (CHA-<size>A-<ratio>); None where the table has no such unit.

    The loss and lost motion are the catalogue's limits ("<"), kept as the record's values: a unit within its
    specification shows at most these."""
    from strainwave.analytic.catalogue import read_catalogue
    m = _UNIT.match(name.strip())
    if m is None or int(m.group(3)) not in _CHA_RATIOS:
        return None
    size, label = int(m.group(2)), _label(int(m.group(3)))
    row = next((r for r in read_catalogue() if r.size == size and r.ratio_label == label), None)
    if row is None:
        return None
    return DriveCurve(row.K1_Nm_per_rad, row.K2_Nm_per_rad, row.K3_Nm_per_rad, row.T1_Nm, row.T2_Nm,
                      lost_motion_rad=CHA_LOST_MOTION_LIMIT_ARCMIN * ARCMIN,
                      hysteresis_rad=CHA_HYSTERESIS_LIMIT_ARCMIN[label] * ARCMIN,
                      source=f"{name.strip().upper()}: {CHA_SOURCE}")


__all__ = ["ARCMIN", "CHA_SOURCE", "DriveCurve", "LOST_MOTION_FRACTION", "known_units", "unit_curve"]
