"""Issue 53's reproducers, run as the issue ran them (the installed CLI in a fresh folder), and the count table the
issue asks for: per finding, how many reproducers ended with the user's data intact and a clean exit (0, or 2 with
one line).

    .venv/bin/python benchmarks/reproduce_issue53.py [STRAINWAVE]     # default: this venv's; ~5-10 min, 2 cores

Pass another checkout's ``.venv/bin/strainwave`` to count the same reproducers against it (the "before" column).
Each reproducer is a function returning (ok, note); the table prints per category: tried, clean, and the notes of
the others. Exit status 0 when every reproducer is clean.
"""
from __future__ import annotations

import hashlib
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BIN = sys.argv[1] if len(sys.argv) > 1 else str(Path(sys.executable).with_name("strainwave"))
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
SWEEP = ["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,120", "--quick", "--workers", "1"]


def sw(cwd: Path, *argv, timeout: float = 900, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([BIN, *argv], cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env or ENV)


def one_line(done, status=2) -> bool:
    errors = [ln for ln in done.stderr.splitlines() if ln.startswith("error: ") or "Traceback" in ln]
    return done.returncode == status and len(errors) == (1 if status == 2 else 0) and \
        (status != 2 or len([ln for ln in done.stderr.splitlines() if ln.strip() and not ln.startswith("warning: ")]) == 1)


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else "absent"


def _recording(cwd: Path) -> Path:
    import numpy as np
    from strainwave.compare.diagnose.recording import RecordingKind, format_recording
    load = np.linspace(0.0, 1000.0, 40)
    rec = cwd / "r.csv"
    rec.write_text(format_recording(RecordingKind.TORSION, "output_shaft", load,
                                    load / 4.0e8 + 1e-10 * np.sin(np.arange(40))))
    return rec


# ---- 1. user folders deleted -----------------------------------------------------------------------------

def folder_beside_json(cwd):
    (cwd / "strainwave-mesh-2024-12-backup").mkdir()
    (cwd / "strainwave-mesh-2024-12-backup" / "rig.csv").write_text("data\n")
    done = sw(cwd, "analytic", "--json", "out.json")
    return one_line(done, 0) and digest(cwd / "strainwave-mesh-2024-12-backup" / "rig.csv") != "absent", done.stderr[-200:]


def folder_in_out(cwd):
    (cwd / "o").mkdir()
    (cwd / "o" / "strainwave-scratch-99999999-old").mkdir()
    (cwd / "o" / "strainwave-scratch-99999999-old" / "notes.txt").write_text("mine")
    done = sw(cwd, "params", "--json", "o/p.json")
    return one_line(done, 0) and (cwd / "o" / "strainwave-scratch-99999999-old" / "notes.txt").exists(), done.stderr[-200:]


def folder_in_tmp_on_solve(cwd):
    tmp = cwd / "tmp"
    (tmp / "strainwave-solve-99999999-results").mkdir(parents=True)
    (tmp / "strainwave-solve-99999999-results" / "a.vtu").write_text("mine")
    done = sw(cwd, "solve", "shaft-torsion", "--mesh-size-mm", "12", env={**ENV, "TMPDIR": str(tmp)})
    return one_line(done, 0) and (tmp / "strainwave-solve-99999999-results" / "a.vtu").exists(), done.stderr[-200:]


# ---- 2. user files replaced --------------------------------------------------------------------------------

def users_points_json(cwd):
    (cwd / "lab").mkdir()
    (cwd / "lab" / "points.json").write_text("mine")
    (cwd / "lab" / "summary.md").write_text("my notes")
    done = sw(cwd, *SWEEP, "--out", "lab")
    kept = (cwd / "lab" / "points.json").read_text() == "mine" and (cwd / "lab" / "summary.md").read_text() == "my notes"
    return kept and done.returncode in (0, 2) and (done.returncode == 0 or one_line(done)), f"exit {done.returncode}"


def edited_report(cwd):
    first = sw(cwd, *SWEEP, "--out", "s")
    (cwd / "s" / "summary.md").write_text("edited by the user")
    done = sw(cwd, *SWEEP, "--out", "s")
    kept = (cwd / "s" / "summary.md").read_text() == "edited by the user"
    return first.returncode == 0 and kept and (done.returncode == 0 or one_line(done)), f"exit {done.returncode}"


def manifest_lists_files(cwd):
    done = sw(cwd, *SWEEP, "--out", "s")
    import json
    try:
        files = json.loads((cwd / "s" / ".strainwave-outputs.json").read_text())["files"]
    except (OSError, ValueError, KeyError):
        files = {}
    return done.returncode == 0 and "points.json" in files and "summary.md" in files, f"{len(files)} files listed"


# ---- 3. outputs together -------------------------------------------------------------------------------------

def interrupted_validate(cwd):
    first = sw(cwd, "validate", "--quick", "--out", "v", timeout=1800)
    before = {p: digest(p) for p in (cwd / "v").rglob("*") if p.is_file() and "cache" not in p.parts}
    (cwd / "t.toml").write_text("[gear]\noutput_torque_Nmm = 2000.0\n")
    proc = subprocess.Popen([BIN, "validate", "--quick", "--out", "v", "--params", "t.toml"], cwd=cwd, env=ENV,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    for line in proc.stderr:   # the images stage: the FEA fields of the new run are written by now
        if line.startswith("[5/6] images"):
            time.sleep(2)
            proc.send_signal(signal.SIGTERM)
            break
    proc.communicate(timeout=120)
    after = {p: digest(p) for p in (cwd / "v").rglob("*") if p.is_file() and "cache" not in p.parts
             and not any(part.startswith(".strainwave-") and part != ".strainwave-outputs.json" for part in p.parts)}
    return first.returncode in (0, 1) and after == before, f"{sum(after.get(p) != d for p, d in before.items())} " \
                                                           f"files changed, {len(set(after) - set(before))} new"


# ---- 4. impossible drives ------------------------------------------------------------------------------------

def _impossible(cwd, text, *argv):
    (cwd / "p.toml").write_text(text)
    done = sw(cwd, *argv, "--params", "p.toml")
    return one_line(done), f"exit {done.returncode}: {done.stderr.strip().splitlines()[-1][:120] if done.stderr.strip() else ''}"


def w0_analytic(cwd):
    return _impossible(cwd, "[gear]\nradial_deformation_mm = 100\n", "analytic")


def w0_solve(cwd):
    return _impossible(cwd, "[gear]\nradial_deformation_mm = 100\n", "solve", "wg-bearing")


def w0_validate(cwd):
    return _impossible(cwd, "[gear]\nradial_deformation_mm = 100\n", "validate", "--quick", "--out", "v")


def patch_solve(cwd):
    return _impossible(cwd, "[wave_generator]\ncontact_semi_axes_mm = [900.0, 900.0]\n", "solve", "wg-bearing")


def ring_analytic(cwd):
    return _impossible(cwd, "[wave_generator]\nbearing_inner_ring_thickness_mm = 90\n", "analytic")


# ---- 5. refusals name what the user gave -----------------------------------------------------------------------

def cup_length(cwd):
    (cwd / "p.toml").write_text("[flexspline_cup]\nlength_mm = 1\n")
    done = sw(cwd, "solve", "cup-torsion", "--params", "p.toml")
    return one_line(done) and "flexspline_cup.length_mm" in done.stderr, done.stderr.strip()[:160]


def thin_wall_validate(cwd):
    (cwd / "p.toml").write_text("[flexspline_cup]\nwall_thickness_mm = 0.05\nroot_crack_depth_mm = 0.03\n"
                                "[crack_geometry]\nslot_width_mm = 0.005\n")
    done = sw(cwd, "validate", "--quick", "--out", "v", "--params", "p.toml")
    return one_line(done) and "--params" not in done.stderr and "flexspline_cup" in done.stderr, done.stderr.strip()[:160]


def header_key(cwd):
    rec = _recording(cwd)
    lines = rec.read_text().splitlines()
    rec.write_text("\n".join(["# [params.output_shaft]", "# inner_diameter_mm = 60.0"] + lines) + "\n")
    (cwd / "p.toml").write_text("[output_shaft]\nouter_diameter_mm = 50.0\n")
    done = sw(cwd, "diagnose", "r.csv", "--params", "p.toml")
    return one_line(done) and "r.csv" in done.stderr, done.stderr.strip()[:160]


# ---- 6. cache ------------------------------------------------------------------------------------------------

def _damaged_sweep(cwd, text):
    first = sw(cwd, *SWEEP, "--out", "s")
    for entry in (cwd / "s" / "cache").glob("*.json"):
        entry.write_text(text)
    done = sw(cwd, *SWEEP, "--out", "s")
    import json
    try:
        points = json.loads((cwd / "s" / "points.json").read_text())
        recomputed = all(p.get("fea") for p in points)
    except (OSError, ValueError, AttributeError):
        recomputed = False
    return first.returncode == 0 and done.returncode == 0 and recomputed, f"exit {done.returncode}: {done.stderr[-150:]!r}"


def cache_list(cwd):
    return _damaged_sweep(cwd, "[]")


def cache_status_ok(cwd):
    return _damaged_sweep(cwd, '{"status": "ok"}')


# ---- 7. lock, 8. Dask HTTP ----------------------------------------------------------------------------------

def two_sweeps(cwd):
    a = subprocess.Popen([BIN, *SWEEP, "--out", "s"], cwd=cwd, env=ENV, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    time.sleep(3)
    b = sw(cwd, *SWEEP, "--vary", "output_shaft.inner_diameter_mm=40,45", "--out", "s")
    a.communicate(timeout=900)
    return a.returncode == 0 and one_line(b), f"first exit {a.returncode}, second exit {b.returncode}"


def dask_http(cwd):
    proc = subprocess.Popen([BIN, *SWEEP, "--out", "s"], cwd=cwd, env=ENV, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    served = False
    for line in proc.stderr:
        if "Dask workers at" in line:
            with socket.socket() as s:
                s.settimeout(2)
                served = s.connect_ex(("127.0.0.1", 8787)) == 0
            break
    proc.communicate(timeout=900)
    return not served and proc.returncode == 0, f"8787 {'answers' if served else 'closed'}"


# ---- 9. minor ------------------------------------------------------------------------------------------------

def curves_garbage(cwd):
    _recording(cwd)
    (cwd / "garbage.bin").write_bytes(os.urandom(2048))
    done = sw(cwd, "size-crack", "r.csv", "--curves", "garbage.bin")
    return one_line(done), f"exit {done.returncode}"


def wg_cam_refusal_time(cwd):
    (cwd / "p.toml").write_text("[gear]\nradial_deformation_mm = 60\n")
    start = time.perf_counter()
    done = sw(cwd, "export-step", "--part", "wg-cam", "-o", "c.step", "--params", "p.toml")
    took = time.perf_counter() - start
    return one_line(done) and took < 5.0, f"exit {done.returncode} in {took:.1f} s"


CATEGORIES = {
    "1 user folders deleted": [folder_beside_json, folder_in_out, folder_in_tmp_on_solve],
    "2 user files replaced": [users_points_json, edited_report, manifest_lists_files],
    "3 outputs not together": [interrupted_validate],
    "4 impossible drives solved": [w0_analytic, w0_solve, w0_validate, patch_solve, ring_analytic],
    "5 refusal names another key": [cup_length, thin_wall_validate, header_key],
    "6 damaged cache entry": [cache_list, cache_status_ok],
    "7 two runs in one --out": [two_sweeps],
    "8 Dask HTTP endpoint": [dask_http],
    "9 minor": [curves_garbage, wg_cam_refusal_time],
}


def main() -> int:
    only = set(os.environ.get("ONLY", "").split(",")) - {""}
    rows, failed = [], 0
    for category, checks in CATEGORIES.items():
        clean, notes = 0, []
        run = [c for c in checks if not only or c.__name__ in only]
        for check in run:
            with tempfile.TemporaryDirectory(prefix="issue53-") as cwd:
                try:
                    ok, note = check(Path(cwd))
                except subprocess.TimeoutExpired:
                    ok, note = False, "timed out"
            clean += ok
            if not ok:
                notes.append(f"{check.__name__}: {note}")
            print(f"  {'clean' if ok else 'NOT  '} {check.__name__}: {note}", file=sys.stderr, flush=True)
        rows.append((category, len(run), clean, notes))
        failed += len(run) - clean
    print(f"{'finding':<30} {'tried':>5} {'clean':>5}")
    for category, tried, clean, notes in rows:
        print(f"{category:<30} {tried:>5} {clean:>5}" + (f"   ({'; '.join(notes)})" if notes else ""))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
