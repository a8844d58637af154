"""All checks of a validation run, plus the crack sweeps and fitted exponents they rest on."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from strainwave.registry import STUDIES
from strainwave.compare.validate.check_list import At, CheckContext, CheckSpec, beside, current
from strainwave.compare.validate.checks import Check, not_evaluated, quick_resolution
from strainwave.compare.validate.crack_scaling import PowerFit, fit_power_law
from strainwave.compare.validate.fea_book import FeaBook, Sweep
from strainwave.compare.validate.plan import COMPONENT_STUDY, Plan

@dataclass(frozen=True)
class SweepReport:
    sweep: Sweep
    fit: PowerFit | None                       # over the resolved depths
    analytic: dict[str, list[float]]           # variant -> closed form at each depth
    analytic_fits: dict[str, float] = field(default_factory=dict)   # variant -> exponent over resolved depths
    range_notes: tuple[str, ...] = ()          # per depth: "" or why the corrected form is used out of range

    def to_dict(self) -> dict:
        return {**self.sweep.to_dict(), "fit": None if self.fit is None else self.fit.to_dict(),
                "analytic": self.analytic, "analytic_exponents": self.analytic_fits,
                "range_notes": list(self.range_notes)}


@dataclass(frozen=True)
class CheckSet:
    checks: tuple[Check, ...]
    sweeps: dict[str, SweepReport]
    records: dict[str, dict] = field(default_factory=dict)     # check id -> its CheckSpec.record (non-empty)

    def by_id(self) -> dict[str, Check]:
        return {c.id: c for c in self.checks}


def _sweep_report(sweep: Sweep, curve, range_note=None) -> SweepReport:
    analytic = {}
    for depth in sweep.depths_mm:
        for variant, value in curve(depth).items():
            analytic.setdefault(variant, []).append(value)
    ok = sweep.resolved(3.0)
    depths = np.asarray(sweep.depths_mm)[ok]
    fit = fit_power_law(depths, np.asarray(sweep.values)[ok])
    analytic_fits = {}
    if fit is not None:
        for variant, values in analytic.items():
            f = fit_power_law(depths, np.asarray(values)[ok])
            if f is not None:
                analytic_fits[variant] = f.exponent
    notes = tuple(range_note(d) for d in sweep.depths_mm) if range_note is not None else ()
    return SweepReport(sweep, fit, analytic, analytic_fits, notes)


def _variants(reference) -> dict[str, float]:
    return {} if reference is None else reference.variants()


def _sweeps(ctx: CheckContext, checks: tuple[CheckSpec, ...]) -> dict[str, SweepReport]:
    """Per crack component, its FEA sweep beside the closed form of the check that stands beside its crack
    delta (``CheckSpec.reference``, at each depth and the FEA's force)."""
    out = {}
    for component, name in COMPONENT_STUDY.items():
        study = STUDIES[name]
        spec = beside(name, checks).get(study.crack_delta.name)
        labels = [ctx.plan.headline[component].label] + [c.label for c in ctx.plan.sweeps[component]]
        sweep = ctx.book.sweep(component, labels, study.crack_delta.name)
        if sweep is None or spec is None or spec.reference is None:
            continue
        force = ctx.book.applied_force_N(labels[0])
        note = None if spec.range_note is None else (lambda a, f=spec.range_note: f(ctx.params, a))
        out[component] = _sweep_report(sweep, lambda a, r=spec.reference: _variants(r(ctx.params, At(a, force))),
                                       note)
    return out


def build_checks(book: FeaBook, plan: Plan, summary: dict, params,
                 checks: tuple[CheckSpec, ...] | None = None, *, quick: bool = False) -> CheckSet:
    """Every check of ``checks`` (the check list), in their order; one whose builder made none is listed as not
    evaluated. ``quick``: a check the coarse meshes do not resolve is reported so (``checks.quick_resolution``)."""
    checks = checks or current()
    ctx = CheckContext(book, plan, summary, params)
    built = []
    for spec in checks:
        check = spec.builder(ctx)
        check = check if check is not None else not_evaluated(spec.id, spec.id, "", "no builder produced this check")
        built.append(quick_resolution(check) if quick else check)
    records = {spec.id: spec.record(ctx) for spec in checks if spec.record is not None}
    return CheckSet(tuple(built), _sweeps(ctx, checks), {k: r for k, r in records.items() if r})
