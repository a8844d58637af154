"""`strainwave validate --quick` end to end in a temporary folder, and its HTML report in headless Chromium.

One quick run is shared by every test of this module (module fixture); a second run into the same
folder checks that finished cases are reused from the cache.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from PIL import Image

from strainwave.compare.validate.checks import REQUIRED_IDS
from strainwave.compare.validate.results import load_schema

# every test here reads one `validate --quick` run (minutes): the heavy set (`make test-heavy`)
pytestmark = pytest.mark.heavy

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync")


def _validate(out: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    # --step: the quick run also exports the parts, so the STEP files and previews are checked end to end
    return subprocess.run([sys.executable, "-m", "strainwave.cli", "validate", "--quick", "--step", "--out", str(out)],
                          capture_output=True, text=True, env=env, timeout=600)


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("validate") / "out"
    proc = _validate(out)
    return out, proc


@pytest.fixture(scope="module")
def results(quick_run):
    out, _ = quick_run
    return json.loads((out / "results.json").read_text(encoding="utf-8"))


def test_exit_status_matches_the_checks_and_failures_are_listed(quick_run, results):
    _, proc = quick_run
    assert "Traceback" not in proc.stderr
    assert proc.returncode == (0 if results["passed"] else 1), proc.stderr[-2000:]
    failing = [c["id"] for c in results["checks"] if not c["passed"]]
    assert results["passed"] == (not failing)
    for check_id in failing:  # every failing check is named on the terminal, never hidden
        assert check_id in proc.stdout
    assert ("FAILING" in proc.stdout) == bool(failing)


def test_files_exist_and_results_validate_against_the_schema(quick_run, results):
    out, _ = quick_run
    for name in ("results.json", "report.html", "report.md"):
        assert (out / name).stat().st_size > 0
    jsonschema.validate(results, load_schema(), cls=jsonschema.Draft202012Validator)
    assert [c["id"] for c in results["checks"]][:len(REQUIRED_IDS)] == list(REQUIRED_IDS)
    for path in results["files"]["step"] + results["files"]["fields"] + [i["path"] for i in results["images"]]:
        assert (out / path).is_file(), path
    # every case that solved wrote the VTU its study declares, every part that was built wrote its STEP
    from strainwave.registry import STUDIES
    for case in results["metadata"]["cases"]:
        if case["ok"] and STUDIES[case["study"]].vtu_fields:
            assert case["result"]["fields"], case["label"]
    for step in results["metadata"]["steps"]:
        assert bool(step["files"]) != bool(step["error"]), step
    # no temporary file of an atomic write is left behind
    assert not [p for p in out.rglob("*.tmp")]


def test_every_check_states_its_tolerance_reason_and_verdict(results):
    for c in results["checks"]:
        if c["verdict"] == "not evaluated":
            assert c["reason_not_evaluated"] and not c["passed"]
            continue
        assert c["tolerance"]["reason"] and c["tolerance"]["relative"] > 0
        assert c["verdict"] in ("published", "corrected", "both", "neither")
        # the pass flag is exactly the asserted variant's error against the stated tolerance: two-sided
        # for an equality, one-sided for an upper bound (the bearing ring against 1/K_G0)
        err = c["rel_error"][c["asserts"]]
        assert c["relation"] in ("equal", "at_most")
        assert c["passed"] == ((err if c["relation"] == "at_most" else abs(err)) <= c["tolerance"]["relative"])


def test_audit_lists_every_seed_inconsistency(results):
    from strainwave.analytic.audit import audit_records
    from strainwave.params import load_params

    ids = [a["id"] for a in results["audit"]]
    assert ids == [r.id for r in audit_records(load_params())]
    assert all(a["settled"] for a in results["audit"])


def test_timings_per_stage_recorded(results):
    timings = results["metadata"]["timings_s"]
    for stage in ("analytic", "step", "fea", "checks", "images"):
        assert stage in timings and timings[stage] >= 0
    # STEP export overlaps the FEA (background process); the sequential stages add up to at most the total
    sequential = sum(timings[k] for k in ("analytic", "fea", "checks", "images"))
    assert results["metadata"]["total_s"] >= sequential


def test_every_image_is_non_blank(quick_run, results):
    out, _ = quick_run
    pngs = sorted((out / "images").glob("*.png")) if (out / "images").exists() else []
    assert len(pngs) == len(results["images"])
    for png in pngs:
        pixels = np.asarray(Image.open(png).convert("RGB"), dtype=float)
        # a blank render is one colour: std 0. A real plot or render has a std of tens of grey levels;
        # 5 is far above JPEG-like noise (none in PNG) and far below any drawn content.
        assert pixels.std() > 5.0, png.name
        assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 8, png.name


def test_every_component_states_its_inputs_rated_stress_and_gci(quick_run, results):
    out, _ = quick_run
    html = (out / "report.html").read_text(encoding="utf-8")
    md = (out / "report.md").read_text(encoding="utf-8")
    components = ("shaft", "cup", "bearing", "ring")
    for component in components:
        inputs = results["inputs"][component]
        meshes = inputs["meshes"]
        assert len(meshes) == 3 and all(0 < m["min_quality"] <= 1 for m in meshes)
        # h1 < h2 < h3: the finer mesh has more dofs (every study states all three)
        assert meshes[0]["h_mm"] < meshes[1]["h_mm"] < meshes[2]["h_mm"], component
        assert meshes[0]["dofs"] > meshes[1]["dofs"] > meshes[2]["dofs"] > 0, component
        assert f'id="inputs-{component}"' in html
        rated = results["stress_at_rated"][component]
        assert rated["safety_factor"] == pytest.approx(rated["fatigue_limit_MPa"] / rated["peak_von_mises_MPa"])
        assert rated["load"]["rated"] > 0 and rated["load"]["scale"] > 0
    assert md.count("### Inputs and model") == len(components)
    assert "## Stress at the rated load" in md and 'id="rated"' in html
    # at seed 000's T = 1000 N*mm the shaft showed 0.03 MPa: at the rated torque it is a designer's number
    assert results["stress_at_rated"]["shaft"]["peak_von_mises_MPa"] > 10.0
    # one GCI row per FEA quantity with three meshes, in the HTML table too
    expected = sum(1 for c in results["metadata"]["cases"] if c["ok"]
                   for q in c["result"]["quantities"].values() if q["convergence"])
    assert len(results["gci_table"]) == expected > 0
    table = html.split('id="gci-table"')[1].split("</table>")[0]
    assert table.count("<tr>") == expected + 1          # + the header row
    for row in results["gci_table"]:
        assert row["asymptotic"] == (not row["flags"])


def test_every_stress_image_states_its_load_and_section(results):
    images = [i for i in results["images"] if i["kind"] == "stress"]
    # the design components' pictures (their peak is a design stress) ...
    stress = {i["component"]: i["caption"] for i in images if i["path"] == f"images/{i['component']}_von_mises.png"}
    assert set(stress) == {"shaft", "cup", "bearing", "ring"}
    for caption in stress.values():
        assert "safety factor" in caption and "peak" in caption
    # ... and the pictured studies' von Mises, each saying why its peak is no design factor
    pictured = [i["caption"] for i in images if i["path"].endswith("_von_mises.png") and i["caption"] not in stress.values()]
    assert pictured and all("no design factor" in c or "left out of the factor" in c for c in pictured)
    assert "2D plane stress section" in stress["ring"]
    # supports and loads marked from the named boundary groups (NAME.boundary.vtu), and said in the caption
    assert "black: supports ('fixed')" in stress["shaft"] and "magenta: load T on 'loaded'" in stress["shaft"]
    assert "black: supports ('bore')" in stress["bearing"] and "load F_r on 'contact'" in stress["bearing"]
    assert "black: supports ('A', 'B', 'D')" in stress["ring"] and "load W0 on 'contact'" in stress["ring"]
    previews = {i["component"] for i in results["images"] if i["kind"] == "preview"}
    assert previews == {"shaft", "cup", "bearing", "ring"}


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links: list[str] = []
        self.images: list[str] = []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs["src"])
        for key in ("src", "href"):
            if attrs.get(key):
                self.links.append(attrs[key])


def test_html_embeds_every_image_and_links_only_existing_relative_files(quick_run, results):
    out, _ = quick_run
    parser = _Links()
    parser.feed((out / "report.html").read_text(encoding="utf-8"))
    # self-contained: every picture is inside the page, so report.html alone shows them all
    assert len(parser.images) == len(results["images"])
    assert all(src.startswith("data:image/png;base64,") for src in parser.images)
    for link in parser.links:
        if link.startswith(("data:", "#")):
            continue
        assert "://" not in link and not link.startswith("/"), link  # relative: the folder opens anywhere
        assert (out / link).is_file(), link
    # the table of contents points at sections that exist
    html = (out / "report.html").read_text(encoding="utf-8")
    anchors = [link[1:] for link in parser.links if link.startswith("#")]
    assert len(anchors) >= 10 and all(f'id="{a}"' in html for a in anchors)


def test_rerun_reuses_finished_cases_and_says_so(quick_run):
    out, first = quick_run
    before = json.loads((out / "results.json").read_text())
    solved = {c["label"] for c in before["metadata"]["cases"] if c["ok"]}
    proc = _validate(out)
    assert proc.returncode == first.returncode
    rerun = json.loads((out / "results.json").read_text())
    cached = {c["label"] for c in rerun["metadata"]["cases"] if c["cached"]}
    if rerun["metadata"]["versions"]["code_version"] == before["metadata"]["versions"]["code_version"]:
        assert cached == solved
        for label in cached:
            assert f"{label}: reusing cached" in proc.stderr
    else:
        # the shared tree changed between the two runs: a new code version must invalidate every case
        assert cached == set()


def _chromium() -> str:
    if not Path(CHROMIUM).exists():
        # The test set-up installs Debian's chromium when it is missing (root in the CI container).
        subprocess.run(["apt-get", "install", "-y", "chromium"], check=True, capture_output=True, timeout=900)
    return CHROMIUM


def test_report_opens_in_headless_chromium_and_every_image_loads(quick_run, results, tmp_path):
    out, _ = quick_run
    chromium = _chromium()
    # A copy of the report with a probe script next to it (same folder, so relative links resolve); the report's
    # own one script is the 3D viewer (checked below).
    probe = out / "report_probe.html"
    html = (out / "report.html").read_text(encoding="utf-8")
    script = ("<script>window.addEventListener('load',function(){var im=[].slice.call(document.images);"
              "var ok=im.filter(function(i){return i.complete&&i.naturalWidth>0;}).length;"
              "var d=document.createElement('div');d.id='probe';d.textContent='IMAGES '+ok+' OF '+im.length;"
              "document.body.appendChild(d);});</script>")
    probe.write_text(html.replace("</body>", script + "</body>"), encoding="utf-8")
    try:
        base = [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=10000"]
        dom = subprocess.run(base + ["--dump-dom", probe.as_uri()], capture_output=True, text=True, timeout=120)
        shot = tmp_path / "report.png"
        subprocess.run(base + [f"--screenshot={shot}", "--window-size=1200,2000", (out / "report.html").as_uri()],
                       capture_output=True, text=True, timeout=120)
    finally:
        probe.unlink()
    n = len(results["images"])
    assert f"IMAGES {n} OF {n}" in dom.stdout, dom.stdout[-500:] + dom.stderr[-500:]
    assert "strainwave validation report" in dom.stdout
    pixels = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    assert pixels.std() > 5.0  # the page rendered text and tables, not a blank canvas
    shutil.rmtree(tmp_path / "profile", ignore_errors=True)


# ---- regression: the --quick checks equal the numbers main gave before issue 11's refactor ----------------

REFERENCE = Path(__file__).parent / "data" / "validate_quick_checks.json"
REGRESSION_RTOL = 1e-9
# Every DELIBERATE change of a --quick check's numbers, by check id, with its reason. An engineer who
# changes numbers on purpose adds the check id here (one line, saying why and by how much), or, when the
# new numbers become the reference, regenerates tests/data/validate_quick_checks.json from a --quick
# results.json and empties the entry. Anything not listed must reproduce the reference to 1e-9 relative.
_CRACK_GCI = "582f540 (cracks): crack-compliance GCI at the formal order 1 (was bounded [0.5, 2]): uncertainty and tolerance move, the FEA value does not"
_RING_MESH = "01f8eec (ring): smooth ring always on the full meshes in --quick"
_RATIO = ("; arch (issue 11): refinement ratio 1.5 -> 1.4, the one ratio of every study: finest mesh and value "
          "unchanged, the GCI uncertainty moves (ring.sigma_max 0.032 -> 0.179 MPa, ring.tooth_influence "
          "0.123 -> 0.031, bearing crack 8.4e-12 -> 2.5e-12 mm/N)")
_CUP_SEAM_MESH = ("cracks (issue 13): the uncracked cup is solved on the seam mesh, whose embedded crack moved from "
                  "the tooth band to the tube: 4.85142e-10 -> 4.85126e-10 (-0.003 %), GCI 0.37 -> 0.26 %")
# issue 37: GCI by the book - the observed order with Fs = 1.25 only where it lies within 10 % of the formal order,
# else the formal order with Fs = 3 (never a p clipped to 8): every GCI uncertainty and tolerance not confirmed
# asymptotic moves (shaft flexibility: observed p 8.05 -> formal 4, uncertainty 1.79e-14 -> 2.08e-13; shaft
# crack delta: observed 1.62 -> formal 1, Fs 3), FEA values do not
_GCI_BOOK = "issue 37: GCI by the book (observed p with Fs 1.25 within 10 % of the formal order, else formal p with Fs 3)"
_CUP_CALIBRATED = ("issue 37: the cup's junction bias is a calibrated correction (+4.86 %, fitted on two other cups) "
                   "with its 0.41 % scatter as the only allowance (was the bare series model + 6 %)")
# issue 50: every check's tolerance is its GCI once (Fs 1.25 / 3 already inside it) + named allowances, no longer
# 3 x that GCI: every tolerance_relative moves, no FEA value does
_GCI_ONCE = "issue 50: tolerance = GCI once + named allowances (was 3 x a GCI that already holds Fs)"
DELIBERATE_CHANGES: dict[str, str] = {
    "shaft.flexibility": "issue 37: corrected = the G = E/2(1+nu) form of the problem the FEA solves, tolerance "
                         "3 x GCI without the 0.96 % mu allowance (the material gap is reported apart); " + _GCI_BOOK,
    "shaft.crack_compliance": "582f540 (cracks): corrected = hollow-tube strip / thick-tube form (was solid-bar "
                              "K_III); " + _CRACK_GCI + "; cracks (issue 13): tip a/40 in --quick (was a/20): "
                              "6.332e-11 -> 6.365e-11 at a = 6.25 mm, GCI 1.57 -> 0.56 %; " + _GCI_BOOK,
    "cup.crack_compliance": _CRACK_GCI + "; cracks (issue 13): the FEA crack is the seed's through-wall 45 deg "
                            "crack in the fully loaded tube (was a part-through root crack in the load band): "
                            "2.60e-15 -> 1.02e-14 at a = 1.12 mm; corrected = both tips a^2/(2 pi E r_m^4 delta); " + _GCI_BOOK
                            + "; decision 031: solved global-local (1.065e-14 at a = 1.12 mm, GCI 2.2 %); decision 042: "
                            "the patch in one solve (Bueckner) held at the section's exact field: 1.0659e-14, GCI 2.4 %; "
                            "decision 044: through-wall layers the fewest (up to 10) whose face layer is no thicker "
                            "than the a/4 tip, 5 at a = 1.12 mm: 1.06586e-14 -> 1.06569e-14, GCI 2.36 -> 2.44 %",
    "cup.flexibility": _CUP_SEAM_MESH + "; " + _CUP_CALIBRATED + "; " + _GCI_BOOK + "; decision 031: the FEA is the "
                       "cup's exact (r, z) section (4.855e-10 -> 4.9155e-10, +1.2 %: the 3D meshes read low), corrected "
                       "= series model + junction line in delta/d1, tolerance 0.06 %",
    "cup.surface_crack_minor": "decision 033: the shut share's GCI by the face's Schur complement instead of a difference "
                               "of two energies: round-off of a nearly shut state, 1.3749e-8 -> 1.3764e-8",
    "gear.stiffness": _CUP_SEAM_MESH + " (lambda_f0 from that case); issue 34 (wg-bearing): lambda_H from the FEA's "
                      "wave generator radial stiffness K_G (Hertz balls on the cam-held ring, ~14x the seed's "
                      "back-calculated K_G0), corrected = Stribeck-Hertz K_G with rigid rings; " + _CUP_CALIBRATED
                      + "; " + _GCI_BOOK,
    "bearing.crack_compliance": _CRACK_GCI + "; cracks (issue 13): crack faces in frictionless contact, the "
                                "crack at the Hertz centre stays shut: quantity = cracked compliance, asserted "
                                "= uncracked ring (delta 6.24e-8 -> 5.8e-13 mm/N at a = 2.08 mm)" + _RATIO + "; issue 34 "
                                "(wg-bearing): the crack is the race crack at the major axis of the ring on the "
                                "elliptical cam, held open by the cam's bending, solved in 2D (study wg-bearing); "
                                "quantity = its added compliance under the Stribeck ball loads, asserted = Tada's "
                                "edge-crack weight function at the FEA's uncracked hoop stress (seed 000 eq 4); " + _GCI_BOOK,
    "ring.delta_cd": _RING_MESH + _RATIO + "; " + _GCI_BOOK,
    "ring.delta_ab": _RING_MESH + _RATIO + "; " + _GCI_BOOK,
    "ring.sigma_max": _RING_MESH + _RATIO + "; " + _GCI_BOOK,
    "ring.sigma_min": _RING_MESH + " (152.44 vs Winkler-Bach 152.42)" + _RATIO + "; " + _GCI_BOOK,
    "ring.tooth_influence": _RING_MESH + "; corrected = the FEA-fitted tooth-factor model (was the seed's 1.07)" + _RATIO + "; " + _GCI_BOOK,
    "ring.stress_concentration": "01f8eec (ring): K_sigma compared like with like (root factor / K_delta) "
                                 "against the tooth-factor model (was the seed's 1.9)" + _RATIO + "; " + _GCI_BOOK,
}
for _id in ("shaft.flexibility", "shaft.crack_compliance", "cup.flexibility", "cup.crack_compliance",
            "bearing.crack_compliance", "ring.delta_cd", "ring.delta_ab", "ring.sigma_max", "ring.sigma_min",
            "ring.tooth_influence", "ring.stress_concentration", "gear.stiffness", "cup.surface_crack_major",
            "cup.surface_crack_between", "cup.surface_crack_minor"):
    DELIBERATE_CHANGES[_id] = DELIBERATE_CHANGES.get(_id, "") + ("; " if _id in DELIBERATE_CHANGES else "") + _GCI_ONCE
DELIBERATE_CHANGES["cup.surface_crack_major"] += (
    "; issue 50 item 3 (decision 067-crack50b): quarter-point nodes at the front and the checked depth graded over "
    "8a + h/2: 4.2376e-16 -> 4.3252e-16 (-5.1 % -> -3.2 % of Newman-Raju), GCI 10.5 -> 0.72 %, tolerance 20.7 -> 11.0 %")
# Checks removed on purpose, with the reason (a removed check is listed, never silently gone).
DELIBERATE_REMOVALS: dict[str, str] = {
    "cup.surface_crack_between": "issue 50 (decision 067-crack50b): equal to cup.surface_crack_major to every digit (an "
                                 "open crack's tangent compliance does not depend on where it sits); replaced by "
                                 "cup.surface_crack_closure_angle",
    "cup.surface_crack_minor": "issue 50 (decision 067-crack50b): a shut share that is 1 by construction once the crack "
                               "shuts whole; cup.surface_crack_closure_angle checks when it does",
    "gear.stiffness": "issue 48 item 4 (decision 073-assembled48): the sum of members each checked elsewhere (it could "
                      "not fail); replaced by gear.drive_assembled, the drive assembled (teeth + cup wall + wave "
                      "generator) against the chain of the same members in series",
    "bearing.radial_compliance": "ring (issue 13): passed vacuously (ring FEA 31x below 1/K_G0 back-computed from "
                                 "the seed's table); now information: analytic checks entry and audit 13 (K_G0 "
                                 "= 0.139 of one ball's Hertz contacts at the seed's ellipse)",
}
NUMBERS = ("fea", "fea_uncertainty", "published", "corrected", "tolerance_relative")


def _numbers(check: dict) -> dict:
    return {"fea": check["fea"], "fea_uncertainty": check["fea_uncertainty"],
            "published": check["analytic"].get("published"), "corrected": check["analytic"].get("corrected"),
            "tolerance_relative": (check.get("tolerance") or {}).get("relative")}


def test_quick_checks_reproduce_the_reference_or_are_listed_as_deliberate(results):
    reference = json.loads(REFERENCE.read_text(encoding="utf-8"))["checks"]
    now = {c["id"]: c for c in results["checks"]}
    gone = set(reference) - set(now) - set(DELIBERATE_REMOVALS)
    assert not gone, f"checks gone: {sorted(gone)}"
    changed = {}
    for check_id, ref in reference.items():
        if check_id in DELIBERATE_CHANGES or check_id in DELIBERATE_REMOVALS:
            continue
        got = _numbers(now[check_id])
        for name in NUMBERS:
            a, b = got[name], ref[name]
            if (a is None) != (b is None) or (a is not None and not np.isclose(a, b, rtol=REGRESSION_RTOL, atol=0.0)):
                changed.setdefault(check_id, []).append(f"{name}: {b!r} -> {a!r}")
        if now[check_id]["verdict"] != ref["verdict"]:
            changed.setdefault(check_id, []).append(f"verdict: {ref['verdict']} -> {now[check_id]['verdict']}")
    assert not changed, f"undeclared changes (list them in DELIBERATE_CHANGES with a reason): {changed}"


FULL_VERDICTS = Path(__file__).parent / "data" / "validate_full_verdicts.json"
# Verdicts --quick may reach apart from the recorded full run, by check id, with the reason: only where quick
# still PASSES and only the published side moves. A full `make validate` re-records FULL_VERDICTS and empties this.
QUICK_VERDICT_EXCEPTIONS: dict[str, str] = {
    "bearing.crack_compliance": "issue 49's 3 mm ring: the full run's tolerance (10.8 %, mostly its GCI) holds the "
                                "published form too ('both'); quick's own tolerance excludes it ('corrected'); the "
                                "asserted corrected form passes in both",
    "cup.crack_compliance": "issue 50: the midpoint of plane stress and plane strain is asserted; quick's best-resolved "
                            "depth is a = 1.12 mm (full: 0.14 mm), where the FEA lies nearer plane stress (-2.8 % of it), "
                            "so the published (plane-stress) form is inside too ('both', passing)",
}
# Checks --quick reports "not resolved at --quick" (issue 50: their coarse-mesh GCI exceeds their named allowances
# by more than 1 %, so a pass would rest on a tolerance more than twice the full run's), with the numbers measured.
# bearing.crack_compliance left this list with issue 49's 3 mm ring: quick's meshes of it resolve the crack.
QUICK_NOT_RESOLVED: dict[str, str] = {
    "ring.stress_concentration": "quick's toothed-ring series diverges (observed p -6.4): GCI 27.6 % against the "
                                 "fit residual's 3.5 % (tolerance 31 %, full run 4.2 %)",
    "cup.wg_bending_major": "GCI 5.2 % against 3.3 % of allowances (tolerance 8.6 %, full run 4.5 %)",
    "mesh.rigid_rim_sharing": "quick's three rim meshes put 16 / 16 / 14 pairs in contact (observed p 0.5): GCI "
                              "10.1 % against no allowance (the closed form is exact; full run 1.04 %; decision 067)",
}


def test_quick_verdicts_are_those_of_the_full_run(results):
    """--quick must not reach another verdict than the full run (issue 14: it once passed cup.crack_compliance
    with a 60 % tolerance that the full run failed). The full run's verdicts are recorded with their source."""
    full = json.loads(FULL_VERDICTS.read_text(encoding="utf-8"))["verdicts"]
    quick = {c["id"]: {"verdict": c["verdict"], "passed": c["passed"]} for c in results["checks"]}
    assert set(full) <= set(quick), sorted(set(full) - set(quick))
    differ = {k: (quick[k], v) for k, v in full.items()
              if quick[k] != v and k not in QUICK_VERDICT_EXCEPTIONS and k not in QUICK_NOT_RESOLVED}
    assert not differ, f"quick vs full verdicts: {differ}"
    reasons = {c["id"]: c["reason_not_evaluated"] for c in results["checks"]}
    unresolved = {k for k, r in reasons.items() if r.startswith("not resolved at --quick")}
    assert unresolved == set(QUICK_NOT_RESOLVED), (unresolved, sorted(QUICK_NOT_RESOLVED))
    kept = {"corrected", "both"}            # the asserted (corrected) form inside the tolerance
    for k in QUICK_VERDICT_EXCEPTIONS:      # an exception never hides a failure or a lost corrected verdict
        assert quick[k]["passed"] and (quick[k]["verdict"] in (full[k]["verdict"], "both")
                                       or {quick[k]["verdict"], full[k]["verdict"]} <= kept), (k, quick[k], full[k])

# Injected first into <head>: records every script error and console.error, then, once the page has loaded,
# counts the drawn (non-white) pixels and distinct colours of every 3D view canvas.
_VIEW_PROBE = (
    "<script>window.__errors=[];window.addEventListener('error',function(e){window.__errors.push(String(e.message));});"
    "window.addEventListener('unhandledrejection',function(e){window.__errors.push(String(e.reason));});"
    "var __ce=console.error;console.error=function(){window.__errors.push([].join.call(arguments,' '));"
    "__ce.apply(console,arguments);};"
    "window.addEventListener('load',function(){setTimeout(function(){var out=[];"
    "[].forEach.call(document.querySelectorAll('canvas.sw-view'),function(c){var t=document.createElement('canvas');"
    "t.width=c.width;t.height=c.height;var x=t.getContext('2d');x.drawImage(c,0,0);"
    "var d=x.getImageData(0,0,t.width,t.height).data,n=0,cols={};"
    "for(var i=0;i<d.length;i+=4){if(d[i]<250||d[i+1]<250||d[i+2]<250){n++;"
    "cols[(d[i]>>4)+','+(d[i+1]>>4)+','+(d[i+2]>>4)]=1;}}"
    "out.push(c.getAttribute('data-source')+'='+n+'/'+Object.keys(cols).length);});"
    "var p=document.createElement('pre');p.id='probe3d';p.textContent='VIEWS '+out.join(' ')+' ERRORS '"
    "+window.__errors.length+': '+window.__errors.join(' | ');document.body.appendChild(p);},500);});</script>")


def test_report_3d_views_render_in_headless_chromium_without_errors(quick_run, results, tmp_path):
    out, _ = quick_run
    chromium = _chromium()
    html = (out / "report.html").read_text(encoding="utf-8")
    assert html.count('<canvas class="sw-view"') == len(results["views"]) == 4
    # the page is self-contained: nothing is fetched from anywhere (no src/href leaves the folder, no import)
    assert "://" not in html.split("<script>")[-1] and "import(" not in html
    probe = out / "report_probe3d.html"
    probe.write_text(html.replace('<meta charset="utf-8">', '<meta charset="utf-8">' + _VIEW_PROBE, 1),
                     encoding="utf-8")
    try:
        base = [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}", "--virtual-time-budget=15000"]
        dom = subprocess.run(base + ["--dump-dom", probe.as_uri()], capture_output=True, text=True, timeout=180)
    finally:
        probe.unlink()
        shutil.rmtree(tmp_path / "profile", ignore_errors=True)
    report = dom.stdout.split('<pre id="probe3d">')[1].split("</pre>")[0]
    assert report.endswith("ERRORS 0: "), report
    counts = dict(item.split("=") for item in report.split(" ERRORS")[0].split()[1:])
    assert set(counts) == {f"view-data-{c}" for c in results["views"]}
    for name, value in counts.items():
        drawn, colours = (int(v) for v in value.split("/"))
        # a blank canvas has 0 drawn pixels; a drawn stress field covers thousands of pixels (the thin EWG ring
        # about 11,000 of the 307,200) in many colours of the map
        assert drawn > 3000 and colours > 8, (name, value)
    # the inputs section and the GCI table are on the rendered page
    assert 'id="inputs-shaft"' in dom.stdout and 'id="gci-table"' in dom.stdout


# ---- issue 40: two verdicts, a portable report (PDF, CSV), fields at the rated load ------------------------------

def test_both_verdicts_open_the_report_and_a_failing_design_is_red(quick_run, results):
    out, proc = quick_run
    design = results["design"]
    html = (out / "report.html").read_text(encoding="utf-8")
    box = html.split('id="design-verdict"')[0].rsplit("<div", 1)[1]
    assert ("verdict pass" in box) == design["passed"] and ("verdict fail" in box) == (not design["passed"])
    assert html.index('id="verdict"') < html.index('id="design-verdict"') < html.index('id="contents"')
    # one factor per component and point of it (issue 49), each recomputed from the inputs it states (design.csv's
    # row): Goodman on its amplitude and mean, the static check beside it; the verdict is exactly theirs
    assert {f["component"] for f in design["factors"]} == {"shaft", "cup", "ring", "cup_tooth_root", "cup_band_edge",
                                                           "wg_inner_ring", "wg_outer_ring", "cup_diaphragm"}
    for f in design["factors"]:
        assert f["definition"] and f["required"] == design["required_safety_factor"]
        row = f["fatigue"]
        demand = (row["notch_K"] * row["amplitude_MPa"] / row["fatigue_limit_MPa"]
                  + max(row["mean_MPa"], 0.0) / row["ultimate_strength_MPa"])
        assert f["safety_factor"] == pytest.approx(1.0 / demand, rel=1e-12)
        assert f["static_n"] == pytest.approx(row["yield_strength_MPa"] / (abs(row["mean_MPa"])
                                                                          + row["notch_K"] * row["amplitude_MPa"]))
        assert f["passed"] == (f["verdict"] == "PASS")
        if f["component"] in ("shaft", "cup"):     # the FEA's own peak, fully reversed: sigma_-1 / peak
            assert f["safety_factor"] == pytest.approx(results["stress_at_rated"][f["component"]]["safety_factor"])
        if f["component"] == "wg_inner_ring":      # the cam's race stress, swung by the balls (FEA wg-bearing)
            case = next(c for c in results["metadata"]["cases"] if c["study"] == "wg-bearing")
            q = case["result"]["quantities"]
            cam, net = q["race_stress_major_MPa"]["value"], q["net_race_stress_major_MPa"]["value"]
            assert row["mean_MPa"] == pytest.approx(0.5 * (cam + net)) and row["amplitude_MPa"] == pytest.approx(
                0.5 * abs(net - cam))
    rows = list(csv.DictReader((out / "design.csv").open()))
    assert [r["component"] for r in rows] == [f["component"] for f in design["factors"]]
    assert design["passed"] == all(f["passed"] for f in design["factors"])
    assert ("design (does the drive meet [n] at the rated load?): " + design["headline"]) in proc.stdout


def test_pdf_is_printed_with_every_image(quick_run, results):
    from pypdf import PdfReader

    out, proc = quick_run
    assert results["files"]["report_pdf"] == "report.pdf", [l for l in (proc.stdout + proc.stderr).splitlines() if "pdf" in l]
    reader = PdfReader(out / "report.pdf")
    # about 17 A4 pages for --quick; far fewer means a truncated print, far more a runaway layout
    assert 8 <= len(reader.pages) <= 60
    assert sum(len(page.images) for page in reader.pages) >= len(results["images"])
    assert "strainwave validation report" in reader.pages[0].extract_text()


def test_csv_tables_sit_beside_the_report_with_the_json_numbers(quick_run, results):
    import csv

    out, _ = quick_run
    checks = list(csv.DictReader((out / "checks.csv").open(encoding="utf-8")))
    assert [r["id"] for r in checks] == [c["id"] for c in results["checks"]]
    for row, check in zip(checks, results["checks"]):
        if check["fea"] is not None:
            assert float(row["fea"]) == check["fea"]
    assert len(list(csv.DictReader((out / "gci.csv").open(encoding="utf-8")))) == len(results["gci_table"])
    stress = {r["component"]: r for r in csv.DictReader((out / "stress.csv").open(encoding="utf-8"))}
    assert set(stress) == set(results["stress_at_rated"])
    for component, s in results["stress_at_rated"].items():
        assert float(stress[component]["peak_von_mises_MPa"]) == s["peak_von_mises_MPa"]


def test_every_field_file_is_at_the_rated_load_and_says_so(quick_run, results):
    import pyvista as pv

    from strainwave.fea.fields import field_text

    out, _ = quick_run
    for component, s in results["stress_at_rated"].items():
        grid = pv.read(out / "fields" / s["field_file"])
        assert field_text(grid, "fields_at")[0].startswith("the rated load: "), component
        assert grid.field_data["load_scale_applied"][0] == pytest.approx(s["load"]["scale"])
        vm = np.asarray(grid.point_data["von_mises_MPa"], float)
        # the file's own peak is the reported one, or a crack tip's or sharp edge's, reported apart (float32: 1e-5)
        top = max(s["peak_von_mises_MPa"], s["tip_peak_von_mises_MPa"] or 0.0, s["corner_peak_von_mises_MPa"] or 0.0)
        assert vm.max() == pytest.approx(top, rel=1e-5), component
    sizes = sum((out / p).stat().st_size for p in results["files"]["fields"])
    assert sizes < 30e6     # issue 40: <= 30 MB of fields per gear
