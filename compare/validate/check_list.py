"""The one list of validate's checks: each ``CheckSpec`` names its id, its report component, the builder that
confronts the FEA with the closed form, that closed form as a function of a point's parameters, the rule its
tolerance follows, and the FEA quantities of registry studies it stands beside.

Read by: ``check_set.build_checks`` (builds each, in this order), ``REQUIRED_IDS`` and the report's order,
``registry.Study.checked`` (the sweep's closed-form columns, via ``reference`` at the point's own parameters,
so validate and the sweep compare one FEA quantity with one closed form) and the report's convergence plots.
Adding a check is its builder (and reference) plus one ``CheckSpec`` line here.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from strainwave.analytic.reference import Reference
from strainwave.compare.validate import (ring_checks, surface_crack_checks, torsion_checks, wg_bearing_checks,
                                        wg_cup_checks)
from strainwave.compare.validate import tooth_mesh_checks
from strainwave.compare.validate import mesh_closed_form_checks
from strainwave.compare.validate import buckling_checks
from strainwave.compare.validate import flank_hertz_checks
from strainwave.compare.validate import drive_assembled_checks
from strainwave.compare.validate.checks import Check
from strainwave.compare.validate.crack_checks import cup_crack, shaft_crack, shaft_range_note

__all__ = ["At", "CheckContext", "CheckSpec", "CHECKS", "REQUIRED_IDS", "SECTIONS", "beside", "check_spec", "current",
           "sections", "summary_reference"]


@dataclass(frozen=True)
class At:
    """Where a closed form is evaluated besides the parameters: the crack depth and the force the FEA applied."""

    crack_depth_mm: float | None = None
    force_N: float | None = None


ReferenceAt = Callable[[object, At], "Reference | None"]    # (params, At) -> the closed form there (None: none)


@dataclass
class CheckContext:
    """What a builder reads: the FEA book, the plan, the parameters and the analytic summary (once per run)."""

    book: object
    plan: object
    summary: dict
    params: object
    memo: dict = field(default_factory=dict)

    @property
    def s000(self) -> dict:
        return self.summary.get("seed000", {})

    @property
    def refs(self) -> dict:
        return self.summary.get("checks", {})

    def label(self, study: str) -> str | None:
        """The case label of ``study``: a crack component's headline case, or the study's one case."""
        from strainwave.registry import STUDIES
        component = STUDIES[study].component
        if component is not None and component in self.plan.headline:
            return self.plan.headline[component].label
        return self.plan.label_of(study)

    def group(self, builder: Callable[["CheckContext"], list[Check]]) -> dict[str, Check]:
        """The checks a builder of several makes, built once per run, by id."""
        if builder not in self.memo:
            self.memo[builder] = {c.id: c for c in builder(self)}
        return self.memo[builder]


@dataclass(frozen=True)
class CheckSpec:
    id: str                                        # "component.quantity"
    component: str                                 # the report section it is listed under
    builder: Callable[[CheckContext], Check]
    reference: ReferenceAt | None                  # the closed form at a point; None: not a function of one point
    tolerance: str                                 # the rule the builder's tolerance follows
    beside: tuple[tuple[str, str], ...] = ()       # (registry study, FEA quantity) the reference stands beside
    plot: tuple[str, str] | None = None            # (study, quantity) whose convergence history is drawn
    range_note: Callable[[object, float], str] | None = None   # per crack depth: why a form is used out of range
    record: Callable[[CheckContext], dict] | None = None       # a table beside the check: results.json records[id]

    def __post_init__(self):
        if self.id.split(".", 1)[0] != self.component:
            raise ValueError(f"check {self.id}: its id must start with its component {self.component!r}")


def summary_reference(check_id: str, *, with_force: bool = True) -> ReferenceAt:
    """The analytic summary's entry (``analytic/checks.py``). ``with_force``: the FEA quantity is at the force it
    applied, so an entry given at a force (its ``force_N``) is scaled to it, and has no value at a point that
    states none; otherwise both sides are at the same prescribed deformation (the ring's stresses at W0)."""
    def reference(params, at: At) -> Reference | None:
        from strainwave.analytic.summary import analytic_summary
        entry = analytic_summary(params)["checks"][check_id]
        ref = Reference(entry["published"], entry["corrected"], entry["unit"], f"analytic_summary checks.{check_id}")
        if not (with_force and "force_N" in entry):
            return ref
        return None if at.force_N is None else ref.scaled(at.force_N / entry["force_N"])
    return reference


def _crack_at(curve) -> ReferenceAt:
    return lambda params, at: None if at.crack_depth_mm is None else curve(params, at.crack_depth_mm)


def _pick(group, check_id: str):
    return lambda ctx: ctx.group(group).get(check_id)     # None: the group made no such check


def _wg_bearing(ctx):
    return wg_bearing_checks.wg_bearing_checks(ctx.book, ctx.label(wg_bearing_checks.STUDY) or "", ctx.params)


def _ring(ctx):
    return ring_checks.ring_checks(ctx.book, ctx.label(RING) or "", ctx.refs, ctx.params)


def _wg_cup(ctx):
    label = ctx.label(wg_cup_checks.STUDY)
    return [] if label is None else wg_cup_checks.wg_checks(ctx.book, label, ctx.params)


def _surface_crack(ctx):
    return surface_crack_checks.surface_crack_checks(ctx.book, ctx.label(surface_crack_checks.STUDY), ctx.params)


def _buckling(ctx) -> Check:
    """The buckling check, solved once per run (its record reads the same solve)."""
    if "buckling" not in ctx.memo:
        ctx.memo["buckling"] = buckling_checks.buckling_check(ctx.params)
    return ctx.memo["buckling"]


def _buckling_record(ctx) -> dict:
    return buckling_checks.buckling_record(ctx.params, _buckling(ctx))


def _surface_crack_record(ctx) -> dict:
    return surface_crack_checks.surface_crack_record(ctx.book, ctx.label(surface_crack_checks.STUDY), ctx.params)


def _flank_hertz(ctx):
    load, _ = flank_hertz_checks.rated_peak_line_load(ctx.book, ctx.label(flank_hertz_checks.STUDY), ctx.params)
    return flank_hertz_checks.hertz_checks(ctx.params, rated_load_N_per_mm=load)


def _flank_hertz_record(ctx) -> dict:
    """The FE and Hertz at the tooth-mesh study's rated peak flank load (beside the checks, not asserted)."""
    load, why = flank_hertz_checks.rated_peak_line_load(ctx.book, ctx.label(flank_hertz_checks.STUDY), ctx.params)
    return flank_hertz_checks.rated_record(ctx.params, load, why)


SHAFT, CUP, BEARING, RING = "shaft-torsion", "cup-torsion", "bearing-ring", "ring-compression"
GCI = "GCI (Roache Fs 1.25 / 3 inside, added once)"
ARC = f"{GCI} + the ring's arc-load and (delta/r_m)^2 allowances"
NEWMAN_RAJU = f"{GCI} + Newman-Raju's K^2 (10 %) + the block's far face (c/L)^3"
CLOSURE = f"{GCI} of the closure ratio, as an angle + Newman-Raju's K < 0 rule vs the exact face condition + bisection"

CHECKS: tuple[CheckSpec, ...] = (
    CheckSpec("shaft.flexibility", "shaft",
              lambda ctx: torsion_checks.shaft_flexibility(ctx.book, ctx.label(SHAFT), ctx.s000, ctx.params),
              lambda params, at: torsion_checks.shaft_flexibility_reference(params), GCI,
              ((SHAFT, "flexibility_rad_per_Nmm"),), (SHAFT, "flexibility_rad_per_Nmm")),
    CheckSpec("shaft.crack_compliance", "shaft", shaft_crack, _crack_at(torsion_checks.shaft_crack_curve),
              f"{GCI} + the thick-tube fit's scatter", ((SHAFT, "delta_flexibility_rad_per_Nmm"),),
              range_note=shaft_range_note),
    CheckSpec("cup.flexibility", "cup",
              lambda ctx: torsion_checks.cup_flexibility(ctx.book, ctx.label(CUP), ctx.s000, ctx.params),
              lambda params, at: torsion_checks.cup_flexibility_reference(params),
              f"{GCI} + the junction calibration's scatter", ((CUP, "flexibility_rad_per_Nmm"),),
              (CUP, "flexibility_rad_per_Nmm")),
    CheckSpec("cup.crack_compliance", "cup", cup_crack, _crack_at(torsion_checks.cup_crack_curve),
              f"{GCI} + plane stress/strain (nu^2) + shell curvature (lambda^2)",
              ((CUP, "delta_flexibility_rad_per_Nmm"),)),
    # checked on the ring on the cam (wg-bearing); beside the 3D bonded-bore ring's sweep: seed 000's du_H / F_r
    CheckSpec("bearing.crack_compliance", "bearing", _pick(_wg_bearing, "bearing.crack_compliance"),
              lambda params, at: (None if at.crack_depth_mm is None or at.force_N is None else
                                  torsion_checks.bearing_crack_curve(params, at.crack_depth_mm, at.force_N)),
              f"{GCI} + back face + Tada's weight function", ((BEARING, "delta_radial_compliance_mm_per_N"),)),
    CheckSpec("bearing.race_stress_major", "bearing", _pick(_wg_bearing, "bearing.race_stress_major"),
              lambda params, at: wg_bearing_checks.race_stress_reference(params, "major"),
              f"{GCI} + surface stress recovery (exact Michell reference)", ((wg_bearing_checks.STUDY, "race_stress_major_MPa"),)),
    CheckSpec("bearing.race_stress_minor", "bearing", _pick(_wg_bearing, "bearing.race_stress_minor"),
              lambda params, at: wg_bearing_checks.race_stress_reference(params, "minor"),
              f"{GCI} + surface stress recovery (exact Michell reference)", ((wg_bearing_checks.STUDY, "race_stress_minor_MPa"),)),
    CheckSpec("bearing.ball_loads", "bearing", _pick(_wg_bearing, "bearing.ball_loads"),
              lambda params, at: wg_bearing_checks.ball_load_reference(params),
              f"{GCI} + the ring's compliance under a ball, in series with Hertz", ((wg_bearing_checks.STUDY, "ball_load_ratio"),)),
    CheckSpec("ring.delta_cd", "ring", _pick(_ring, "ring.delta_cd"), summary_reference("ring.delta_cd"), ARC,
              ((RING, "delta_cd_mm"),), (RING, "delta_cd_mm")),
    CheckSpec("ring.delta_ab", "ring", _pick(_ring, "ring.delta_ab"), summary_reference("ring.delta_ab"), ARC,
              ((RING, "delta_ab_mm"),), (RING, "delta_ab_mm")),
    CheckSpec("ring.delta_cd_solid", "ring", _pick(_ring, "ring.delta_cd_solid"), None,
              f"{ARC} + the width effect", (), (RING, "delta_cd_3d_mm")),
    CheckSpec("ring.sigma_max", "ring", _pick(_ring, "ring.sigma_max"), summary_reference("ring.sigma_max", with_force=False), ARC,
              ((RING, "sigma_D_outer_MPa"),), (RING, "sigma_D_outer_MPa")),
    CheckSpec("ring.sigma_min", "ring", _pick(_ring, "ring.sigma_min"), summary_reference("ring.sigma_min", with_force=False), ARC,
              ((RING, "sigma_B_outer_MPa"),), (RING, "sigma_B_outer_MPa")),
    CheckSpec("ring.tooth_influence", "ring", _pick(_ring, "ring.tooth_influence"),
              summary_reference("ring.tooth_influence"), f"{GCI} + the tooth-factor fit",
              ((RING, "tooth_influence"),), (RING, "tooth_influence")),
    CheckSpec("ring.stress_concentration", "ring", _pick(_ring, "ring.stress_concentration"),
              summary_reference("ring.stress_concentration"), f"{GCI} + the tooth-factor fit",
              ((RING, "stress_concentration"),), (RING, "stress_concentration")),
    # issue 48 item 4 (decision 073-assembled48): replaces gear.stiffness (a sum of members checked elsewhere)
    CheckSpec(drive_assembled_checks.CHECK, "gear",
              lambda ctx: drive_assembled_checks.drive_check(
                  ctx.book, ctx.label(drive_assembled_checks.STUDY), ctx.label(wg_bearing_checks.STUDY) or "",
                  ctx.params, ctx.memo),
              None, f"{GCI} + the Fourier truncation of the teeth's load on the wall"),
    CheckSpec("cup.wg_bending_major", "cup", _pick(_wg_cup, "cup.wg_bending_major"),
              lambda params, at: wg_cup_checks.references(params, "major"), f"{GCI} + curved beam + edge zones",
              ((wg_cup_checks.STUDY, "prescribed_linear_bending_major_MPa"),)),
    CheckSpec("cup.wg_bending_minor", "cup", _pick(_wg_cup, "cup.wg_bending_minor"),
              lambda params, at: wg_cup_checks.references(params, "minor"), f"{GCI} + curved beam + edge zones",
              ((wg_cup_checks.STUDY, "prescribed_linear_bending_minor_MPa"),)),
    CheckSpec("cup.surface_crack_major", "cup", _pick(_surface_crack, "cup.surface_crack_major"),
              surface_crack_checks.reference_at("major"), NEWMAN_RAJU, record=_surface_crack_record),
    # issue 50: replaces cup.surface_crack_between (equal to _major) and _minor (a shut share 1 by construction)
    CheckSpec("cup.surface_crack_closure_angle", "cup", _pick(_surface_crack, "cup.surface_crack_closure_angle"),
              surface_crack_checks.reference_at("closure"), CLOSURE),
    CheckSpec("mesh.pair_stiffness", "mesh",
              lambda ctx: tooth_mesh_checks.pair_check(ctx.book, ctx.label(tooth_mesh_checks.STUDY), ctx.params),
              lambda params, at: tooth_mesh_checks.pair_reference(params),
              f"{GCI} + ISO's q' fit + the unit load's band", ((tooth_mesh_checks.STUDY, tooth_mesh_checks.PAIR),)),
    CheckSpec("mesh.rigid_rim_sharing", "mesh",
              lambda ctx: mesh_closed_form_checks.rigid_rim_check(ctx.book, ctx.label(mesh_closed_form_checks.STUDY),
                                                                  ctx.params),
              None, f"{GCI} (the closed form solves the same contact problem exactly)"),
    CheckSpec("mesh.engagement_zone", "mesh",
              lambda ctx: mesh_closed_form_checks.zone_check(ctx.book, ctx.label(mesh_closed_form_checks.STUDY),
                                                             ctx.params),
              lambda params, at: Reference(None, mesh_closed_form_checks.zone_reference(params)[0], "rad",
                                           "analytic/engagement_zone.py"),
              f"{GCI} + one FS pitch + the contact point (tip vs mid-overlap)",
              ((mesh_closed_form_checks.STUDY, mesh_closed_form_checks.ZONE),)),
    # issue 49: the flexspline's torsional buckling, FE eigenvalue of the full tube (validate's own three meshes)
    CheckSpec("cup.buckling_torque", "cup", _buckling,
              lambda params, at: buckling_checks.reference(params),
              f"{GCI} + Donnell's 1/n^2 + the Galerkin sum's truncation", record=_buckling_record),
    # issue 48 item 3: Hertz at the flank, the real cup and spline teeth in plane-strain contact at a small load
    CheckSpec(flank_hertz_checks.CHECK_P0, "mesh", _pick(_flank_hertz, flank_hertz_checks.CHECK_P0),
              lambda params, at: flank_hertz_checks.reference(params, "p0"), flank_hertz_checks.TOLERANCE,
              record=_flank_hertz_record),
    CheckSpec(flank_hertz_checks.CHECK_B, "mesh", _pick(_flank_hertz, flank_hertz_checks.CHECK_B),
              lambda params, at: flank_hertz_checks.reference(params, "b"), flank_hertz_checks.TOLERANCE),
)

REQUIRED_IDS = tuple(spec.id for spec in CHECKS)

# The report's section title of each component, in the report's order (a component without one is titled by its name).
SECTIONS = {"shaft": "Output shaft (seed 000)", "cup": "Flexspline cup (seed 000)",
            "bearing": "Wave-generator bearing inner ring (seed 000)", "ring": "EWG flexspline ring (seed 003)",
            "gear": "Drive stiffness (seed 000)", "mesh": "Teeth in mesh (issue 48)"}


def current() -> tuple[CheckSpec, ...]:
    """The check list as it stands now (read at call time, so a registered addition counts everywhere)."""
    import sys
    return sys.modules[__name__].CHECKS


def sections(checks: tuple[CheckSpec, ...] | None = None) -> tuple[tuple[str, str], ...]:
    """(component, title) of the report's sections: every component of the check list, in its order."""
    components = dict.fromkeys(s.component for s in (checks or current()))
    return tuple((c, SECTIONS.get(c, c)) for c in components)


def check_spec(check_id: str, checks: tuple[CheckSpec, ...] | None = None) -> CheckSpec:
    return next(s for s in (checks or current()) if s.id == check_id)


def beside(study: str, checks: tuple[CheckSpec, ...] | None = None) -> dict[str, CheckSpec]:
    """{FEA quantity of ``study``: the CheckSpec whose closed form stands beside it}."""
    return {q: spec for spec in (checks or current()) for s, q in spec.beside if s == study}

