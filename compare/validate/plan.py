"""Which FEA cases a validation runs: the headline case per study plus a crack-depth sweep per component.

The seed's default crack (0.1 mm) changes a flexibility by parts per million, below what a mesh
resolves; the sweep therefore runs from a small fraction of the wall to about half of it, where the
crack compliance is measurable and its growth with depth (a^2 or a^3) can be fitted. --quick runs one
depth per component (the deepest), the full run the seed's depth plus three.
"""
from __future__ import annotations

from dataclasses import dataclass

import math

import numpy as np

from strainwave.registry import STUDIES
from strainwave.compare.validate.runner import Case

# component -> its study, from the registry (the crack-bearing studies)
COMPONENT_STUDY = {s.component: s.name for s in STUDIES.values() if s.component}
RING_STUDY = "ring-compression"
WG_BEARING_STUDY = "wg-bearing"      # the inner ring on the elliptical cam: one 2D case, its own crack sweep
# studies of the drive as it works (issue 34): one uncracked case each, label = study name
DRIVE_STUDIES = ("cup-wave-generator", "cup-surface-crack")


@dataclass(frozen=True)
class Plan:
    headline: dict[str, Case]                      # component -> case at the default crack depth
    sweeps: dict[str, tuple[Case, ...]]            # component -> deeper cracks
    ring: Case
    wg_bearing: Case = Case("wg-bearing", WG_BEARING_STUDY, None)
    drive: tuple[Case, ...] = ()

    def all_cases(self) -> tuple[Case, ...]:
        cases = list(self.headline.values())
        for sweep in self.sweeps.values():
            cases += list(sweep)
        return tuple(cases) + (self.ring, self.wg_bearing) + self.drive

    def drive_label(self, study: str) -> str | None:
        return next((c.label for c in self.drive if c.study == study), None)


def walls_mm(params) -> dict[str, float]:
    """The wall each component's crack cuts (the same walls params.py bounds the depth by)."""
    return {"shaft": params.output_shaft.wall_mm, "cup": params.flexspline_cup.wall_thickness_mm,
            "bearing": params.wave_generator.bearing_inner_ring_thickness_mm}


def bearing_depth_limit_mm(params) -> float:
    """Deepest bearing crack whose surface half-length c still fits the contact patch.

    geometry/bearing_ring.py refuses c >= 0.5 sqrt(pi) a' (the patch half-length across the race), with
    c from Q = 1 + 1.464 (a/c)^1.65 (seed 000); c/a is fixed by Q, so the depth is bounded.
    """
    from strainwave.geometry.cracks import half_length_from_q

    patch_half_mm = 0.5 * math.sqrt(math.pi) * params.wave_generator.contact_semi_axes_mm[0]
    c_per_a = half_length_from_q(1.0, params.cracks.surface_crack_shape_factor)
    return patch_half_mm / c_per_a


def sweep_limits_mm(params) -> dict[str, float]:
    """Deepest crack per component: half the wall, and for the bearing 90 % of the contact-patch limit."""
    limits = {k: 0.5 * w for k, w in walls_mm(params).items()}
    limits["bearing"] = min(limits["bearing"], 0.9 * bearing_depth_limit_mm(params))
    return limits


def sweep_depths_mm(deepest_mm: float, points: int) -> tuple[float, ...]:
    """Geometric depths from deepest/8 (two points: deepest/2) to ``deepest_mm``, 3 significant digits."""
    lo = deepest_mm / (2.0 if points <= 2 else 8.0)
    depths = np.geomspace(lo, deepest_mm, points)
    return tuple(float(f"{d:.3g}") for d in depths)


# Full-run sweep depths besides the seed's: four points fit a^2 vs a^3 within budget (docs/decisions/022-validate-run-budget.md).
FULL_SWEEP_POINTS = 3


def sweep_mesh_size_mm(params, component: str) -> float | None:
    """Global size of the sweep cases: the --quick size for the shaft and the cup.

    A sweep case is there for the crack delta, which is solved closed and opened on one mesh (seam,
    or the shaft's axisymmetric section with its own sizes) and so hardly depends on the far-field
    size; the headline case keeps the fine global mesh for the flexibility checks
    (docs/decisions/022-validate-run-budget.md)."""
    from strainwave.fea import cup_torsion, shaft_torsion
    sizes = {"shaft": shaft_torsion.default_size_mm, "cup": cup_torsion.default_size_mm}
    return sizes[component](params, True) if component in sizes else None


def make_plan(params, *, quick: bool) -> Plan:
    """Full: the seed's crack depth plus three sweep depths per component. Quick: the deepest depth only.

    The seed's 0.1 mm crack needs the finest crack-front mesh of all cases (minutes for the shaft), so
    --quick leaves it out: its headline case is the shallower of its two depths (the uncracked
    flexibility is solved in every case), and the crack checks use the sweep anyway.
    """
    from strainwave.fea.studies import with_crack
    headline, sweeps = {}, {}
    for c, deepest in sweep_limits_mm(params).items():
        depth = params.crack_depth_mm(STUDIES[COMPONENT_STUDY[c]].crack_key)
        depths = sweep_depths_mm(deepest, 2 if quick else FULL_SWEEP_POINTS)
        if quick:
            # One case per component, at the deepest crack (where the crack compliance stands out of the
            # mesh noise): the uncracked flexibility is solved in the same case.
            deep = depths[-1]
            headline[c] = Case(f"{c}-a{deep:g}", COMPONENT_STUDY[c], deep)
            sweeps[c] = ()
        else:
            headline[c] = Case(f"{c}-a{depth:g}", COMPONENT_STUDY[c], depth)
            sweep_h = sweep_mesh_size_mm(params, c)
            deeper = [d for d in depths if d > depth]
            # only the deepest sweep case's field is drawn (the crack-tip close-up): the others write none
            sweeps[c] = tuple(Case(f"{c}-a{d:g}", COMPONENT_STUDY[c], d, sweep_h, fields=d == deeper[-1])
                              for d in deeper)
    plan = Plan(headline, sweeps, Case("ring", RING_STUDY, None),
                drive=tuple(Case(s, s, None) for s in DRIVE_STUDIES))
    for case in plan.all_cases():   # every crack checked against its own wall before any mesh is built
        with_crack(case.study, params, case.crack_depth_mm)
    return plan
