"""Manufacturing deviations of the teeth, drawn to an ISO 1328-1 flank tolerance class (decision 070-engage48).

A real flexspline and circular spline are not the ideal rack: each tooth stands off its nominal place and each flank
off its nominal profile, within the tolerances of the accuracy class the gears are made to. ISO 1328-1:2013
(eq. 5, 6, 8; the class step (sqrt 2)^(A - 5) from the unrounded class-5 value, section 5.2.2) gives, in um with
d the reference diameter and m the module, both in mm:

    single pitch            f_pT  = (0.001 d + 0.4 m + 5)              (sqrt 2)^(A - 5)
    total cumulative pitch  F_pT  = (0.002 d + 0.55 sqrt(d) + 0.7 m + 12) (sqrt 2)^(A - 5)
    profile form            f_faT = (0.55 m + 5)                       (sqrt 2)^(A - 5)

The draw (one rule for every gear; a seed picks one unit out of the many a catalogue value averages):
- each tooth's place: a once-per-revolution wave of amplitude F_pT / 2 and random phase (the cumulative pitch
  deviation's usual form, runout; ISO/TR 10064-1) plus an independent normal scatter whose adjacent difference (the
  single pitch deviation) has f_pT as its two-sigma bound: sigma = f_pT / (2 sqrt 2);
- each flank's profile at the contact: an independent normal offset with f_faT as its two-sigma bound.
Positive: the tooth (FS) or the space (CS) moved in the +tangential direction; a form offset thins the flank.
ISO 1328-1:2013 holds for m >= 0.5 mm and 5 <= z <= 1000; ``outside_iso_range`` says when a gear is beyond it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["IsoTolerances", "ToothDeviations", "iso1328_tolerances_um", "draw_deviations", "outside_iso_range"]


@dataclass(frozen=True)
class IsoTolerances:
    """ISO 1328-1:2013 flank tolerances of one gear (um)."""

    single_pitch_um: float
    total_pitch_um: float
    profile_form_um: float


def iso1328_tolerances_um(module_mm: float, diameter_mm: float, grade: float) -> IsoTolerances:
    """f_pT, F_pT, f_faT of a gear of ``module_mm`` on ``diameter_mm`` in tolerance class ``grade`` (unrounded)."""
    if not (module_mm > 0.0 and diameter_mm > 0.0):
        raise ValueError("module and diameter must be > 0")
    step = math.sqrt(2.0) ** (grade - 5.0)
    d, m = diameter_mm, module_mm
    return IsoTolerances((0.001 * d + 0.4 * m + 5.0) * step,
                         (0.002 * d + 0.55 * math.sqrt(d) + 0.7 * m + 12.0) * step,
                         (0.55 * m + 5.0) * step)


def outside_iso_range(module_mm: float, teeth: int) -> bool:
    """True where ISO 1328-1:2013's formulas are extrapolated (m < 0.5 mm or z outside 5..1000)."""
    return module_mm < 0.5 or not 5 <= teeth <= 1000


@dataclass(frozen=True)
class ToothDeviations:
    """One unit's deviations (mm): each FS tooth's and each CS space's tangential place, each flank's form
    offset (column 0 the driving (+) flank, 1 the reverse (-) flank)."""

    fs_place_mm: np.ndarray        # (Z_f,)
    cs_place_mm: np.ndarray        # (Z_c,)
    fs_form_mm: np.ndarray         # (Z_f, 2)
    cs_form_mm: np.ndarray         # (Z_c, 2)

    def flank_offset_mm(self, fs_tooth: np.ndarray, cs_space: np.ndarray, sign: float) -> np.ndarray:
        """The circumferential gap each pair gains (> 0: wider) on its ``sign`` flank."""
        col = 0 if sign > 0 else 1
        place = self.cs_place_mm[cs_space] - self.fs_place_mm[fs_tooth]
        return sign * place + self.fs_form_mm[fs_tooth, col] + self.cs_form_mm[cs_space, col]


def _places(rng: np.random.Generator, teeth: int, tol: IsoTolerances) -> np.ndarray:
    phase = rng.uniform(0.0, 2.0 * math.pi)
    wave = 0.5 * tol.total_pitch_um * np.sin(2.0 * math.pi * np.arange(teeth) / teeth + phase)
    scatter = rng.normal(0.0, tol.single_pitch_um / (2.0 * math.sqrt(2.0)), teeth)
    return 1e-3 * (wave + scatter)


def draw_deviations(teeth_fs: int, teeth_cs: int, module_mm: float, grade: float, seed: int) -> ToothDeviations:
    """A unit made to ISO 1328-1 class ``grade``: both gears on the module's pitch diameters, same class."""
    rng = np.random.default_rng(seed)
    out = []
    for z in (teeth_fs, teeth_cs):
        tol = iso1328_tolerances_um(module_mm, module_mm * z, grade)
        out.append((_places(rng, z, tol), 1e-3 * rng.normal(0.0, 0.5 * tol.profile_form_um, (z, 2))))
    return ToothDeviations(out[0][0], out[1][0], out[0][1], out[1][1])
