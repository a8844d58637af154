"""Which FEA cases a validation runs: the headline case per study plus a crack-depth sweep per component.

The seed's default crack (0.1 mm) changes a flexibility by parts per million, below what a mesh
resolves; the sweep therefore runs from a small fraction of the wall to about half of it, where the
crack compliance is measurable and its growth with depth (a^2 or a^3) can be fitted. --quick runs one
depth per component (the deepest), the full run the seed's depth plus three.
"""
from __future__ import annotations

from dataclasses import dataclass


import numpy as np

from strainwave.registry import STUDIES
from strainwave.compare.validate.runner import Case

# component -> its study, from the registry (the crack-bearing studies)
COMPONENT_STUDY = {s.component: s.name for s in STUDIES.values() if s.component}


@dataclass(frozen=True)
class Plan:
    headline: dict[str, Case]                      # component -> case at the default crack depth
    sweeps: dict[str, tuple[Case, ...]]            # component -> deeper cracks
    singles: tuple[Case, ...] = ()                 # one uncracked case per study without a crack, registry order

    def all_cases(self) -> tuple[Case, ...]:
        cases = list(self.headline.values())
        for sweep in self.sweeps.values():
            cases += list(sweep)
        return tuple(cases) + self.singles

    def case_of(self, study: str) -> Case | None:
        """The one case of a study without a crack (None: not in this plan)."""
        return next((c for c in self.singles if c.study == study), None)

    def label_of(self, study: str) -> str | None:
        case = self.case_of(study)
        return None if case is None else case.label

    def reported(self) -> list[tuple[str, Case]]:
        """(component, case) of the report's inputs and stress sections and of the design factors: each crack
        component's headline case, then each single study its variant shows under a component
        (``StudyFacts.report_component``) whose field is a design stress (no ``outside_design``)."""
        return list(self.headline.items()) + [(f.report_component, c) for f, c in self._shown() if not f.outside_design]

    def pictured(self) -> list[tuple[str, Case]]:
        """(component, case) of each single study drawn in its component's section but kept out of the design
        factors and the stress table (``StudyFacts.outside_design`` says why)."""
        return [(f.report_component, c) for f, c in self._shown() if f.outside_design]

    def _shown(self) -> list[tuple[type, Case]]:
        facts = [(STUDIES[c.study].facts(), c) for c in self.singles]
        return [(f, c) for f, c in facts if f.report_component]


def single_cases() -> tuple[Case, ...]:
    """One uncracked case per registry study without a crack component, labelled as its variant says."""
    return tuple(Case(s.facts().validate_label or s.name, s.name, None) for s in STUDIES.values() if not s.component)


def sweep_limits_mm(params) -> dict[str, float]:
    """Deepest crack per component, as its study's variant states (``StudyFacts.deepest_crack_mm``)."""
    return {c: STUDIES[s].facts().deepest_crack_mm(params) for c, s in COMPONENT_STUDY.items()}


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
    facts = STUDIES[COMPONENT_STUDY[component]].facts()
    return facts.default_size_mm(params, True) if facts.sweep_at_quick_size else None


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
            # only the deepest sweep case's field is drawn (the crack-tip close-up): the others write none, and it
            # writes the crack's own field alone where its study can (the close-up reads no other)
            alone = STUDIES[COMPONENT_STUDY[c]].facts().crack_field_alone
            sweeps[c] = tuple(Case(f"{c}-a{d:g}", COMPONENT_STUDY[c], d, sweep_h, fields=d == deeper[-1],
                                   crack_field_only=alone and d == deeper[-1]) for d in deeper)
    plan = Plan(headline, sweeps, single_cases())
    for case in plan.all_cases():   # every crack checked against its own wall before any mesh is built
        with_crack(case.study, params, case.crack_depth_mm)
    return plan
