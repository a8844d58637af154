"""Which FEA cases a validation runs: the headline case per study plus a crack-depth sweep per component.

The seed's default crack (0.1 mm) changes a flexibility by parts per million, below what a mesh
resolves; the sweep therefore runs from a small fraction of the wall to about half of it, where the
crack compliance is measurable and its growth with depth (a^2 or a^3) can be fitted.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .runner import Case

COMPONENT_STUDY = {"shaft": "shaft-torsion", "cup": "cup-torsion", "bearing": "bearing-ring"}


@dataclass(frozen=True)
class Plan:
    headline: dict[str, Case]                      # component -> case at the default crack depth
    sweeps: dict[str, tuple[Case, ...]]            # component -> deeper cracks
    ring: Case

    def all_cases(self) -> tuple[Case, ...]:
        cases = list(self.headline.values())
        for sweep in self.sweeps.values():
            cases += list(sweep)
        return tuple(cases) + (self.ring,)


def walls_mm(params) -> dict[str, float]:
    """The wall each component's crack cuts (the same walls params.py bounds the depth by)."""
    return {"shaft": params.output_shaft.wall_mm, "cup": params.flexspline_cup.wall_thickness_mm,
            "bearing": params.wave_generator.bearing_inner_ring_thickness_mm}


def sweep_depths_mm(wall_mm: float, points: int) -> tuple[float, ...]:
    """Geometric depths from wall/16 (quick: wall/8) to wall/2, rounded to 3 significant digits."""
    lo = wall_mm / (8.0 if points <= 3 else 16.0)
    depths = np.geomspace(lo, 0.5 * wall_mm, points)
    return tuple(float(f"{d:.3g}") for d in depths)


def make_plan(params, *, quick: bool) -> Plan:
    depth = params.cracks.depth_mm
    points = 3 if quick else 5
    headline = {c: Case(f"{c}-a{depth:g}", study, depth) for c, study in COMPONENT_STUDY.items()}
    sweeps = {c: tuple(Case(f"{c}-a{d:g}", COMPONENT_STUDY[c], d)
                       for d in sweep_depths_mm(wall, points) if d > depth)
              for c, wall in walls_mm(params).items()}
    return Plan(headline, sweeps, Case("ring", "ring-compression", None))
