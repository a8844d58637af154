"""The promises of issue 16 on real command runs, from the harness benchmarks/fuzz_reliability.py (reduced):
each bad path, flag and oversized request exits 2 in one line before any work (items 6, 7, 15-22); an
interrupted validate leaves no process, no half file and no traceback (items 23, 24); two runs agree
(determinism); nothing is written outside the outputs (item 26); the mesh estimate is near the real mesh."""
import json
import os
import signal
import time
import warnings

import pytest

from conftest import benchmark_module
from strainwave.cli import main



@pytest.fixture(scope="module")
def harness():
    with benchmark_module("fuzz_reliability") as module:
        yield module


def _table(harness, tmp_path):
    return [(what, argv, kept) for what, argv, kept in harness.path_table(tmp_path)] + \
        [(what, argv, None) for what, argv in harness.resource_table(tmp_path)]


def test_every_bad_path_flag_and_oversized_request_exits_2_in_one_line_before_any_work(harness, tmp_path, capsys):
    # 15 s: a refusal is argument and schema checks (~0.01-1 s in-process); anything that meshed, solved or
    # started a cluster would take longer, and a hang far longer.
    for what, argv, kept in _table(harness, tmp_path):
        before = kept.read_bytes() if kept is not None else None
        start = time.perf_counter()
        status = main(argv)
        took = time.perf_counter() - start
        err = capsys.readouterr().err
        assert status == 2, (what, err)
        assert err.count("\n") == 1 and err.startswith("error: ") and "internal error" not in err, (what, err)
        assert took < 15.0, (what, took)
        if kept is not None:
            assert kept.read_bytes() == before, f"{what}: the input was changed"


def test_mesh_estimate_is_within_a_factor_two_of_the_mesh(tmp_path):
    """The budget refuses by an estimate; it must be near what gmsh makes (shaft at h = 12 mm)."""
    from strainwave.fea.budget import estimate
    from strainwave.fea.studies import run_study
    from strainwave.params import load_params

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params()
        real = run_study("shaft-torsion", params, mesh_size_mm=12.0).mesh.elements
    guess = estimate("shaft-torsion", params, 12.0).elements
    assert 0.5 < guess / real < 2.0, (guess, real)


@pytest.mark.heavy
@pytest.mark.parametrize("sig,group", [(signal.SIGINT, False), (signal.SIGKILL, False)])
def test_interrupted_validate_leaves_no_process_half_file_or_traceback(harness, tmp_path, sig, group):
    """SIGINT (exit 130, 'error: interrupted', queued cases never start) and SIGKILL of the main process
    alone (its FEA and STEP children follow it) 8 s in, while the FEA cases run."""
    out = tmp_path / "validate"
    outcome, note = harness.interrupt(["validate", "--quick", "--out", str(out)], out, 8.0, sig, group)
    assert outcome == "refused", note


def test_analytic_and_diagnose_are_deterministic(tmp_path, capsys, harness):
    rec = tmp_path / "r.csv"
    rec.write_text(harness._good_recording(__import__("random").Random(1)))
    for argv in (["analytic"], ["diagnose", str(rec)]):
        runs = []
        for k in range(2):
            target = tmp_path / f"{argv[0]}{k}.json"
            assert main([*argv, "--json", str(target)]) == 0
            runs.append(json.loads(target.read_text()))
        capsys.readouterr()
        assert harness._close(runs[0], runs[1], 1e-12), argv[0]


@pytest.mark.heavy
def test_commands_write_nothing_outside_their_outputs(harness, tmp_path):
    """analytic, diagnose, export-step --png and solve under strace with HOME and TMPDIR empty: no ldconfig/gcc
    temp files (pypardiso's find_library), no Mesa shader cache, no scratch in /tmp. ezdxf's font list in
    XDG_CACHE_HOME is the one documented cache allowed; gmsh's FLTK prefs are listed apart (not fixed)."""
    row = harness.side_effects(tmp_path, solve=True)
    if row.notes and "not installed" in row.notes[0]:
        if os.environ.get("CI"):   # .ci/run installs strace: missing there is a broken set-up, not a skip
            pytest.fail("strace is not installed although .ci/run installs it")
        pytest.skip("strace is not installed (.ci/run installs it)")
    assert row.tried == 4 and row.accepted == 4, row.notes


def test_a_cad_kernel_failure_is_a_named_stage_failure(tmp_path, capsys, monkeypatch):
    """Item 8: OCC's own exceptions on a geometry it cannot build say which stage and part failed (exit 1),
    not 'internal error'. The kernel's failure is stood in for: no in-range parameter set is known to cause one."""
    from strainwave.geometry import export

    def occ_fails(*args, **kwargs):
        raise RuntimeError("BRepAdaptor_Curve::No geometry")

    monkeypatch.setattr(export, "export_part", occ_fails)
    assert main(["export-step", "--part", "output-shaft", "-o", str(tmp_path / "s.step")]) == 1
    err = capsys.readouterr().err
    assert err == "error: output-shaft: CAD failed: RuntimeError: BRepAdaptor_Curve::No geometry\n"
