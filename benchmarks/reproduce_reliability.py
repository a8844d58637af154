"""Issue 38's reproducers, each run as the issue ran it (the installed CLI, from a shell in an empty folder),
and the table the issue asks for: category, tried, clean, internal errors, hangs, files lost.

    .venv/bin/python benchmarks/reproduce_reliability.py          # ~2-4 min on 2 shared cores

clean: exit 2 with one line (or exit 1 'disk full: PATH' for a full disk, or a run that should go through and
did, with one line per warning); internal: any other exit, a traceback or more lines; hang: past the limit
(REFUSAL_LIMIT_S, or 3 s after SIGTERM); files lost: an input or foreign file changed, a partial output set
or a scratch/stage folder left behind. Exit status 0 when the last three columns are zeros.
"""
from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from dataclasses import dataclass, field
from pathlib import Path

BIN = Path(sys.executable).with_name("strainwave")
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
REFUSAL_LIMIT_S = 30.0   # a refusal is argument and schema checks; the machine is shared (load 4-14 seen)


@dataclass
class Row:
    category: str
    tried: int = 0
    clean: int = 0
    internal: int = 0
    hangs: int = 0
    lost: int = 0
    notes: list[str] = field(default_factory=list)

    def add(self, outcome: str, note: str) -> None:
        self.tried += 1
        setattr(self, outcome, getattr(self, outcome) + 1)
        if outcome != "clean":
            self.notes.append(note[:300])


def _digest(paths) -> dict:
    return {p: hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else None for p in paths}


def _leftovers(folder: Path) -> list[str]:
    return [str(p) for p in folder.rglob("*") if p.name.startswith((".strainwave-stage-", ".strainwave-scratch-"))
            or p.name.endswith(".tmp")]


def run(row: Row, what: str, argv: list[str], cwd: Path, *, keep=(), expect=(2,), absent=(),
        limit_s: float = REFUSAL_LIMIT_S, env: dict | None = None) -> None:
    """One reproducer: ``expect`` the exit statuses counted clean; ``keep`` files that must not change;
    ``absent`` outputs that must not appear."""
    before = _digest([cwd / k for k in keep])
    start = time.perf_counter()
    try:
        done = subprocess.run([str(BIN), *argv], cwd=cwd, capture_output=True, text=True, timeout=limit_s, env=env or ENV)
    except subprocess.TimeoutExpired:
        row.add("hangs", f"{what}: still running after {limit_s:g} s")
        return
    took = time.perf_counter() - start
    lines = [ln for ln in done.stderr.splitlines() if ln.strip()]
    errors = [ln for ln in lines if not ln.startswith("warning: ")]
    if _digest([cwd / k for k in keep]) != before or any((cwd / a).exists() for a in absent) or _leftovers(cwd):
        row.add("lost", f"{what}: a kept file changed, an output appeared or scratch was left")
    elif done.returncode not in expect or "Traceback" in done.stderr or "internal error" in done.stderr \
            or len(errors) > 1 or (done.returncode and not errors) or any("\x1b" in ln for ln in lines):
        row.add("internal", f"{what}: exit {done.returncode} in {took:.1f} s: {done.stderr[-300:]!r}")
    else:
        row.add("clean", what)


def _recording(kind: str, specimen: str, params_toml: str = "") -> str:
    import numpy as np
    from strainwave.compare.diagnose.recording import RecordingKind, format_recording
    load = np.linspace(0.0, 1000.0, 40)
    text = format_recording(RecordingKind(kind), specimen, load, load / 4.0e8 + 1e-10 * np.sin(np.arange(40)))
    lines = text.splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    return "\n".join(lines[:first] + ["# " + ln for ln in params_toml.splitlines()] + lines[first:]) + "\n"


def meshing(work: Path) -> Row:
    row = Row("meshing hangs and budget (1-3)")
    (work / "p.toml").write_text("[ewg_drive]\npressure_angle_deg=40.0\ndedendum_coefficient=0.1\n")
    run(row, "solve ring-compression, pointed teeth", ["solve", "ring-compression", "--params", "p.toml"], work)
    (work / "r1.csv").write_text(_recording("ring_compression", "ewg_ring",
                                            "[params.ewg_drive]\npressure_angle_deg=40.0\ndedendum_coefficient=0.1"))
    run(row, "diagnose --baseline fea, pointed teeth", ["diagnose", "r1.csv", "--baseline", "fea"], work)
    (work / "r2.csv").write_text(_recording("torsion", "output_shaft", "[params.output_shaft]\ninner_diameter_mm=69.9979\n"
                                            "crack_depth_mm=0.001\n[params.crack_geometry]\nslot_width_mm=0.0001"))
    run(row, "diagnose --baseline fea, thin wall", ["diagnose", "r2.csv", "--baseline", "fea"], work)
    for axes in ("[1e3,3.0]", "[1e3,1e-3]"):
        (work / "b.toml").write_text(f"[wave_generator]\ncontact_semi_axes_mm={axes}\n")
        run(row, f"bearing contact {axes}", ["solve", "bearing-ring", "--params", "b.toml", "--mesh-size-mm", "20"], work)
    return row


def outputs(work: Path) -> Row:
    row = Row("outputs: overwrites and collisions (4, 9, 11)")
    (work / "o").mkdir()
    (work / "o" / "sweep.csv").write_text("output_shaft.length_mm\n100\n150\n")
    run(row, "sweep onto its --samples", ["sweep", "shaft-torsion", "--samples", "o/sweep.csv", "--quick", "--out", "o"],
        work, keep=["o/sweep.csv"])
    (work / "d.csv").write_text(_recording("torsion", "output_shaft"))
    (work / "README.md").write_text("# the project's readme\n")
    cases = [("diagnose --json x --plot x", ["diagnose", "d.csv", "--json", "x", "--plot", "x"], ["x"]),
             ("solve --vtu s.vtu --json s.vtu", ["solve", "shaft-torsion", "--vtu", "s.vtu", "--json", "s.vtu"], ["s.vtu"]),
             ("--json t.boundary.vtu beside --vtu t.vtu",
              ["solve", "shaft-torsion", "--vtu", "t.vtu", "--json", "t.boundary.vtu"], ["t.vtu"]),
             ("export-step -o s.step --png s.step", ["export-step", "--part", "output-shaft", "-o", "s.step", "--png",
                                                     "s.step"], ["s.step"]),
             ("solve --vtu README.md", ["solve", "shaft-torsion", "--vtu", "README.md"], [])]
    for what, argv, absent in cases:
        run(row, what, argv, work, keep=["README.md", "d.csv"], absent=absent)
    (work / "a-ewg-drive.step").mkdir()
    run(row, "export-step assembly onto a folder", ["export-step", "--part", "assembly", "-o", "a.step"], work,
        absent=["a.step"])
    run(row, "solve --json shaft-torsion (an option takes no positional)",
        ["solve", "--json", "shaft-torsion", "--mesh-size-mm", "1e-300"], work, absent=["shaft-torsion"])
    run(row, "--mesh abbreviation", ["solve", "shaft-torsion", "--mesh", "3"], work)
    return row


def paths_and_inputs(work: Path) -> Row:
    row = Row("paths, FIFOs, CSV, TOML, messages (7, 8, 10, 12)")
    os.mkfifo(work / "f")
    for argv in (["analytic", "--params", "f"], ["diagnose", "f"], ["sweep", "shaft-torsion", "--samples", "f", "--out", "sf"]):
        run(row, f"FIFO: {' '.join(argv)}", argv, work)
    (work / "loop").symlink_to(work / "loop")
    for what, argv in [("--json symlink loop", ["analytic", "--json", "loop"]),
                       ("--out symlink loop", ["benchmark-diagnose", "--n", "1", "--out", "loop"]),
                       ("300-character name", ["analytic", "--json", "n" * 300 + ".json"]),
                       ("path over 4096", ["analytic", "--json", "/".join(["d" * 200] * 22) + "/a.json"])]:
        run(row, what, argv, work)
    rec = _recording("torsion", "output_shaft").splitlines()
    first = next(i for i, ln in enumerate(rec) if not ln.startswith("#"))
    for size in (100_000, 1_000_000):
        (work / "q.csv").write_text("\n".join(rec[:first + 1] + [',"a' * (size // 3)] + rec[first + 1:]) + "\n")
        run(row, f"quadratic sniff {size // 1000} KB", ["diagnose", "q.csv"], work)
    (work / "c.csv").write_text("\n".join(rec[:first] + ['"' + "t" * 140_000 + '",twist_rad'] + rec[first + 1:]) + "\n")
    run(row, "column row over the csv field limit", ["diagnose", "c.csv"], work)
    (work / "s.csv").write_text('output_shaft.length_mm\n"' + "1" * 140_000 + '"\n')
    run(row, "--samples cell over the csv field limit", ["sweep", "shaft-torsion", "--samples", "s.csv", "--out", "so"], work)
    (work / "deep.toml").write_text("[material." + ".".join(["x"] * 5000) + "]\n")
    run(row, "5,000-level TOML table", ["analytic", "--params", "deep.toml"], work)
    (work / "esc.toml").write_text('[material]\n"\\u001b[2J\\u000bX" = 1\n')
    run(row, "control codes in a key", ["analytic", "--params", "esc.toml"], work)
    name = "x$\\foo{$y.csv"
    (work / name).write_text(_recording("torsion", "output_shaft"))
    run(row, "mathtext file name with --plot", ["diagnose", name, "--plot", "m.png"], work, expect=(0,))
    return row


def flags_and_scheduler(work: Path) -> Row:
    row = Row("flags, scheduler, workers (5, 6, 8, 15)")
    vary = ["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--out", "w"]
    for what, argv in [("--workers 10000", [*vary, "--workers", "10000"]),
                       ("--scheduler tls://127.0.0.1:9", [*vary, "--scheduler", "tls://127.0.0.1:9"]),
                       ("--scheduler unix://", [*vary, "--scheduler", "unix:///tmp/x"]),
                       ("ring --mesh-size-mm 10", ["solve", "ring-compression", "--mesh-size-mm", "10"]),
                       ("--mesh-size-mm 5e-324", ["solve", "shaft-torsion", "--mesh-size-mm", "5e-324"]),
                       ("benchmark-diagnose --seed -1", ["benchmark-diagnose", "--seed", "-1"]),
                       ("benchmark-diagnose --n 1e9", ["benchmark-diagnose", "--n", "1000000000"])]:
        run(row, what, argv, work)
    (work / "u.csv").write_text("output_shaft.length_mm\n1_00\n")
    run(row, "1_00 in --samples", ["sweep", "shaft-torsion", "--samples", "u.csv", "--out", "uo"], work)
    rec = _recording("torsion", "output_shaft").splitlines()
    first = next(i for i, ln in enumerate(rec) if not ln.startswith("#"))
    rec[first + 2] = "\u0661\u0660,\uff11"
    (work / "ar.csv").write_text("\n".join(rec) + "\n", encoding="utf-8")
    run(row, "Arabic-Indic / full-width digits", ["diagnose", "ar.csv"], work)
    done = subprocess.run([sys.executable, "-c", _INTRUDER], capture_output=True, text=True, timeout=180, env=ENV,
                          cwd=work)
    row.add("clean" if done.stdout.strip() == "refused" else "internal",
            f"local scheduler without credentials: {done.stdout.strip()} {done.stderr[-200:]}")
    return row


_INTRUDER = textwrap.dedent("""
    from pathlib import Path
    from distributed import Client
    from strainwave.compare.sweep.pipeline import dask_client
    with dask_client(None, 1, Path("scratch")) as (client, n):
        address = client.scheduler.address
        try:
            Client(address.replace("tls://", "tcp://"), timeout="3s").submit(sum, [1]).result(timeout=5)
            print("ACCEPTED")
        except Exception:
            try:
                Client(address, timeout="3s").submit(sum, [1]).result(timeout=5)
                print("ACCEPTED")
            except Exception:
                print("refused")
""")


def physics(work: Path) -> Row:
    row = Row("absurd physics, one check (14)")
    for what, body, argvs in [("2 EWG teeth", "[ewg_drive]\nflexspline_teeth=2\ntooth_difference=1\n",
                               (["analytic"], ["solve", "ring-compression"])),
                              ("400 cup teeth of 0.01 mm", "[flexspline_cup]\nteeth=400\nmodule_mm=0.01\n",
                               (["analytic"], ["export-step", "--part", "flexspline-cup", "-o", "c.step"]))]:
        (work / "g.toml").write_text(body)
        for argv in argvs:
            run(row, f"{what}: {argv[0]}", [*argv, "--params", "g.toml"], work)
    (work / "deep_crack.toml").write_text("[output_shaft]\ncrack_depth_mm = 12.49\n")
    run(row, "crack at a/t -> 1 (one line per warning)", ["analytic", "--params", "deep_crack.toml"], work, expect=(0, 2))
    done = subprocess.run([str(BIN), "analytic"], cwd=work, capture_output=True, text=True, env=ENV, timeout=60)
    row.add("clean" if done.stderr.count("warning: material") <= 1 else "internal", "material warning printed twice")
    return row


def _group(pgid: int) -> list[str]:
    return subprocess.run(["pgrep", "-g", str(pgid)], capture_output=True, text=True).stdout.split()


def sigterm(work: Path) -> Row:
    row = Row("SIGTERM and stale scratch (13)")
    tmp = work / "tmp"
    tmp.mkdir()
    env = {**ENV, "TMPDIR": str(tmp)}
    for argv in (["solve", "shaft-torsion"], ["sweep", "shaft-torsion", "--quick", "--vary",
                                               "output_shaft.inner_diameter_mm=40,42", "--workers", "1", "--out", "sw"]):
        proc = subprocess.Popen([str(BIN), *argv], cwd=work, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                env=env, start_new_session=True)
        time.sleep(12)
        proc.send_signal(signal.SIGTERM)
        sent = time.perf_counter()
        try:
            _, err = proc.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            row.add("hangs", f"{argv[0]}: running 15 s after SIGTERM")
            continue
        took = time.perf_counter() - sent
        deadline = time.perf_counter() + 5.0   # as fuzz_reliability.interrupt: no process of the group after 5 s
        while time.perf_counter() < deadline and _group(proc.pid):
            time.sleep(0.2)
        alive = _group(proc.pid)
        left = [p.name for p in tmp.iterdir()] + _leftovers(work) + [str(p) for p in work.rglob(".dask-scratch")]
        if left or alive:
            row.add("lost", f"{argv[0]}: left {left[:3]} and processes {alive}")
        elif took > 3.0 or (proc.returncode not in (143, 0)) or "Traceback" in err:
            row.add("hangs" if took > 3.0 else "internal", f"{argv[0]}: exit {proc.returncode} {took:.1f} s after "
                                                             f"SIGTERM: {err[-200:]!r}")
        else:
            row.add("clean", argv[0])
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = work / "st" / f".strainwave-scratch-{dead.stdout.strip()}-x"
    stale.mkdir(parents=True)
    subprocess.run([str(BIN), "analytic", "--json", "st/a.json"], cwd=work, capture_output=True, env=ENV, timeout=60)
    row.add("lost" if stale.exists() else "clean", "stale scratch of a killed run not removed")
    return row


def disk_full(work: Path) -> Row:
    row = Row("full disk (8, 11)")   # 48 KiB: room for the PNG (45 KB), not for the JSON after it
    mnt = work / "small"
    mnt.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=48k", "tmpfs", str(mnt)], capture_output=True).returncode:
        row.notes.append("not tried: no permission to mount a small tmpfs (tests/test_reliability_guards.py simulates it)")
        return row
    try:
        (work / "d.csv").write_text(_recording("torsion", "output_shaft"))
        run(row, "diagnose --plot --json on a full disk",
            ["diagnose", "d.csv", "--plot", "small/d.png", "--json", "small/d.json"], work, expect=(1,),
            absent=["small/d.png", "small/d.json"])
    finally:
        subprocess.run(["umount", str(mnt)], capture_output=True)
    return row


def main() -> int:
    rows = []
    with tempfile.TemporaryDirectory(prefix="issue38-") as tmp:
        for name, category in [("m", meshing), ("o", outputs), ("p", paths_and_inputs), ("f", flags_and_scheduler),
                               ("x", physics), ("d", disk_full), ("s", sigterm)]:
            work = Path(tmp) / name
            work.mkdir()
            rows.append(category(work))
            print(f"{rows[-1].category}: done", file=sys.stderr, flush=True)
    print(f"| {'category':<48} | tried | clean | internal errors | hangs | files lost |")
    print(f"|{'-' * 50}|-------|-------|-----------------|-------|------------|")
    for r in rows:
        print(f"| {r.category:<48} | {r.tried:>5} | {r.clean:>5} | {r.internal:>15} | {r.hangs:>5} | {r.lost:>10} |")
    total = Row("total", *(sum(getattr(r, c) for r in rows) for c in ("tried", "clean", "internal", "hangs", "lost")))
    print(f"| {'total':<48} | {total.tried:>5} | {total.clean:>5} | {total.internal:>15} | {total.hangs:>5} | "
          f"{total.lost:>10} |")
    for r in rows:
        for note in r.notes:
            print(f"  {r.category}: {note}")
    return 0 if total.internal == total.hangs == total.lost == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
