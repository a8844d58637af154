"""Drives no one here designed: Harmonic Drive's published CHA stiffness beside the seed models.

The catalogue (``strainwave/data/cha_torsional_stiffness.csv``, sizes 14-58) gives K1, K2, K3 of real
units. Each size becomes a parameter set by ONE set of design rules fixed before any comparison
(``DesignRules``); no size is tuned. The unit's stiffness without the output shaft is
K = 1/(lambda_H + lambda_f), from the seed's published forms and from the corrected forms (and, in
``benchmarks/catalogue_drives.py``, with lambda_f from the FEA). It is compared with K3, the
high-torque slope, which is the only catalogue figure a linear model speaks to.
"""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from importlib import resources

from strainwave.analytic import torsion
from strainwave.analytic.variant import Variant

__all__ = ["DesignRules", "CatalogueRow", "CatalogueComparison", "read_catalogue", "overrides_for",
           "unit_stiffness_Nm_per_rad", "compare_row", "log_slope", "RATIO_OF_LABEL"]

# ">50" rows hold for 80..160; the model's K does not depend on the ratio (w0 = m = d1/(2 i)), so the
# middle value is a label, not a tuning.
RATIO_OF_LABEL = {"30": 30, "50": 50, ">50": 100}


@dataclass(frozen=True)
class DesignRules:
    """How a catalogue size becomes a drive; each ratio is the seed 000 example's own proportion."""

    pitch_diameter_per_size_mm: float = 2.54    # Harmonic Drive's size = pitch diameter in tenths of an inch
    wall_over_d1: float = 2.24 / 160.0          # seed 000 example: delta / d1
    length_over_d1: float = 160.0 / 160.0       # seed 000 example: L / d1
    tooth_difference: int = 2                   # dual wave: Z_c - Z_f = 2, so Z_f = 2 i
    K_G0_default_N_per_mm: float = 6.303e4      # seed 000's implied K_G0 at its d1 = 160 mm ...
    K_G0_default_d1_mm: float = 160.0           # ... scaled with d1: similar bodies of one material
    force_coefficient: float = 0.35             # seed 000's k_r
    bearing_ring_over_d1: float = 10.0 / 160.0  # seed 000 example: t_i / d1 (the bearing scales with its cup)
    contact_over_d1: tuple[float, float] = (5.0 / 160.0, 3.0 / 160.0)   # seed 000 example: (a', b') / d1
    ball_over_d1: float = 9.525 / 160.0         # the default drive's D_w / d1
    outer_ring_over_d1: float = 2.5 / 160.0     # the default drive's outer ring / d1
    spline_over_d1: tuple[float, float] = (200.0 / 160.0, 30.0 / 160.0)   # circular spline (outer diameter, b) / d1

    def K_G0_N_per_mm(self, d1_mm: float) -> float:
        """Geometric similitude: a radial stiffness scales with the linear size (E L)."""
        return self.K_G0_default_N_per_mm * d1_mm / self.K_G0_default_d1_mm


@dataclass(frozen=True)
class CatalogueRow:
    size: int
    ratio_label: str
    T1_Nm: float
    T2_Nm: float
    K1_Nm_per_rad: float
    K2_Nm_per_rad: float
    K3_Nm_per_rad: float

    @property
    def gear_ratio(self) -> int:
        return RATIO_OF_LABEL[self.ratio_label]


@dataclass(frozen=True)
class CatalogueComparison:
    row: CatalogueRow
    d1_mm: float
    K_published_Nm_per_rad: float
    K_corrected_Nm_per_rad: float
    K_fea_Nm_per_rad: float | None = None

    def ratio(self, which: str) -> float | None:
        """Model over catalogue K3 for ``which`` in published | corrected | fea."""
        K = getattr(self, f"K_{which}_Nm_per_rad")
        return None if K is None else K / self.row.K3_Nm_per_rad


def read_catalogue(text: str | None = None) -> list[CatalogueRow]:
    """The shipped CHA table (K in 1e3 N m/rad in the file), or ``text`` in the same format."""
    if text is None:
        text = resources.files("strainwave.data").joinpath("cha_torsional_stiffness.csv").read_text("utf-8")
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    rows = []
    for rec in csv.DictReader(io.StringIO("\n".join(lines))):
        rows.append(CatalogueRow(int(rec["size"]), rec["ratio"].strip(), float(rec["T1_Nm"]), float(rec["T2_Nm"]),
                                 1e3 * float(rec["K1_e3"]), 1e3 * float(rec["K2_e3"]), 1e3 * float(rec["K3_e3"])))
    return rows


def overrides_for(row: CatalogueRow, rules: DesignRules = DesignRules()) -> dict:
    """The parameter overrides of one catalogue drive: only the rules above, nothing per size."""
    d1 = rules.pitch_diameter_per_size_mm * row.size
    teeth = rules.tooth_difference * row.gear_ratio
    module = d1 / teeth
    return {"gear": {"gear_ratio": float(row.gear_ratio), "radial_deformation_mm": module,
                     "force_coefficient": rules.force_coefficient},
            "flexspline_cup": {"pitch_diameter_mm": d1, "wall_thickness_mm": rules.wall_over_d1 * d1,
                               "length_mm": rules.length_over_d1 * d1, "teeth": teeth, "module_mm": module},
            "wave_generator": {"uncracked_radial_stiffness_N_per_mm": rules.K_G0_N_per_mm(d1),
                               "bearing_inner_ring_thickness_mm": rules.bearing_ring_over_d1 * d1,
                               "contact_semi_axes_mm": [c * d1 for c in rules.contact_over_d1],
                               "ball_diameter_mm": rules.ball_over_d1 * d1,
                               "outer_ring_thickness_mm": rules.outer_ring_over_d1 * d1},
            "circular_spline": {"outer_diameter_mm": rules.spline_over_d1[0] * d1,
                                "face_width_mm": rules.spline_over_d1[1] * d1}}


def _lambda_H(params) -> float:
    g, cup = params.gear, params.flexspline_cup
    return torsion.wave_generator_flexibility(g.force_coefficient, params.wave_generator.uncracked_radial_stiffness_N_per_mm,
                                              cup.pitch_diameter_mm, g.wave_number, g.radial_deformation_mm,
                                              g.gear_ratio)


def unit_stiffness_Nm_per_rad(params, variant: Variant, lambda_f_rad_per_Nmm: float | None = None) -> float:
    """K = 1/(lambda_H + lambda_f) of the unit without its output shaft, in N m/rad.

    ``lambda_f_rad_per_Nmm`` replaces the closed-form flexspline flexibility (the FEA chain passes its own).
    """
    cup, mat = params.flexspline_cup, params.material
    if lambda_f_rad_per_Nmm is None:
        mu = mat.shear_modulus_MPa if variant is Variant.PUBLISHED else mat.implied_shear_modulus_MPa
        k_f = torsion.shape_coefficient(cup.shape.value == "bell")
        lambda_f_rad_per_Nmm = torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm,
                                                              cup.length_mm, mu, k_f,
                                                              torsion.structure_coefficient(cup.cup), variant)
    return 1e-3 * torsion.drive_stiffness_Nmm_per_rad(_lambda_H(params) + lambda_f_rad_per_Nmm)


def compare_row(row: CatalogueRow, params, lambda_f_fea: float | None = None) -> CatalogueComparison:
    """One catalogue size: the published, corrected and (optionally) FEA-chain K beside its K3."""
    return CatalogueComparison(row, params.flexspline_cup.pitch_diameter_mm,
                               unit_stiffness_Nm_per_rad(params, Variant.PUBLISHED),
                               unit_stiffness_Nm_per_rad(params, Variant.CORRECTED),
                               None if lambda_f_fea is None else
                               unit_stiffness_Nm_per_rad(params, Variant.CORRECTED, lambda_f_fea))


def log_slope(sizes: list[float], stiffnesses: list[float]) -> float:
    """Least-squares slope of log K against log size."""
    x = [math.log(s) for s in sizes]
    y = [math.log(k) for k in stiffnesses]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
