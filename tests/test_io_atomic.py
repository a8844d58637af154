"""Atomic writes: the user's umask decides the mode (not mkstemp's 0600), data and directory are fsync'ed
around the rename, and a failing writer leaves the old file and no temporary behind."""
import json
import math
import os
import stat

import pytest

from strainwave import io_atomic
from strainwave.io_atomic import json_ready, atomic_path, atomic_write_bytes, atomic_write_text


@pytest.fixture
def umask():
    """Set the process umask for one test and restore it afterwards."""
    saved = os.umask(0o022)
    os.umask(saved)
    yield lambda mask: os.umask(mask)
    os.umask(saved)


@pytest.mark.parametrize("mask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664), (0o027, 0o640)])
@pytest.mark.parametrize("writer", [atomic_write_text, atomic_write_bytes])
def test_mode_follows_umask(tmp_path, umask, mask, mode, writer):
    umask(mask)
    target = tmp_path / "out" / "report.html"
    writer(target, "x" if writer is atomic_write_text else b"x")
    assert stat.S_IMODE(target.stat().st_mode) == mode


def test_fsync_file_then_rename_then_fsync_directory(tmp_path, monkeypatch):
    events = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd):
        events.append(("fsync", os.readlink(f"/proc/self/fd/{fd}")))
        real_fsync(fd)

    def replace(src, dst):
        events.append(("replace", str(src), str(dst)))
        real_replace(src, dst)

    monkeypatch.setattr(io_atomic.os, "fsync", fsync)
    monkeypatch.setattr(io_atomic.os, "replace", replace)
    target = tmp_path / "results.json"
    atomic_write_text(target, "{}\n")
    assert [e[0] for e in events] == ["fsync", "replace", "fsync"]
    tmp_name = events[1][1]
    assert events[0][1] == tmp_name and events[1][2] == str(target)   # the data, before the rename
    assert events[2][1] == str(tmp_path)                                 # then the directory entry
    assert target.read_text() == "{}\n"


def test_failed_writer_keeps_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "a.txt"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("writer died")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


def test_temporary_keeps_the_target_suffix(tmp_path):
    # writers that pick the format from the extension (matplotlib, VTK) must see it
    with atomic_path(tmp_path / "plot.png") as tmp:
        assert tmp.name.endswith(".png.tmp") and tmp.parent == tmp_path
        tmp.write_bytes(b"png")


def test_stale_temporary_files_of_a_killed_writer_are_removed_and_nothing_else(tmp_path):
    """A writer killed with -9 inside atomic_path leaves its temporary file (issue 16, interruption): the next
    run removes exactly those, never a target or another hidden file."""
    import os
    import signal
    import subprocess
    import sys

    from strainwave.io_atomic import remove_stale_temps

    target = tmp_path / "part.step"
    target.write_text("old, complete\n")
    (tmp_path / ".keep").write_text("")
    (tmp_path / "notes.tmp").write_text("a user's file")
    writer = subprocess.Popen([sys.executable, "-c", (
        "import sys, time; from pathlib import Path; from strainwave.io_atomic import atomic_path\n"
        f"with atomic_path(Path({str(target)!r})) as tmp:\n"
        "    tmp.write_text('half'); print('writing', flush=True); time.sleep(60)\n")], stdout=subprocess.PIPE, text=True)
    assert writer.stdout.readline().strip() == "writing"
    os.kill(writer.pid, signal.SIGKILL)
    writer.wait(10)
    left = sorted(p.name for p in tmp_path.iterdir())
    assert len(left) == 4 and target.read_text() == "old, complete\n"
    assert remove_stale_temps(tmp_path) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == [".keep", "notes.tmp", "part.step"]


def test_json_ready_turns_non_finite_floats_into_null():
    # an unbounded fitted stiffness (K3 = inf of a runner-up stiffening form) crashed `diagnose --json`
    data = {"K3": (math.inf, "N*mm/rad"), "list": [math.nan, 1.5, -math.inf], "n": 3, "s": "x"}
    text = json.dumps(json_ready(data), allow_nan=False)
    assert json.loads(text) == {"K3": [None, "N*mm/rad"], "list": [None, 1.5, None], "n": 3, "s": "x"}
