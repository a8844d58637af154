"""Issue 53's reproducers of lost user data: folders named like strainwave's scratch, user files in an --out folder,
a run's outputs appearing one by one, two runs in one folder, damaged cache entries. The --out command is the real
CLI path (checks, lock, staging, commit, manifest) around a stand-in for the sweep's computation, so each runs in
well under a second."""
import hashlib
import json
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from strainwave.cache import ResultCache
from strainwave.cli import main
from strainwave.output_guard import MANIFEST, remove_stale


def _refusal(capsys, status) -> str:
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and err.startswith("error: "), err
    return err


def _digests(folder: Path) -> dict:
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file() and p.name != MANIFEST}


@dataclass
class _Outcome:
    n_ok: int = 1

    def summary(self) -> str:
        return "swept"


def _fake_sweep(monkeypatch, files: dict[str, str], *, fail_after: int | None = None, cache_entry: bool = False):
    """run_sweep replaced by one that writes ``files`` (relative path -> text) into its out_dir, optionally a cache
    entry first, and raises KeyboardInterrupt (as Ctrl-C) after ``fail_after`` files."""
    import strainwave.compare.sweep.pipeline as pipeline

    def run_sweep(study, *, out_dir, **kw):
        out_dir = Path(out_dir)
        if cache_entry:
            ResultCache(out_dir / "cache").put("finished", {"status": "ok"})
        for i, (rel, text) in enumerate(files.items()):
            if fail_after is not None and i == fail_after:
                raise KeyboardInterrupt
            (out_dir / rel).parent.mkdir(parents=True, exist_ok=True)
            (out_dir / rel).write_text(text)
        return _Outcome()

    monkeypatch.setattr(pipeline, "run_sweep", run_sweep)


def _sweep(out: Path, *extra) -> int:
    return main(["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,120", "--out", str(out), *extra])


RUN_1 = {"points.json": "[1]", "summary.md": "one", "plots/a.png": "a1", "plots/b.png": "b1", "plots/a.boundary.vtu": "ab"}
RUN_2 = {"points.json": "[2]", "summary.md": "two", "plots/a.png": "a2"}


def test_a_user_folder_named_like_strainwave_scratch_is_kept(tmp_path, capsys):
    """Reproducer 1: `strainwave analytic --json out.json` beside strainwave-mesh-2024-12-backup/ deleted it."""
    backups = [tmp_path / "strainwave-mesh-2024-12-backup", tmp_path / ".strainwave-scratch-1-x",
               tmp_path / f"strainwave-solve-{2 ** 22 + 7}-old"]   # names of strainwave's own, no owner record
    for folder in backups:
        folder.mkdir()
        (folder / "rig.csv").write_text("data\n")
    assert main(["analytic", "--json", str(tmp_path / "out.json")]) == 0
    assert remove_stale(tmp_path) == 0
    assert all((folder / "rig.csv").read_text() == "data\n" for folder in backups)


def test_a_folder_with_the_users_points_json_is_not_taken_as_strainwave_s(tmp_path, capsys, monkeypatch):
    """Reproducer 2a: `sweep --out lab` over the user's points.json and summary.md replaced both and exited 0."""
    _fake_sweep(monkeypatch, RUN_1)
    lab = tmp_path / "lab"
    lab.mkdir()
    (lab / "points.json").write_text("mine")
    (lab / "summary.md").write_text("my notes")
    _refusal(capsys, _sweep(lab))
    assert _digests(lab) == {"points.json": hashlib.sha256(b"mine").hexdigest(),
                             "summary.md": hashlib.sha256(b"my notes").hexdigest()}


def test_the_manifest_lists_every_file_with_its_hash_and_an_edited_report_is_kept(tmp_path, capsys, monkeypatch):
    """Reproducer 2b: the manifest was empty, so an edited report was replaced by the next run."""
    out = tmp_path / "s"
    _fake_sweep(monkeypatch, RUN_1)
    assert _sweep(out) == 0
    listed = json.loads((out / MANIFEST).read_text())["files"]
    assert {k: v["sha256"] for k, v in listed.items()} == _digests(out)
    (out / "summary.md").write_text("one, with my comments")
    err = _refusal(capsys, _sweep(out))
    assert "summary.md" in err and (out / "summary.md").read_text() == "one, with my comments"
    assert _sweep(out, "--force") == 0 and (out / "summary.md").read_text() == "one"


def test_a_rerun_replaces_the_previous_set_and_keeps_what_the_user_added(tmp_path, monkeypatch):
    out = tmp_path / "s"
    _fake_sweep(monkeypatch, RUN_1)
    assert _sweep(out) == 0
    (out / "plots" / "my-sketch.png").write_text("user's")
    _fake_sweep(monkeypatch, RUN_2)
    assert _sweep(out) == 0
    assert _digests(out) == {**{k: hashlib.sha256(v.encode()).hexdigest() for k, v in RUN_2.items()},
                             "plots/my-sketch.png": hashlib.sha256(b"user's").hexdigest()}
    assert set(json.loads((out / MANIFEST).read_text())["files"]) == set(RUN_2)


def test_an_interrupted_run_leaves_the_previous_complete_set_and_its_finished_cases(tmp_path, capsys, monkeypatch):
    """Reproducer 3: SIGTERM during the images left new VTUs beside the old run's reports."""
    out = tmp_path / "s"
    _fake_sweep(monkeypatch, RUN_1)
    assert _sweep(out) == 0
    before = _digests(out)
    _fake_sweep(monkeypatch, RUN_2, fail_after=2, cache_entry=True)
    assert _sweep(out) == 130
    assert _digests(out) == {**before, "cache/finished.json": _digests(out)["cache/finished.json"]}
    assert not [p for p in out.iterdir() if p.name.startswith(".strainwave-")
                and p.name != MANIFEST], "no staging folder is left"


def test_a_second_run_into_a_locked_folder_is_refused_in_one_line(tmp_path, capsys, monkeypatch):
    """Reproducer 7: two sweeps into one --out both exited 0, the last one's outputs replacing the first's."""
    out = tmp_path / "s"
    out.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", "import fcntl, os, sys, time; fd = os.open(sys.argv[1], os.O_RDONLY);"
                               "fcntl.flock(fd, fcntl.LOCK_EX); print('held', flush=True); time.sleep(60)", str(out)],
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        _fake_sweep(monkeypatch, RUN_1)
        assert "another strainwave run" in _refusal(capsys, _sweep(out))
    finally:
        holder.kill()
        holder.wait()
    assert list(out.iterdir()) == []
    assert _sweep(out) == 0, "the lock goes with the process that held it"


@pytest.mark.parametrize("text", ["[]", '{"status": "ok"}', '{"status": "ok", "fea": {}, "analytic": {}}', "nul\x00"])
def test_a_damaged_or_hand_made_sweep_point_is_recomputed(tmp_path, text):
    """Reproducer 6: '[]' gave an internal error, {"status": "ok"} was taken as a finished point."""
    from strainwave.compare.sweep.task import point_record_ok
    cache = ResultCache(tmp_path)
    cache.path("k").write_text(text)
    assert cache.get("k", lambda r: point_record_ok(r, "k")) is None
    good = {"key": "k", "status": "ok", "error": None, "fea": {"q": {"value": 1.0, "unit": "mm"}}, "analytic": {}}
    cache.put("k", good)
    assert cache.get("k", lambda r: point_record_ok(r, "k")) == good
    assert cache.get("k", lambda r: point_record_ok(r, "other")) is None, "an entry answers only its own key"


def test_a_validate_case_entry_of_another_shape_is_recomputed(tmp_path):
    from strainwave.cache import NUMBER
    cache = ResultCache(tmp_path)
    schema = {"result": dict, "seconds": NUMBER}
    for bad in ([], {"result": [], "seconds": 1.0}, {"result": {}, "seconds": True}, {"result": {}}):
        cache.put("k", bad)
        assert cache.get("k", schema) is None, bad
    cache.put("k", {"result": {}, "seconds": 2})
    assert cache.get("k", schema) == {"result": {}, "seconds": 2}


def test_a_file_of_an_earlier_run_is_reused_only_while_unchanged(tmp_path, monkeypatch):
    """validate reuses a cached case's VTU from the previous run (now in the folder, not in its removed stage)."""
    from strainwave.output_guard import reuse_output
    out = tmp_path / "s"
    _fake_sweep(monkeypatch, RUN_1)
    assert _sweep(out) == 0
    recorded = out / ".strainwave-stage-123-gone" / "plots" / "a.png"   # as the earlier run recorded it
    seen = {}

    def run_sweep(study, *, out_dir, **kw):
        reused = reuse_output(recorded)
        seen["reused"] = (str(reused), reused.read_text())
        (out / "plots" / "b.png").write_text("edited")   # the user edits another of the earlier run's files
        seen["changed"] = reuse_output(out / "plots" / "b.png")
        return _Outcome()

    import strainwave.compare.sweep.pipeline as pipeline
    monkeypatch.setattr(pipeline, "run_sweep", run_sweep)
    assert _sweep(out) == 0
    assert seen["reused"][1] == "a1" and ".strainwave-stage-" in seen["reused"][0], "linked into this run's stage"
    assert (out / "plots" / "a.boundary.vtu").read_text() == "ab", "with the file written beside it"
    assert seen["changed"] is None
    assert (out / "plots" / "a.png").read_text() == "a1" and (out / "plots" / "b.png").read_text() == "edited"
    assert set(json.loads((out / MANIFEST).read_text())["files"]) == {"plots/a.png", "plots/a.boundary.vtu"}


def test_a_json_summary_written_into_the_out_folder_is_kept_and_listed(tmp_path, monkeypatch):
    out = tmp_path / "s"
    _fake_sweep(monkeypatch, RUN_1)
    assert _sweep(out, "--json", str(out / "summary.json")) == 0
    assert _sweep(out, "--json", str(out / "summary.json")) == 0, "its own summary is strainwave's on the rerun"
    assert json.loads((out / "summary.json").read_text()) is not None
    assert "summary.json" in json.loads((out / MANIFEST).read_text())["files"]


def test_size_crack_reads_its_curves_file_before_any_work(tmp_path, capsys):
    """Minor item: `size-crack ... --curves garbage.bin` exited 0 without reading it."""
    from tests.test_reliability_guards import _GOOD
    (tmp_path / "r.csv").write_text(_GOOD)
    (tmp_path / "garbage.bin").write_bytes(bytes(range(256)) * 8)
    (tmp_path / "other.json").write_text('{"checks": []}')
    for name in ("garbage.bin", "other.json"):
        err = _refusal(capsys, main(["size-crack", str(tmp_path / "r.csv"), "--curves", str(tmp_path / name)]))
        assert err.startswith(f"error: --curves = '{tmp_path / name}': a validate results.json"), err
