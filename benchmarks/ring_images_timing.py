"""CPU of the ring's 2D series and of validate's images stage (docs/decisions/045-ring-images-nafems-cost.md).

    python benchmarks/ring_images_timing.py ring [PARAMS.toml]
        the smooth and toothed 2D series (three meshes each): CPU of this process and its gmsh children
    python benchmarks/ring_images_timing.py images OUT [PARAMS.toml]
        validate's images stage again on a finished run's folder OUT (its fields and results.json, with the
        PARAMS it ran on): CPU of this process and of the image worker, wall, and what was made (a convergence
        plot of a non-monotone quantity fails here: results.json stores its NaN observed order as null)
    python benchmarks/ring_images_timing.py stages OUT [PARAMS.toml]
        the images stage, then the reports stage (report.md, report.html, report.pdf, results.json from OUT's
        results.json and the fresh pictures and 3D views): wall and CPU of each, Chromium's processes included
        (this process is their subreaper) (docs/decisions/055-images-reports-cpu.md)

Run each in a checkout of the old and of the new code, alternating, with ``OMP_NUM_THREADS=1 nice -n 10``.
"""
from __future__ import annotations

import ctypes
import json
import os
import sys
from pathlib import Path

import numpy as np


def _cpu(t) -> tuple[float, float]:
    return t.user + t.system, t.children_user + t.children_system


def ring_series(params) -> str:
    from strainwave.fea import ring_compression as rc
    from strainwave.fea.assembly import Lame
    from strainwave.fea.ring_plane import solve_ring_section
    from strainwave.registry import study

    load = study("ring-compression").load_for(params)
    geo = rc.ring_geometry(params)
    arc = rc.contact_load(geo, load["force_N"])
    lame = Lame.from_young(params.material.youngs_modulus_MPa, params.material.poisson_ratio, plane_stress=True)
    faces = {"smooth": rc.section_face(params, teeth=False), "toothed": rc.section_face(params, teeth=True)}
    pitch = 2 * np.pi / params.ewg_drive.flexspline_teeth
    solve_ring_section(faces["smooth"], geo, arc, lame, size_mm=geo.thickness_mm / 1.5, order=2)   # imports, warm
    out = []
    for series in ("smooth", "toothed"):
        t0 = os.times()
        for h in rc.mesh_sizes_mm(geo, None, False):
            solve_ring_section(faces[series], geo, arc, lame, size_mm=h, order=2, ewg_w0_mm=load["w0_mm"], pitch_rad=pitch)
        t1 = os.times()
        out.append(f"{series} {sum(_cpu(t1)) - sum(_cpu(t0)):.2f} s")
    return "ring 2D series CPU: " + ", ".join(out)


def images_stage(out: Path, params, reports: bool = False) -> str:
    from strainwave.analytic.summary import analytic_summary
    from strainwave.compare.validate import pipeline
    from strainwave.compare.validate.artifacts import make_images
    from strainwave.compare.validate.check_set import build_checks
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.plan import make_plan
    from strainwave.compare.validate.runner import CaseOutcome
    from strainwave.fea.result import StudyResult

    doc = json.loads((out / "results.json").read_text())
    plan = make_plan(params, quick=doc["metadata"]["settings"]["quick"])
    cases = {c.label: c for c in plan.all_cases()}
    outcomes = {}
    for rec in doc["metadata"]["cases"]:
        result = rec["result"]
        if result is not None:
            result = StudyResult.from_dict({**result, "fields": [str(out / p) for p in result["fields"]]})
        outcomes[rec["label"]] = CaseOutcome(cases[rec["label"]], result, rec["seconds"], rec["cached"],
                                             rec["error"] or "", rec["cpu_s"])
    book, summary = FeaBook(outcomes), analytic_summary(params)
    check_set = build_checks(book, plan, summary, params)
    (out / "images").mkdir(exist_ok=True)
    (out / "cache").mkdir(exist_ok=True)
    t0 = os.times()
    with pipeline._shader_cache(out / "cache" / "mesa-shaders"):
        made = make_images(out, book, plan, check_set, summary, lambda m: None, params=params)
    t1 = os.times()
    (here, worker), (here0, worker0) = _cpu(t1), _cpu(t0)
    said = (f"images: wall {t1.elapsed - t0.elapsed:.2f} s, CPU this process {here - here0:.2f} s, worker "
            f"{worker - worker0:.2f} s; {len(made.images)} images, {len(made.missing)} missing")
    return said + ("; " + reports_stage(out, doc, made) if reports else "")


def reports_stage(out: Path, doc: dict, made) -> str:
    """report.md/.html/.pdf and results.json of ``doc`` with ``made``'s pictures and views, as the pipeline writes them."""
    from strainwave.compare.validate import pipeline
    from strainwave.compare.validate.results import write_results

    doc = {**doc, "images": [i.to_dict() for i in made.images], "missing_images": [m.to_dict() for m in made.missing],
           "views": {c: v.to_dict() for c, v in made.views.items()}}
    t0 = os.times()
    pipeline._write_reports(out, doc, {c: v.payload for c, v in made.views.items()}, lambda m: None)
    write_results(out / "results.json", doc)
    while True:        # Chromium's processes left to this subreaper: their CPU counts too
        try:
            os.waitpid(-1, 0)
        except ChildProcessError:
            break
    t1 = os.times()
    (here, children), (here0, children0) = _cpu(t1), _cpu(t0)
    return (f"reports: wall {t1.elapsed - t0.elapsed:.2f} s, CPU this process {here - here0:.2f} s, Chromium "
            f"{children - children0:.2f} s")


def main(argv: list[str]) -> int:
    from strainwave.params import load_params

    if len(argv) >= 1 and argv[0] == "ring":
        print(f"load {os.getloadavg()[0]:.2f}; " + ring_series(load_params(argv[1] if len(argv) > 1 else None)))
        return 0
    if len(argv) >= 2 and argv[0] in ("images", "stages"):
        params = load_params(argv[2] if len(argv) > 2 else None)
        if argv[0] == "stages":
            ctypes.CDLL(None).prctl(36, 1, 0, 0, 0)     # PR_SET_CHILD_SUBREAPER: Chromium's helpers are reaped here
        print(f"load {os.getloadavg()[0]:.2f}; " + images_stage(Path(argv[1]), params, reports=argv[0] == "stages"))
        return 0
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
