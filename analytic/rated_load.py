"""The load each study's fields are drawn at (the rated load) and the factor from the solved load to it.

Linear elasticity: every field scales with the load, so a study solved at seed 000's T = 1000 N*mm is shown
at the rated torque by multiplying stresses and displacements by T_rated / T. The seeds give no rated
torque: ``gear.rated_output_torque_Nmm`` is a chosen value and every report says so. The wave generator's
rated radial force follows from it with seed 000's F_r = 1.15 k_r T / d1. The EWG ring is loaded by its wave
generator's displacement W0 = 0.5 m dZ (seed 003 eq 7), the operating deformation: its rated load is the
force that gives that W0 (from the FEA of the toothed ring), so its factor is that force over the force solved.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.analytic.torsion import radial_force_N

__all__ = ["RatedLoad", "rated_torque", "rated_radial_force", "rated_ewg_force", "fatigue_safety_factor", "TORQUE_SOURCE"]

TORQUE_SOURCE = "gear.rated_output_torque_Nmm; chosen, the seeds give no rated torque"


@dataclass(frozen=True)
class RatedLoad:
    study: str
    name: str             # what the load is, e.g. "output torque T"
    unit: str
    solved: float         # the load the study's fields were computed at
    rated: float          # the load they are drawn at
    source: str           # where the rated value comes from

    def __post_init__(self):
        if not (math.isfinite(self.solved) and math.isfinite(self.rated) and self.solved > 0 and self.rated > 0):
            raise ValueError(f"{self.study}: loads must be finite and > 0, got solved {self.solved}, "
                             f"rated {self.rated}")

    @property
    def scale(self) -> float:
        return self.rated / self.solved

    def describe(self) -> str:
        from strainwave.catalogue_units import beside
        return f"{self.name} = {self.rated:.4g} {self.unit}{beside(self.rated, self.unit)} ({self.source})"

    def to_dict(self) -> dict:
        return {"study": self.study, "name": self.name, "unit": self.unit, "solved": self.solved,
                "rated": self.rated, "scale": self.scale, "source": self.source}


def rated_torque(study: str, params, solved: float, quantities=None) -> RatedLoad:
    """A torque-loaded study: the chosen rated output torque."""
    return RatedLoad(study, "output torque T", "N*mm", solved, params.gear.rated_output_torque_Nmm, TORQUE_SOURCE)


def rated_radial_force(study: str, params, solved: float, quantities=None) -> RatedLoad:
    """The wave generator's radial force: seed 000's F_r = 1.15 k_r T / d1 at the rated torque."""
    g, cup = params.gear, params.flexspline_cup
    rated = radial_force_N(g.force_coefficient, g.rated_output_torque_Nmm, cup.pitch_diameter_mm)
    return RatedLoad(study, "wave generator radial force F_r", "N", solved, rated,
                     f"seed 000: F_r = 1.15 k_r T / d1 at the rated T = {g.rated_output_torque_Nmm:g} N*mm "
                     f"({TORQUE_SOURCE})")


def rated_ewg_force(study: str, params, solved: float, quantities=None) -> RatedLoad:
    """The EWG ring: the force the toothed FEA ring needs for W0 = 0.5 m dZ (``quantities``' value of
    ``toothed_force_for_W0_N``), the operating deformation."""
    if not quantities or "toothed_force_for_W0_N" not in quantities:
        raise ValueError(f"{study}: its rated load is the force for W0; pass the study's toothed_force_for_W0_N")
    e = params.ewg_drive
    w0 = 0.5 * e.module_mm * e.tooth_difference
    return RatedLoad(study, f"EWG force for W0 = {w0:g} mm", "N", solved, quantities["toothed_force_for_W0_N"],
                     "seed 003 eq 7: W0 = 0.5 m dZ, the operating deformation; force from the toothed-ring FEA")


def fatigue_safety_factor(fatigue_limit_MPa: float, peak_von_mises_MPa: float) -> float:
    """sigma_-1 / sigma_vM,peak: the peak stress taken as a fully reversed amplitude, no notch, size or
    mean-stress factor (the material-only figure; seed 003 eqs 12-13 refine it for the EWG tooth root)."""
    if not peak_von_mises_MPa > 0:
        raise ValueError(f"peak von Mises stress must be > 0, got {peak_von_mises_MPa}")
    return fatigue_limit_MPa / peak_von_mises_MPa
