"""Every image of the report for one run: stress renders, crack-tip close-ups, ring shape, plots.

A picture that cannot be made is recorded with its reason (it is not silently left out), so the report
can say what is missing and why.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from strainwave.compare.validate import plots
from strainwave.compare.validate.check_set import CheckSet
from strainwave.compare.validate.fea_book import FeaBook
from strainwave.compare.validate.plan import Plan
from strainwave.rated_stress import StressAtRated, rated_load_of, stress_at_rated, stress_field_of
from strainwave.compare.validate.gci_table import asymptotic_flags
from strainwave.compare.validate.wg_bearing_checks import STUDY as WG_BEARING

def _component_titles() -> dict[str, str]:
    from strainwave.registry import STUDIES
    titles = {}
    for s in STUDIES.values():
        facts = s.facts()
        if facts.outside_design:
            continue   # drawn under another study's component, with its own title
        if facts.report_component or s.component:
            titles[facts.report_component or s.component] = facts.title
    return titles


# component -> its title on pictures, as each study's variant states it
COMPONENT_TITLES = _component_titles()


@dataclass(frozen=True)
class Image:
    path: Path           # relative to the output folder
    caption: str
    component: str       # shaft | cup | bearing | ring | gear
    kind: str            # preview | stress | closeup | ring-shape | convergence | crack-sweep | crack-opening

    def to_dict(self) -> dict:
        return {"path": self.path.as_posix(), "caption": self.caption, "component": self.component,
                "kind": self.kind}


@dataclass(frozen=True)
class Missing:
    what: str
    reason: str

    def to_dict(self) -> dict:
        return {"what": self.what, "reason": self.reason}


@dataclass(frozen=True)
class Drawn:
    """What a picture gives besides its PNG: the caption and the records the report merges (the stress at the
    rated load and the 3D view of a component, a part that could not be made)."""
    caption: str
    stresses: dict = field(default_factory=dict)      # component -> StressAtRated
    views: dict = field(default_factory=dict)         # component -> view3d.View
    missing: tuple[Missing, ...] = ()


@dataclass(frozen=True)
class Attempted:
    """One picture's outcome, as typed records (a worker process sends it back to be merged in order)."""
    image: Image | None
    drawn: Drawn | None
    failure: Missing | None
    said: tuple[str, ...] = ()


class _Collector:
    """The pictures to make, in the report's order; ``run`` makes them in two processes (``image_workers``)."""

    def __init__(self, out_dir: Path, progress, checkpoint: Callable[[], None] = lambda: None):
        self.out_dir, self.progress, self.checkpoint = Path(out_dir), progress, checkpoint
        self.tasks: list[tuple] = []

    def attempt(self, what: str, component: str, kind: str, make: Callable[[Path], str | Drawn], name: str) -> None:
        self.tasks.append((what, component, kind, make, name))

    def one(self, k: int) -> Attempted:
        what, component, kind, make, name = self.tasks[k]
        target = self.out_dir / "images" / name
        try:
            drawn = make(target)
        except Exception as exc:  # noqa: BLE001 - a failed picture is reported, the run goes on
            reason = f"{type(exc).__name__}: {exc}"
            return Attempted(None, None, Missing(what, reason), (f"  image {name}: FAILED ({reason})",))
        drawn = drawn if isinstance(drawn, Drawn) else Drawn(drawn)
        return Attempted(Image(target.relative_to(self.out_dir), drawn.caption, component, kind), drawn, None)

    def run(self) -> "Artifacts":
        """Every picture (two at a time), merged in the order they were asked for."""
        from strainwave.compare.validate.image_workers import run_tasks

        images, missing, stresses, views = [], [], {}, {}
        outcomes = run_tasks(len(self.tasks), self.one, self.checkpoint,
                             lambda k, why: Attempted(None, None, Missing(self.tasks[k][0], why)))
        for outcome in outcomes:
            for line in outcome.said:
                self.progress(line)
            if outcome.failure is not None:
                missing.append(outcome.failure)
                continue
            images.append(outcome.image)
            missing += outcome.drawn.missing
            stresses.update(outcome.drawn.stresses)
            views.update(outcome.drawn.views)
        return Artifacts(images, missing, stresses, views)


def _vtu(book: FeaBook, label: str, prefer: str = "") -> Path | None:
    """The case's VTU; with several (e.g. ``_cracked``/``_uncracked``, ``_smooth``/``_toothed``) the one
    whose name ends with ``prefer``."""
    outcome = book.outcomes.get(label)
    if outcome is None or outcome.result is None:
        return None
    files = [Path(p) for p in outcome.result.fields if str(p).endswith(".vtu") and Path(p).exists()
             and not str(p).endswith(".boundary.vtu")]
    preferred = [p for p in files if prefer and p.stem.endswith(prefer) and not p.stem.endswith("un" + prefer)]
    return (preferred or files or [None])[0]


def _require(path):
    if path is None:
        raise FileNotFoundError("the case wrote no VTU field (or it failed)")
    return path


# What a planar field of a component is, said on its picture
SECTION_OF_PLANE = {"shaft": "axisymmetric (r, z) section: x = r, y = z",
                    "ring": "2D plane stress section (x, y), thickness = face width B",
                    "wg-bearing": "2D plane stress section (x, y), thickness = ring width B"}
def _marks(images, study: str):
    """Supports and loads as the study applies them (its variant's ``image_marks``)."""
    from strainwave.registry import study as registered
    marks = registered(study).facts().image_marks
    if marks is None:
        raise ValueError(f"study {study} states no image marks")
    return images.Marks(*marks)


def _case_field(book: FeaBook, case):
    """(result, VTU, cracked) of the field a case's stress picture shows (``stress_field_of``)."""
    result = book.result(case.label)
    if result is None:
        raise FileNotFoundError(f"case {case.label} has no result")
    found = stress_field_of(case.study, result.fields, case.crack_depth_mm)
    if found is None or not found[0].exists():
        raise FileNotFoundError("the case wrote no VTU field (or it failed)")
    return result, *found


def _stress_picture(images, target: Path, book: FeaBook, component: str, case, params) -> Drawn:
    result, vtu, cracked = _case_field(book, case)
    at = stress_at_rated(case.study, params, result, vtu, cracked=cracked)
    planar = bool(np.ptp(images.read_field(vtu).points[:, 2]) == 0.0)
    from strainwave.registry import study as registered
    radius = registered(case.study).facts().image_zoom_mm(params)   # a second panel on the peak, if the study has one
    zoom = None if radius is None else images.Zoom(radius_mm=radius, title="tooth root at the peak")
    rendered = images.render_stress(vtu, target, label=COMPONENT_TITLES[component], at=at,
                                    marks=_marks(images, case.study),
                                    section=SECTION_OF_PLANE.get(component, "2D section") if planar else "",
                                    zoom=zoom)
    from strainwave.compare.validate.view3d import make_view
    try:
        view = make_view(component, vtu, at, exaggeration=rendered.exaggeration or 1.0,
                         label=COMPONENT_TITLES[component])
    except Exception as exc:  # noqa: BLE001 - a view that cannot be made is reported, the PNG stands
        return Drawn(rendered.caption, {component: at}, {},
                     (Missing(f"{COMPONENT_TITLES[component]} 3D view", f"{type(exc).__name__}: {exc}"),))
    return Drawn(rendered.caption, {component: at}, {component: view})


NO_DESIGN_LINE = "no design factor: why in the caption"


def _pictured_stress(images, target: Path, book: FeaBook, case, params) -> str:
    """The stress picture of a study whose field is no design stress (``StudyFacts.outside_design``): drawn
    like a design field, its peak kept out of every factor and of the stress table, its caption says why."""
    from strainwave.rated_stress import crack_front_nodes
    from strainwave.registry import study as registered
    facts = registered(case.study).facts()
    result, vtu, _ = _case_field(book, case)
    # a field with a crack front (the block around a crack) leaves the front's singular zone out of its peak
    cracked = result.crack is not None and crack_front_nodes(vtu).size > 0
    at = stress_at_rated(case.study, params, result, vtu, cracked=cracked)
    planar = bool(np.ptp(images.read_field(vtu).points[:, 2]) == 0.0)
    rendered = images.render_stress(vtu, target, label=facts.title, at=at, marks=_marks(images, case.study),
                                    section=SECTION_OF_PLANE.get(case.study, "2D section") if planar else "",
                                    factor_line=NO_DESIGN_LINE, view_from=facts.image_view_from)
    return rendered.caption.replace(NO_DESIGN_LINE, f"no design factor: {facts.outside_design}")


def _signed_picture(images, target: Path, book: FeaBook, case, params) -> str:
    """The signed stress its variant names (``StudyFacts.signed_stress``) at the rated load."""
    from strainwave.registry import study as registered
    facts = registered(case.study).facts()
    result, vtu, _ = _case_field(book, case)
    array, words = facts.signed_stress
    return images.render_signed(vtu, target, label=facts.title, array=array, words=words,
                                load=rated_load_of(case.study, params, result), view_from=facts.image_view_from).caption


def _opening_picture(images, target: Path, book: FeaBook, case) -> str:
    """The crack's opening in each state the study drew (``StudyFacts.crack_opening_states``)."""
    from strainwave.registry import study as registered
    facts = registered(case.study).facts()
    result = book.result(case.label)
    if result is None:
        raise FileNotFoundError(f"case {case.label} has no result")
    files = [Path(p) for p in result.fields if Path(p).exists()]
    vtus = {}
    for state in facts.crack_opening_states:
        found = [p for p in files if p.suffix == ".vtu" and p.stem.endswith(f"_{state}")]
        if not found:
            raise FileNotFoundError(f"case {case.label} wrote no field of its {state} state")
        vtus[state] = found[0]
    depth = "" if result.crack is None else f", a = {result.crack.depth_mm:g} mm"
    return images.render_crack_opening(vtus, target, label=f"{facts.title}{depth}").caption


@dataclass(frozen=True)
class Artifacts:
    images: list[Image]
    missing: list[Missing]
    stresses: dict[str, StressAtRated]     # component -> its stress field at the rated load
    views: dict                            # component -> view3d.View (interactive 3D, for report.html)


def make_images(out_dir: Path, book: FeaBook, plan: Plan, check_set: CheckSet, summary: dict,
                progress: Callable[[str], None], *, params,
                checkpoint: Callable[[], None] = lambda: None) -> Artifacts:
    """Every picture; also the stress at the rated load per component (the numbers the pictures print) and
    the interactive 3D view of each stress field. ``checkpoint`` is called before each picture (see
    ``strainwave.interrupt``)."""
    from strainwave.compare.validate import images  # pyvista only here

    col = _Collector(out_dir, progress, checkpoint)
    for component, case in plan.reported():
        col.attempt(f"{COMPONENT_TITLES[component]} stress", component, "stress",
                    lambda t, c=component, cs=case: _stress_picture(images, t, book, c, cs, params),
                    f"{component}_von_mises.png")
    from strainwave.registry import study as registered
    for component, case in plan.pictured():
        facts = registered(case.study).facts()
        col.attempt(f"{facts.title} stress", component, "stress",
                    lambda t, cs=case: _pictured_stress(images, t, book, cs, params), f"{case.label}_von_mises.png")
        if facts.signed_stress:
            col.attempt(f"{facts.title}: {facts.signed_stress[1]}", component, "stress",
                        lambda t, cs=case: _signed_picture(images, t, book, cs, params), f"{case.label}_signed.png")
        if facts.crack_opening_states:
            col.attempt(f"{facts.title}: crack opening", component, "crack-opening",
                        lambda t, cs=case: _opening_picture(images, t, book, cs), f"{case.label}_opening.png")
    for component, cases in plan.sweeps.items():
        if not cases:
            continue
        deepest = cases[-1]
        vtu = _vtu(book, deepest.label, "_cracked")
        title = f"{COMPONENT_TITLES[component]}, crack a = {deepest.crack_depth_mm:g} mm"
        solved = book.result(deepest.label)
        z0 = solved.crack.z_mm if solved is not None and solved.crack is not None else None
        radius = 3.0 * deepest.crack_depth_mm  # a few crack depths show the tip field and the slot
        col.attempt(f"{title} close-up", component, "closeup",
                    lambda t, v=vtu, ti=title, z=z0, r=radius, c=component, cs=deepest: images.render_closeup(
                        _require(v), t, label=ti, radius_mm=r, near_z_mm=z,
                        section=SECTION_OF_PLANE.get(c, "2D section"),
                        load=rated_load_of(cs.study, params, book.outcomes[cs.label].result)).caption,
                    f"{component}_crack_tip.png")
    col.attempt("ring mid-layer", "ring", "ring-shape",
                lambda t: _ring_shape(t, book, plan, check_set, summary), "ring_mid_layer.png")
    for check in check_set.checks:
        label = _case_of(check, plan)
        if label is None:
            continue
        col.attempt(f"{check.id} convergence", check.component, "convergence",
                    lambda t, c=check, lb=label: _convergence(t, c, book, lb), f"{check.id.replace('.', '_')}_convergence.png")
    for component, report in check_set.sweeps.items():
        # bearing.crack_compliance tests the race crack of the ring on the cam (wg-bearing), not this bonded-bore
        # sweep (a table only): its plot shows the quantity the check tests
        make = (lambda t: _bearing_sweep(t, book, plan.label_of(WG_BEARING) or "", params)) \
            if component == "bearing" else (lambda t, r=report, c=component: _sweep(t, r, c))
        col.attempt(f"{component} crack sweep", component, "crack-sweep", make, f"{component}_crack_sweep.png")
    return col.run()


def _case_of(check, plan: Plan) -> str | None:
    """The case whose convergence history the check's plot draws (``CheckSpec.plot``), if it has one."""
    from strainwave.compare.validate.check_list import CHECKS
    spec = next((s for s in CHECKS if s.id == check.id), None)
    if spec is None or spec.plot is None or check.fea is None:
        return None
    from strainwave.registry import STUDIES
    component = STUDIES[spec.plot[0]].component
    return plan.headline[component].label if component in plan.headline else plan.label_of(spec.plot[0])


def _convergence(target: Path, check, book: FeaBook, label: str) -> str:
    from strainwave.compare.validate.check_list import check_spec
    q, why = book.quantity(label, check_spec(check.id).plot[1])
    if q is None or q.convergence is None:
        raise ValueError(why or f"{check.id}: the study gave no three-mesh convergence data")
    c = q.convergence
    flags = asymptotic_flags(c)
    plots.convergence_plot(target, title=f"{check.id}: {q.name}", unit=q.unit, h_mm=c.h_mm, values=c.values,
                           extrapolated=c.extrapolated, gci_fine=c.gci_fine, observed_order=c.order_used,
                           analytic=check.analytic if check.id not in ("gear.stiffness",) else None, flags=flags)
    return (f"{check.id}: {q.name} on three meshes (h = {', '.join(f'{h:.3g}' for h in c.h_mm)} mm), observed "
            f"order {c.observed_order:.2f} (formal {c.formal_order:g}), GCI {100 * c.gci_fine:.3g} % ({c.basis})"
            + (f" (not asymptotic: {', '.join(flags)})" if flags else "") + "; right: the fine value against the "
            "closed forms")


def _sweep(target: Path, report, component: str) -> str:
    sw = report.sweep
    curves = {}
    for variant, values in report.analytic.items():
        curves[variant] = (np.asarray(sw.depths_mm), np.asarray(values))
    fit = report.fit
    label = "" if fit is None else f"fitted a^{fit.exponent:.2f}"
    plots.crack_sweep_plot(target, title=f"{COMPONENT_TITLES[component]}: crack compliance vs depth",
                           unit=sw.unit, depths_mm=sw.depths_mm, fea=sw.values, fea_uncertainty=sw.uncertainties,
                           curves=curves, fit_label=label)
    exps = ", ".join(f"{k} a^{v:.2f}" for k, v in report.analytic_fits.items())
    return (f"{COMPONENT_TITLES[component]}: {sw.quantity} against crack depth, FEA (with GCI bars) and both closed "
            f"forms" + (f"; FEA {label}, closed forms {exps}" if label else ""))


def _bearing_sweep(target: Path, book: FeaBook, label: str, params) -> str:
    """What bearing.crack_compliance tests: the race crack's added radial compliance of the ring on the cam
    (wg-bearing case) at each depth, against the edge-crack weight function at the exact ring's stress (corrected)
    and seed 000's form (published), the curves the check itself evaluates."""
    from strainwave.compare.validate.wg_bearing_checks import crack_curve, crack_sweep

    sweep, result = crack_sweep(book, label), book.result(label)
    if sweep is None or result is None:
        raise ValueError(f"case {label} produced no crack compliance")
    curve = crack_curve(params, result)
    depths = np.asarray(sweep.depths_mm, float)
    values = [curve(float(d)) for d in depths]
    curves = {v: (depths, np.array([row[v] for row in values])) for v in ("published", "corrected")}
    plots.crack_sweep_plot(target, title=f"{COMPONENT_TITLES['bearing']} on the cam: race crack compliance vs depth",
                           unit=sweep.unit, depths_mm=depths, fea=sweep.values, fea_uncertainty=sweep.uncertainties,
                           curves=curves)
    return (f"{COMPONENT_TITLES['bearing']}: the quantity bearing.crack_compliance tests, the race crack's added "
            f"radial compliance (FEA {label}, GCI bars) against the edge-crack weight function at the exact ring's stress "
            "(corrected) and seed 000's form (published)")


def _ring_shape(target: Path, book: FeaBook, plan: Plan, check_set: CheckSet, summary: dict) -> str:
    from strainwave.compare.validate.images import sample_circle

    from strainwave.compare.validate.check_list import RING
    vtu = _require(_vtu(book, plan.label_of(RING) or "", "_smooth"))
    checks = check_set.by_id()
    cd, ab = checks["ring.delta_cd"], checks["ring.delta_ab"]
    if cd.fea is None or ab.fea is None or "published" not in cd.analytic:
        raise ValueError("ring delta_CD/delta_AB not evaluated")
    r_m = summary["seed003"]["geometry"]["r_m_mm"]
    sampled = sample_circle(vtu, r_m)
    if sampled is None or len(sampled[0]) < 10:
        raise ValueError(f"{vtu}: the mid-layer circle r = {r_m:g} mm does not cross the mesh")
    theta, u_r, _ = sampled
    load_angle = float(theta[np.argmin(u_r)])  # the loaded points move inward the most
    if np.sin(load_angle) < 0:  # name the upper load point D, so B (phi = 0) lands at +x as in fea/ring_*
        load_angle += np.pi
    plots.ring_midlayer_plot(target, r_m_mm=r_m, theta=theta, u_r_fea=u_r, delta_cd_fea=cd.fea, delta_ab_fea=ab.fea,
                             delta_cd_analytic=cd.analytic["published"], delta_ab_analytic=ab.analytic["published"],
                             load_angle_rad=load_angle)
    return ("EWG ring: deformed mid-layer from the FEA field against the thin-ring shape (seed 003 eqs 3-4), "
            "delta_CD and delta_AB marked at C, D and A, B")
