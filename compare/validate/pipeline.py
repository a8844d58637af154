"""``strainwave validate``: every study on the parameters, confronted with both seeds' closed forms.

Stages (each timed, progress on the terminal): analytic model -> STEP of every part -> FEA cases
(headline per component, crack-depth sweeps, the ring) -> checks -> seed audit with FEA evidence ->
images and plots -> results.json (schema-validated), report.md, report.html. Every file is written under
a temporary name and renamed; finished FEA cases and STEP files are reused from ``<out>/cache`` on a
rerun with the same parameters and code. The run passes only if every required check passes.
"""
from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from strainwave.compare.validate.audit_evidence import audit_with_evidence, exponent_evidence
from strainwave.cache import ResultCache
from strainwave.compare.validate.check_set import CheckSet, build_checks
from strainwave.compare.validate.checks import Check
from strainwave.compare.validate.designer_table import designer_table
from strainwave.compare.validate.run_record import run_record
from strainwave.compare.validate.design import DesignVerdict, design_verdict
from strainwave.compare.validate.fea_book import FeaBook
from strainwave.compare.validate.gci_table import gci_rows
from strainwave.compare.validate.isolated import stop_descendants
from strainwave.compare.validate.nafems_appendix import NafemsJob
from strainwave.io_atomic import remove_stale_temps
from strainwave.compare.validate.plan import make_plan
from strainwave.compare.validate.report_html import write_html
from strainwave.compare.validate.catalogue_table import catalogue_document
from strainwave.compare.validate.mesh_chain_checks import gear_line
from strainwave.compare.validate.report_pdf import chromium, print_pdf
from strainwave.compare.validate.tables_csv import CSV_FILES, write_tables
from strainwave.compare.validate.report_md import write_markdown
from strainwave.compare.validate.results import now_utc, plain, versions, write_results
from strainwave.compare.validate.case_progress import CaseProgress
from strainwave.compare.validate.runner import CaseOutcome, run_case
from strainwave.compare.validate.wg_bearing_checks import STUDY as WG_BEARING_STUDY
from strainwave.compare.validate.wg_cup_checks import STUDY as WG_CUP_STUDY, wg_record

ORDER = 2   # quadratic elements, the fea/ default (curved P2)


@dataclass(frozen=True)
class Outcome:
    out_dir: Path
    checks: tuple[Check, ...]
    timings_s: dict[str, float]
    cases: tuple[CaseOutcome, ...]
    design: DesignVerdict | None = None     # does the drive meet [n] at the rated load (not the exit status)

    @property
    def passed(self) -> bool:
        """The validation verdict: every closed form the checks assert holds."""
        return bool(self.checks) and all(c.passed for c in self.checks)

    @property
    def design_passed(self) -> bool:
        return self.design is not None and self.design.passed

    def summary(self) -> str:
        width = max(len(c.id) for c in self.checks)
        lines = [f"{'check':<{width}}  {'FEA':>11}  {'published':>11} {'err':>9}  {'corrected':>11} {'err':>9}  "
                 f"{'tol':>7}  {'verdict':<13} result"]
        for c in self.checks:
            def val(v):
                return f"{v:11.4g}" if v is not None else f"{'n/a':>11}"

            def err(v):
                return f"{100 * v:+8.3g}%" if v is not None else f"{'':>9}"

            tol = f"{100 * c.tolerance.relative:6.3g}%" if c.tolerance.relative == c.tolerance.relative else " " * 7
            result = "PASS" if c.passed else ("NOT EVALUATED" if c.verdict == "not evaluated" else "FAIL")
            lines.append(f"{c.id:<{width}}  {val(c.fea)}  {val(c.analytic.get('published'))} "
                         f"{err(c.rel_error.get('published'))}  {val(c.analytic.get('corrected'))} "
                         f"{err(c.rel_error.get('corrected'))}  {tol}  {c.verdict:<13} {result}")
        failing = [c for c in self.checks if not c.passed]
        if failing:
            lines.append(f"FAILING ({len(failing)}):")
            lines += [f"  {c.id}: " + (c.reason_not_evaluated or
                                        f"FEA differs from the {c.asserts} form by "
                                        f"{100 * c.rel_error.get(c.asserts, float('nan')):+.3g} % "
                                        f"(tolerance {100 * c.tolerance.relative:.3g} %)") for c in failing]
        cached = sum(1 for c in self.cases if c.cached)
        lines.append(f"{sum(c.passed for c in self.checks)}/{len(self.checks)} checks pass; "
                     f"{len(self.cases)} FEA cases ({cached} reused from cache); time per stage: "
                     + ", ".join(f"{k} {v:.1f} s" for k, v in self.timings_s.items()))
        lines.append(f"validation (do the closed forms hold?): {'PASS' if self.passed else 'FAIL'}")
        if self.design is not None:
            lines.append(f"design (does the drive meet [n] at the rated load?): {self.design.headline()}")
        beside = [n for n in ("report.pdf", "checks.csv", "gci.csv", "stress.csv", "design.csv") if (self.out_dir / n).exists()]
        lines.append(f"report: {self.out_dir / 'report.html'}" + (f" (beside it: {', '.join(beside)})" if beside else ""))
        return "\n".join(lines)


@contextmanager
def _stage(name: str, timings: dict, progress: Callable[[str], None], number: int, total: int):
    progress(f"[{number}/{total}] {name} ...")
    start = time.perf_counter()
    yield
    timings[name] = time.perf_counter() - start
    progress(f"[{number}/{total}] {name} done in {timings[name]:.1f} s")


@contextmanager
def _shader_cache(folder: Path):
    """Mesa's shader cache in the run's own cache folder while this process renders the images.

    The CLI disables the cache (it would write to ~/.cache), so every off-screen plotter compiled its
    shaders anew; a cache of its own makes the images stage much faster, the PNGs byte-identical
    (docs/decisions/014-validate-case-isolation.md). Only this process and only here: a background
    process that is killed (the STEP export, on an interrupted run) could leave a half-written cache entry.
    A user's own MESA_SHADER_CACHE_DIR is left as it is."""
    if "MESA_SHADER_CACHE_DIR" in os.environ:
        yield
        return
    saved = os.environ.get("MESA_SHADER_CACHE_DISABLE")
    os.environ["MESA_SHADER_CACHE_DIR"] = str(folder)
    os.environ["MESA_SHADER_CACHE_DISABLE"] = "false"
    try:
        yield
    finally:
        os.environ.pop("MESA_SHADER_CACHE_DIR", None)
        if saved is None:
            os.environ.pop("MESA_SHADER_CACHE_DISABLE", None)
        else:
            os.environ["MESA_SHADER_CACHE_DISABLE"] = saved


def _case_record(outcome: CaseOutcome, out_dir: Path) -> dict:
    result = None
    if outcome.result is not None:
        result = outcome.result.to_dict()
        result["fields"] = [_relative(p, out_dir) for p in outcome.result.fields]
    return {"label": outcome.case.label, "study": outcome.case.study, "crack_depth_mm": outcome.case.crack_depth_mm,
            "ok": outcome.ok, "cached": outcome.cached, "seconds": outcome.seconds, "cpu_s": outcome.cpu_s,
            "error": outcome.error,
            "result": result}


def _relative(path, out_dir: Path) -> str:
    path = Path(path)
    try:
        return path.resolve().relative_to(out_dir.resolve()).as_posix()
    except ValueError:
        return path.as_posix()


def _shaft_exponent(check_set: CheckSet) -> dict | None:
    report = check_set.sweeps.get("shaft")
    if report is None:
        return None
    return exponent_evidence(report.fit, report.analytic_fits or {"published": 3.0, "corrected": 2.0})


def _output_folders(out_dir: Path) -> tuple[Path, ...]:
    """Every folder a validation writes files into."""
    return (out_dir, out_dir / "step", out_dir / "fields", out_dir / "images", out_dir / "cache")


def _run_cases(cases, params, *, fields_dir: Path, cache, quick: bool, progress) -> dict[str, CaseOutcome]:
    """Solve the cases two at a time, longest first: each runs in its own child process (the threads only
    wait on them), and the machine this targets has two cores. Results keep the plan's order."""
    from strainwave.compare.validate.schedule import durations_file, load_durations, longest_first, save_durations

    workers = max(1, min(2, os.cpu_count() or 1))
    timing_file = durations_file(Path(cache.root), quick)
    durations = load_durations(timing_file)
    tracker = CaseProgress(cases, params, quick=quick, workers=workers, progress=progress)

    def tracked(case):
        outcome = run_case(case, params, fields_dir=fields_dir, cache=cache, quick=quick, order=ORDER,
                           progress=progress)
        tracker.done(case.label, outcome.seconds, "cached" if outcome.cached else "solved" if outcome.ok else "FAILED")
        return outcome

    pool = ThreadPoolExecutor(max_workers=workers)
    try:
        futures = {case.label: pool.submit(tracked, case) for case in longest_first(cases, durations, tracker.costs)}
        outcomes = {case.label: futures[case.label].result() for case in cases}
    except KeyboardInterrupt:
        # Ctrl-C: queued cases must not start, running ones stop now. Their threads only wait on child
        # processes, which die with every process this run started below it.
        pool.shutdown(wait=False, cancel_futures=True)
        stop_descendants(os.getpid())
        remove_stale_temps(fields_dir)   # the stopped cases' half-written fields, under temporary names
        raise
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)   # a bug in a case runner: the rest need not start
        raise
    pool.shutdown(wait=True)
    save_durations(timing_file, [(o.case.label, o.seconds) for o in outcomes.values() if not o.cached],
                   durations)
    return outcomes


def _preview_of() -> dict[str, str]:
    """The part each reported study meshes -> the component whose inputs section its preview opens."""
    from strainwave.registry import STUDIES
    out = {}
    for s in STUDIES.values():
        facts = s.facts()
        component = facts.report_component
        if component and not facts.outside_design:   # the preview opens its design study's inputs section
            out.setdefault(s.part, component)
    return out


def _previews(steps, out_dir: Path) -> list:
    from strainwave.compare.validate.artifacts import Image

    preview_of = _preview_of()
    return [Image(Path(_relative(s.preview, out_dir)), f"{s.part}: the part as designed (uncracked), contact/load "
                  "faces in blue, fixed faces in green; right: close-up", preview_of[s.part], "preview")
            for s in steps if s.preview is not None and s.part in preview_of and Path(s.preview).exists()]


def _inputs(plan, book: FeaBook, params) -> dict:
    """The inputs-and-model record of every component that solved."""
    from strainwave.rated_stress import rated_load_of
    from strainwave.compare.validate.inputs import component_inputs

    out = {}
    for component, case in plan.reported():
        outcome = book.outcomes.get(case.label)
        if outcome is None or outcome.result is None:
            continue
        rated = rated_load_of(case.study, params, outcome.result)
        out[component] = component_inputs(component, case, outcome.result, params, rated).to_dict()
    return out


def _write_reports(out_dir: Path, doc: dict, views: dict[str, str], progress) -> None:
    """report.md, report.html (self-contained), the CSV tables, and report.pdf printed from the page. A PDF
    that cannot be printed is said on the terminal and in the reports (which then link none)."""
    write_markdown(out_dir / "report.md", doc)
    write_html(out_dir / "report.html", doc, views=views)
    write_tables(out_dir, doc)
    if doc["files"]["report_pdf"] is None:
        progress("  report.pdf: not printed: it needs Chromium (Debian/Ubuntu: sudo apt-get install chromium), then "
                 "rerun; report.html and report.md are complete without it")
        return
    try:
        try:
            print_pdf(out_dir / "report.html", out_dir / "report.pdf")
        except RuntimeError as first:   # Chromium's zygote sometimes dies at start in a container: one retry
            progress(f"  report.pdf: first print failed ({first}); retrying once")
            print_pdf(out_dir / "report.html", out_dir / "report.pdf")
    except RuntimeError as exc:
        progress(f"  report.pdf: not printed ({exc})")
        doc["files"]["report_pdf"] = None
        write_markdown(out_dir / "report.md", doc)
        write_html(out_dir / "report.html", doc, views=views)


def _metadata(params, quick: bool, step: bool, plan, outcomes, steps, timings: dict, out_dir: Path) -> dict:
    """results.json's metadata: when, with what, and what each case and STEP export cost."""
    return {
        "created_utc": now_utc(), "params": params.to_dict(), "versions": versions(),
        "settings": {"quick": quick, "order": ORDER, "mesh": "study defaults (quick: coarse), 3 refinements",
                     "solver": "fea/ default (see each case's meta)",
                     "step": step,
                     "step_export": ("background process at low priority, overlapping the FEA stage" if step
                                     else "not exported (--quick without --step)"),
                     "sweep_depths_mm": {k: [c.crack_depth_mm for c in v] for k, v in plan.sweeps.items()}},
        "cases": [_case_record(o, out_dir) for o in outcomes.values()],
        "steps": [{"part": s.part, "files": [_relative(p, out_dir) for p in s.files], "seconds": s.seconds,
                   "cached": s.cached, "error": s.error} for s in steps],
        "timings_s": dict(timings), "total_s": 0.0,
    }


def _designer_lines(summary: dict) -> list[str]:
    """The report's opening lines: seed 003's Z_R,min and seed 000's crack headline, both from FEA-confirmed forms."""
    from strainwave.analytic.summary import crack_headline_lines, design_lines, designer_headline
    return ((design_lines(summary["design"]) if "design" in summary else [])
            + (designer_headline(summary["seed003"]) if "seed003" in summary else [])
            + (crack_headline_lines(summary["crack_headline"]) if "crack_headline" in summary else []))


def _design(params, book, plan, stresses) -> tuple[dict, object]:
    """(the cup-on-the-wave-generator record, the design verdict): every factor by the one method of
    analytic/design_method.py on the FEA's cycles where the studies ran (compare/validate/design_fea.py)."""
    from strainwave.compare.validate.artifacts import COMPONENT_TITLES
    from strainwave.compare.validate.design_fea import design_factors_from_fea
    from strainwave.fea.ring_compression import STUDY as RING_STUDY
    from strainwave.fea.tooth_mesh import STUDY as MESH_STUDY

    wg_cup = wg_record(book, plan.label_of(WG_CUP_STUDY) or "", params)
    labels = {s: plan.label_of(s) for s in (RING_STUDY, WG_CUP_STUDY, WG_BEARING_STUDY, MESH_STUDY)}
    factors = design_factors_from_fea(params, book, labels, stresses, COMPONENT_TITLES,
                                      tuple(c for c, _ in plan.reported()), wg_cup)
    return wg_cup, design_verdict(params, factors)


def _ratcheting(params, book, plan) -> dict | None:
    """The tooth-mesh FE's ratcheting torque beside the closed form's and the catalogue's (None without the study)."""
    from strainwave.compare.validate.ratcheting import ratcheting_record
    from strainwave.fea.tooth_mesh import STUDY as MESH_STUDY
    return ratcheting_record(params, book, plan.label_of(MESH_STUDY))


def _tooth_root(params, book, plan) -> dict | None:
    """The tooth-mesh FE's root stress from the mesh load beside ISO 6336-3's (None without the study)."""
    from strainwave.compare.validate.tooth_root_record import tooth_root_record
    from strainwave.fea.tooth_mesh import STUDY as MESH_STUDY
    return tooth_root_record(params, book, plan.label_of(MESH_STUDY))


def _design_extras(params) -> dict:
    """The materials table and the wave generator bearing's ratings (Hertz p0, ISO 76, ISO 281 L10) beside the
    factors (analytic/design_factors.py)."""
    from strainwave.analytic import design_factors as df
    return {"materials": df.materials_table(params), "ratings": df.bearing_ratings(params)}


def _prepare(out_dir: Path) -> ResultCache:
    """The run folder, cleared of what a run killed with -9 left under temporary names; its result cache."""
    out_dir.mkdir(parents=True, exist_ok=True)
    for folder in _output_folders(out_dir):
        remove_stale_temps(folder)
    return ResultCache(out_dir / "cache")


def _start_step(params, out_dir: Path, cache, progress, step: bool, total: int):
    """The background STEP export of every part (none when ``step`` is off: the job then waits for nothing)."""
    from strainwave.compare.validate.step_export import StepJob

    progress(f"[2/{total}] step: " + ("every part as STEP, in parallel with the FEA" if step
                                      else "skipped (--quick exports no STEP; add --step)"))
    return StepJob(params, out_dir / "step", cache, progress, preview_dir=out_dir / "images",
                   parts=None if step else ())


def _files(out_dir: Path, outcomes, steps) -> dict:
    """results.json's files: the STEP and VTU files written (relative to the run folder) and the reports."""
    fields = sorted({_relative(p, out_dir) for o in outcomes.values() if o.result for p in o.result.fields})
    return {"step": [_relative(p, out_dir) for s in steps for p in s.files], "fields": fields,
            "report_html": "report.html", "report_md": "report.md", "tables": list(CSV_FILES),
            "report_pdf": "report.pdf" if chromium() else None}


def _check_summary(checks: list[dict]) -> dict:
    """How many checks, how many pass, which fail and which could not be evaluated."""
    failed = [c["id"] for c in checks if not c["passed"]]
    return {"checks": len(checks), "passed": len(checks) - len(failed), "failed": failed,
            "not_evaluated": [c["id"] for c in checks if c["verdict"] == "not evaluated"]}


def _results_document(params, quick, step, plan, book, outcomes, steps, timings, out_dir, summary, check_set, made,
                      images, missing, stresses, wg_cup, design, nafems, audit) -> dict:
    """results.json's document (before the run record and the total time): every stage's output by key."""
    checks = [c.to_dict() for c in check_set.checks]
    summary_row = _check_summary(checks)
    return {
        "schema_version": 1,
        "passed": bool(checks) and not summary_row["failed"],
        "summary": summary_row,
        "metadata": _metadata(params, quick, step, plan, outcomes, steps, timings, out_dir),
        "designer": _designer_lines(summary),
        "designer_table": designer_table(summary),
        "design": {**design.to_dict(), **_design_extras(params),
                   "buckling": check_set.records.get("cup.buckling_torque"), "ratcheting": _ratcheting(params, book, plan),
                   "tooth_root_mesh": _tooth_root(params, book, plan)},
        "inputs": _inputs(plan, book, params),
        "stress_at_rated": {c: s.to_dict() for c, s in stresses.items()},
        "cup_wave_generator": wg_cup,
        "records": check_set.records,
        "views": {c: v.to_dict() for c, v in made.views.items()},
        "gci_table": [r.to_dict() for r in gci_rows(book, ORDER)],
        "nafems": nafems,
        "checks": checks, "audit": audit, "catalogue": catalogue_document(gear_line=gear_line(book, plan, params)),
        "crack_sweeps": {k: r.to_dict() for k, r in check_set.sweeps.items()},
        "images": [i.to_dict() for i in images], "missing_images": [m.to_dict() for m in missing],
        "files": _files(out_dir, outcomes, steps),
    }


def run_validate(params, out_dir: Path, *, quick: bool, progress: Callable[[str], None],
                 step: bool | None = None, params_file: str | Path | None = None) -> Outcome:
    """Run the whole validation into ``out_dir``; returns the checks and timings (see module docstring).
    ``step`` (default: not ``quick``) exports every part as STEP with its preview; --quick leaves the CAD
    out unless asked, since the STEP export alone costs more CPU than all of --quick's FEA cases.
    ``params_file`` (the --params file, None for the embedded default) names the gear in the reports."""
    from strainwave.analytic.summary import analytic_summary
    from strainwave.interrupt import deferred_interrupt
    from strainwave.compare.validate.artifacts import make_images
    start = time.perf_counter()
    out_dir = Path(out_dir)
    cache = _prepare(out_dir)
    timings: dict[str, float] = {}
    total = 6
    with _stage("analytic", timings, progress, 1, total):
        summary = analytic_summary(params)
    plan = make_plan(params, quick=quick)
    step = not quick if step is None else step
    step_job = _start_step(params, out_dir, cache, progress, step, total)
    nafems_job = NafemsJob(cache, progress)   # beside the FEA cases, or from the cache (it takes no parameter)
    try:
        with _stage("fea", timings, progress, 3, total):
            outcomes = _run_cases(plan.all_cases(), params, fields_dir=out_dir / "fields", cache=cache,
                                  quick=quick, progress=progress)
        book = FeaBook(outcomes)
        nafems_start = time.perf_counter()
        nafems = nafems_job.appendix(out_dir)
        timings["nafems"] = time.perf_counter() - nafems_start   # the wait after the FEA
        with _stage("checks", timings, progress, 4, total):
            check_set = build_checks(book, plan, summary, params, quick=quick)
            audit = audit_with_evidence(summary.get("audit", []), check_set.by_id(),
                                        shaft_exponent=_shaft_exponent(check_set),
                                        crack_headline=summary.get("crack_headline"))
        # STEP awaited last (checks and images need none), so its tail overlaps them (docs/decisions/014-validate-case-isolation.md)
        with _stage("images", timings, progress, 5, total), deferred_interrupt() as checkpoint, \
                _shader_cache(out_dir / "cache" / "mesa-shaders"):
            made = make_images(out_dir, book, plan, check_set, summary, progress, params=params,
                               checkpoint=checkpoint)
        wait_start = time.perf_counter()
        steps, timings["step"] = step_job.result()
        timings["step_wait_after_images"] = time.perf_counter() - wait_start
    finally:
        step_job.cancel()
        nafems_job.cancel()
    if step:
        progress(f"[2/{total}] step done: {sum(len(s.files) for s in steps)} STEP file(s), {timings['step']:.1f} s "
                 f"wall (waited {timings['step_wait_after_images']:.1f} s after the images)")
    images, missing, stresses = _previews(steps, out_dir) + made.images, made.missing, made.stresses
    wg_cup, design = _design(params, book, plan, stresses)
    with _stage("reports", timings, progress, 6, total):
        doc = _results_document(params, quick, step, plan, book, outcomes, steps, timings, out_dir, summary,
                                check_set, made, images, missing, stresses, wg_cup, design, nafems, audit)
        doc["metadata"]["total_s"] = time.perf_counter() - start
        doc["metadata"]["run"] = run_record(params, params_file)
        doc = plain(doc)
        # The reports are written before results.json so that results.json appearing marks a complete run.
        _write_reports(out_dir, doc, {c: v.payload for c, v in made.views.items()}, progress)
        write_results(out_dir / "results.json", doc)
    timings["total"] = time.perf_counter() - start
    return Outcome(out_dir, check_set.checks, timings, tuple(outcomes.values()), design)
