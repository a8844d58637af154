"""``cache.shared_entry``: what two cases of a run share is computed once, even when they run at once."""
from __future__ import annotations

import multiprocessing
import time
from pathlib import Path

import pytest

from strainwave.cache import shared_entry


def _read(path: Path) -> str:
    text = path.read_text()
    if not text.startswith("ok:"):
        raise ValueError("damaged")
    return text


def _write(path: Path, value: str) -> None:
    path.write_text(value)


def _case(entry: Path, log: Path, out: Path) -> None:
    def compute() -> str:
        with open(log, "a") as f:
            f.write("computed\n")
        time.sleep(0.4)     # long enough that the second case asks while the first still computes
        return "ok:value"
    out.write_text(shared_entry(entry, _read, compute, _write))


@pytest.mark.skipif("fork" not in multiprocessing.get_all_start_methods(), reason="needs fork")
def test_two_cases_at_once_compute_the_entry_once(tmp_path):
    entry, log = tmp_path / "cache" / "ring.txt", tmp_path / "log.txt"
    ctx = multiprocessing.get_context("fork")
    cases = [ctx.Process(target=_case, args=(entry, log, tmp_path / f"out{k}.txt")) for k in range(2)]
    for case in cases:
        case.start()
    for case in cases:
        case.join(20)
    assert [c.exitcode for c in cases] == [0, 0]
    assert log.read_text().count("computed") == 1
    assert (tmp_path / "out0.txt").read_text() == (tmp_path / "out1.txt").read_text() == "ok:value"


def test_a_damaged_entry_is_computed_again_and_no_path_keeps_nothing(tmp_path):
    entry = tmp_path / "ring.txt"
    entry.write_text("garbage")
    assert shared_entry(entry, _read, lambda: "ok:new", _write) == "ok:new"
    assert entry.read_text() == "ok:new"
    assert shared_entry(entry, _read, lambda: "ok:other", _write) == "ok:new"     # read back, not recomputed
    assert shared_entry(None, _read, lambda: "ok:alone", _write) == "ok:alone"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ring.txt", "ring.txt.lock"]


def test_code_version_holds_beside_a_folder_named_strainwave(tmp_path):
    """A folder named strainwave in the working directory (README run: `cp -r strainwave/data`, or an output folder)
    makes `strainwave` a namespace package without __file__ where '' leads sys.path, as in validate's case processes:
    every case keyed by code_version failed with TypeError (found running the README's validate, issue 52)."""
    import subprocess
    import sys

    from strainwave.cache import code_version

    (tmp_path / "strainwave" / "data").mkdir(parents=True)
    proc = subprocess.run([sys.executable, "-c", "from strainwave.cache import code_version; print(code_version())"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-500:]
    assert proc.stdout.strip() == code_version()
