"""One loop per ratio, scaled to every size (decision 071-coning48).

At a fixed ratio the design rules make every drive geometrically similar: every length ~ d, the rated torque and
every load ~ d^3 (forces ~ d^2), every series member's flexibility ~ d^-3, the fatigue rim a fixed fraction of d.
The loop's twist at T / d^3 is then the same for every size (measured: 1e-14 relative between sizes 14 and 58,
with 1 and 8 face slices), so the contact solve runs once per ratio at the reference size and each row gets the
reference loop with its torque scaled by (d / d_ref)^3, read by the same catalogue reader.

Not similar, so solved per row: tooth deviations (ISO 1328-1's are absolute lengths per module and diameter:
``accuracy_grade``), and a lost-motion loop at a table's own rated torque.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.analytic.catalogue_loss import LOST_MOTION_FRACTION, small_loop
from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.drive_curve import DriveCurve, curve_from_loop, predict_curve

__all__ = ["SimilarLoop", "is_similar", "reference_loop"]


def is_similar(rules: MeshRules) -> bool:
    """True when the rules' drives at one ratio are exactly similar across sizes (no absolute length in the rules)."""
    return rules.accuracy_grade is None


@dataclass(frozen=True)
class SimilarLoop:
    """A ratio's reference drive: its rated loop and its +/-4 % loop at the reference pitch diameter."""

    ratio: float
    d_ref_mm: float
    curve: DriveCurve
    small_torque_Nm: np.ndarray
    small_twist_rad: np.ndarray
    cpu_s: float = 0.0

    def scale(self, d_mm: float) -> float:
        """Torque of the drive of pitch diameter ``d_mm`` over the reference's at the same twist."""
        return (d_mm / self.d_ref_mm) ** 3

    def curve_at(self, d_mm: float) -> DriveCurve:
        """The similar drive's curve: the reference loop with its torque scaled, read by the catalogue reader."""
        s, c = self.scale(d_mm), self.curve
        T, tw = s * c.loop_torque_Nm, c.loop_twist_rad
        rated = s * c.rated_torque_Nm
        return curve_from_loop(T, tw, rated, dead_band_rad=c.dead_band_rad,
                               ratcheting_torque_Nm=s * c.ratcheting_torque_Nm, teeth_in_contact=c.teeth_in_contact,
                               source=f"{c.source}; scaled by similitude from d = {self.d_ref_mm:g} mm (decision 071)")

    def small_loop_at(self, d_mm: float) -> tuple[np.ndarray, np.ndarray]:
        """The +/-4 % loop of the similar drive (at the rules' rated torque)."""
        return self.scale(d_mm) * self.small_torque_Nm, self.small_twist_rad


def reference_loop(rules: MeshRules, ratio: float, series_rad_per_Nmm_at) -> SimilarLoop:
    """Solve the ratio's drive once at the rules' reference size (``cup_zone_reference_size``);
    ``series_rad_per_Nmm_at(size)`` is the flexibility in series with the mesh at that size."""
    import time
    if not is_similar(rules):
        raise ValueError("the rules' drives are not similar across sizes (tooth deviations): solve each row")
    t0 = time.process_time()
    size = rules.cup_zone_reference_size
    design, series = rules.design(size, ratio), series_rad_per_Nmm_at(size)
    rated = rules.rated_torque_Nm(size)
    curve = predict_curve(design, series, rated, with_te=False, exact=True)      # the exact loop (decision 074)
    Ts, ths = small_loop(design, series, LOST_MOTION_FRACTION * rated)
    return SimilarLoop(ratio, rules.pitch_diameter_mm(size), curve, Ts, ths, time.process_time() - t0)
