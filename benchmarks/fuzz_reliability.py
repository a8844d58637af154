"""Reliability harness (issue 16): try the input, path, resource, interruption, determinism and side-effect
promises at scale on real runs, and print the table the issue asks for.

    .venv/bin/python benchmarks/fuzz_reliability.py            # full: ~10 min on 2 cores
    .venv/bin/python benchmarks/fuzz_reliability.py --quick    # reduced (what tests/test_reliability_harness.py runs)

Columns: tried, accepted (ran and gave valid output), clean refusals (exit 2 / InputError, one line naming
the key or file:line), internal errors (any other exception or exit status, a traceback, more than one
line, invalid or non-finite JSON), hangs (over the category's time limit), files lost (a half-written or
temporary file left, a results.json that is not valid JSON, an input overwritten) and stray writes (files
written outside the command's outputs, seen by strace). Every run is seeded: the same command gives the same
table. Exit status 0 when the internal-error, hang and files-lost columns are all zero, else 1.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

BIN = Path(sys.executable).with_name("strainwave")
ENV = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
# A refusal happens before any work: the CLI starts in ~0.3 s, imports included. 20 s leaves room for a
# machine shared with other jobs (load 4-5 measured) and still catches anything that started computing.
REFUSAL_LIMIT_S = 20.0


@dataclass
class Row:
    category: str
    tried: int = 0
    accepted: int = 0
    refused: int = 0
    internal: int = 0
    hangs: int = 0
    lost: int = 0
    stray: int = 0
    notes: list[str] = field(default_factory=list)

    def add(self, outcome: str, note: str = "") -> None:
        self.tried += 1
        setattr(self, outcome, getattr(self, outcome) + 1)
        if note and outcome in ("internal", "hangs", "lost", "stray") and len(self.notes) < 8:
            self.notes.append(note[:300])

    @property
    def clean(self) -> bool:
        return self.internal == self.hangs == self.lost == 0


@dataclass(frozen=True)
class Run:
    status: int | None       # None: killed at the time limit
    stdout: str
    stderr: str
    seconds: float


def cli(args: list[str], *, timeout_s: float = REFUSAL_LIMIT_S, env: dict | None = None, cwd: Path | None = None) -> Run:
    start = time.perf_counter()
    try:
        done = subprocess.run([str(BIN), *args], capture_output=True, text=True, timeout=timeout_s,
                              env=env or ENV, cwd=cwd)
    except subprocess.TimeoutExpired as exc:
        return Run(None, exc.stdout or "", exc.stderr or "", time.perf_counter() - start)
    return Run(done.returncode, done.stdout, done.stderr, time.perf_counter() - start)


def one_line_refusal(run: Run) -> bool:
    lines = [ln for ln in run.stderr.splitlines() if ln.strip()]
    return run.status == 2 and len(lines) == 1 and lines[0].startswith("error:") and "internal error" not in lines[0]


def strict_json(text: str) -> object:
    """json.loads that refuses NaN/Infinity (not JSON) and every non-finite number."""
    def bad(constant):
        raise ValueError(f"non-JSON constant {constant}")
    return json.loads(text, parse_constant=bad)


def classify_cli(run: Run, json_path: Path | None = None) -> tuple[str, str]:
    """(outcome, note) of one CLI run that must either succeed with valid JSON or refuse in one line."""
    if run.status is None:
        return "hangs", f"over {run.seconds:.0f} s"
    if "Traceback" in run.stderr:
        return "internal", run.stderr[-300:]
    if run.status == 2:
        return ("refused", "") if one_line_refusal(run) else ("internal", "refusal not one line: " + run.stderr[:300])
    if run.status != 0:
        return "internal", f"exit {run.status}: {run.stderr[-300:]}"
    if json_path is not None:
        try:
            strict_json(json_path.read_text())
        except (OSError, ValueError) as exc:
            return "internal", f"JSON: {exc}"
    return "accepted", ""


# ---- parameter files ------------------------------------------------------------------------------

def _nasty_values(rng: random.Random) -> list[str]:
    """TOML value texts that broke the loader or the closed forms (issue 16 items 1-5, 10)."""
    return ["1" + "0" * 400, "1" + "0" * 4400, "[" * 2000 + "]" * 2000, "1e-300", "5e-324", "1e-320", "1e300",
            "-1.0", "0", "0.0", "inf", "-inf", "nan", "true", '"x"', '"' + "x" * 200_000 + '"', "[1.0, 2.0]",
            "[]", "{a = 1}", "9" * 30, "-" + "9" * 30, "1e12", "1e13", "4.9e-324", "2.5e-308",
            f"{rng.uniform(-1e6, 1e6)!r}", f"{rng.randint(-10**6, 10**6)}", f"{10 ** rng.uniform(-8, 8)!r}"]


def param_files(n: int, seed: int, folder: Path) -> list[Path]:
    """``n`` TOML files, each setting one to three schema keys (sometimes an unknown one) to a nasty or a
    random in-range value."""
    from strainwave.params import default_dict
    from strainwave.params_bounds import BOUNDS

    rng = random.Random(seed)
    schema = default_dict()
    keys = [(s, k) for s, table in schema.items() for k in table]
    files = []
    for i in range(n):
        chosen: dict[str, dict[str, str]] = {}
        for _ in range(rng.choice((1, 1, 2, 3))):
            section, key = rng.choice(keys)
            if rng.random() < 0.05:
                key = "no_such_key"
            bound = BOUNDS.get(f"{section}.{key}")
            if bound is not None and rng.random() < 0.5:
                value = rng.choice((bound.lo, bound.hi, bound.lo + rng.random() * (bound.hi - bound.lo)))
                text = repr(int(value)) if isinstance(bound.lo, int) and isinstance(bound.hi, int) else repr(float(value))
                if key == "contact_semi_axes_mm":
                    text = f"[{text}, {text}]"
            else:
                text = rng.choice(_nasty_values(rng))
            chosen.setdefault(section, {})[key] = text
        body = "".join(f"[{s}]\n" + "".join(f"{k} = {v}\n" for k, v in t.items()) for s, t in chosen.items())
        path = folder / f"params_{i:05d}.toml"
        path.write_text(body)
        files.append(path)
    return files


def params_in_process(files: list[Path]) -> Row:
    """Loader + every closed form in this process: InputError or finite, valid JSON, nothing else."""
    from strainwave.analytic.summary import analytic_summary
    from strainwave.errors import InputError
    from strainwave.params import load_params

    row = Row("parameter files, loader + analytic (in-process)")
    for path in files:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                params = load_params(path)
                json.dumps(analytic_summary(params), allow_nan=False, default=str)
            except InputError:
                row.add("refused")
                continue
            except Exception as exc:  # noqa: BLE001 - counting them is the point
                row.add("internal", f"{path.name}: {type(exc).__name__}: {exc}")
                continue
        row.add("accepted")
    return row


def params_cli(files: list[Path], out: Path) -> Row:
    row = Row("parameter files, `analytic --params F --json OUT`")
    for path in files:
        target = out / f"{path.stem}.json"
        run = cli(["analytic", "--params", str(path), "--json", str(target)])
        outcome, note = classify_cli(run, target if run.status == 0 else None)
        row.add(outcome, f"{path.name}: {note}")
    return row


# ---- recordings -----------------------------------------------------------------------------------

def _good_recording(rng: random.Random, rows: int = 60) -> str:
    from strainwave.compare.diagnose.recording import RecordingKind, format_recording

    import numpy as np
    load = np.linspace(0.0, 1000.0, rows)
    twist = load / 4.0e8 * (1.0 + 0.01 * rng.random()) + 1e-9 * np.sin(np.arange(rows))
    return format_recording(RecordingKind.TORSION, "output_shaft", load, twist, baseline_uncertainty=0.02)


def _mutate(text: str, rng: random.Random) -> str:
    """One spreadsheet-ish or hostile change of a valid recording (issue 16 items 11-13)."""
    lines = text.splitlines()
    header_end = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    k = rng.randrange(header_end + 1, len(lines))
    kind = rng.randrange(16)
    if kind == 0:
        lines[k] = lines[k].replace(",", ";").replace(".", ",")
    elif kind == 1:
        lines = [ln.replace(",", "\t") if not ln.startswith("#") else ln for ln in lines]
    elif kind == 2:
        lines[header_end] = ",".join(f'"{c}"' for c in lines[header_end].split(","))
    elif kind == 3:
        lines[k] = rng.choice(["1_000,2e-6", "nan,1", "inf,1", "1e309,1", "5e-324,5e-324", "1e304,1e300", ",", "x,y"])
    elif kind == 4:
        lines = lines[:header_end + 1] + [f"{5e-324 * (i % 3)!r},5e-324" for i in range(40)]
    elif kind == 5:
        lines = lines[:header_end + 1] + [f"{i!r},0.0" for i in range(40)]
    elif kind == 6:
        lines.insert(1, "# baseline_stiffness_Nmm_per_rad = " + rng.choice(["1e-300", "1" + "0" * 400, "-1", "0"]))
    elif kind == 7:
        lines.insert(1, "# baseline_uncertainty = " + rng.choice(["1e-300", "0", "1", "2", '"x"']))
    elif kind == 8:
        lines.insert(header_end, "# [params.material]")
        lines.insert(header_end + 1, "# youngs_modulus_MPa = " + rng.choice(["1" + "0" * 400, "5e-324", "-5.0", "2.0e5"]))
    elif kind == 9:
        lines.insert(header_end, "# [meta]")
        lines.insert(header_end + 1, "# x = " + rng.choice(["[" * 3000 + "]" * 3000, "1" + "0" * 5000, '"ok"']))
    elif kind == 10:
        lines.insert(3, "#not toml here")
    elif kind == 11:
        lines = lines[:header_end + 5]
    elif kind == 12:
        lines[k] = lines[k] + ",,"
    elif kind == 13:
        lines = ["\ufeff" + lines[0]] + lines[1:]
    elif kind == 14:
        lines[k] = lines[k] + ",3"
    else:
        lines[k] = "\x00\x01binary"
    return "\r\n".join(lines) + "\n" if rng.random() < 0.2 else "\n".join(lines) + "\n"


def recordings(n: int, seed: int, diagnose_every: int) -> Row:
    """Parser on ``n`` mutated recordings; every ``diagnose_every``-th accepted one also through the whole
    diagnosis and its JSON (finite, valid)."""
    from strainwave.compare.diagnose.pipeline import diagnose
    from strainwave.compare.diagnose.recording import parse_text
    from strainwave.errors import InputError
    from strainwave.params import load_params

    rng = random.Random(seed)
    row = Row("recordings, parser (+ diagnose JSON on a sample)")
    base = _good_recording(rng)
    accepted = 0
    for i in range(n):
        text = _mutate(base, rng)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                rec = parse_text(text, f"mutant_{i}.csv")
                if accepted % diagnose_every == 0:
                    params = load_params(overrides=rec.param_overrides or None)
                    diagnosis, _ = diagnose(rec, params)
                    json.dumps(diagnosis.to_dict(), allow_nan=False, default=str)
        except InputError:
            row.add("refused")
            continue
        except Exception as exc:  # noqa: BLE001
            row.add("internal", f"mutant {i}: {type(exc).__name__}: {exc}")
            continue
        accepted += 1
        row.add("accepted")
    return row


# ---- flags, paths, resources ----------------------------------------------------------------------

def path_table(work: Path) -> list[tuple[str, list[str], Path | None]]:
    """(what, argv, a file that must be unchanged afterwards) for every bad path or flag (items 15-22)."""
    rec = work / "rec.csv"
    rec.write_text(_good_recording(random.Random(0)))
    params = work / "p.toml"
    params.write_text("[output_shaft]\nlength_mm = 150.0\n")
    a_file, a_dir = work / "a_file", work / "a_dir"
    a_file.write_text("x")
    a_dir.mkdir(exist_ok=True)
    unwritable = Path("/proc/strainwave-no")   # no one, not even root, creates files in /proc
    return [
        ("solve crack deeper than the wall", ["solve", "shaft-torsion", "--crack-depth-mm", "20"], None),
        ("solve crack on ring-compression", ["solve", "ring-compression", "--crack-depth-mm", "0.1"], None),
        ("solve negative mesh size", ["solve", "shaft-torsion", "--mesh-size-mm", "-3"], None),
        ("solve unknown study", ["solve", "no-such-study"], None),
        ("solve --vtu into a file's child", ["solve", "shaft-torsion", "--vtu", str(a_file / "x.vtu")], None),
        ("solve --vtu unwritable", ["solve", "shaft-torsion", "--vtu", str(unwritable / "x.vtu")], None),
        ("solve --json is a directory", ["solve", "shaft-torsion", "--json", str(a_dir)], None),
        ("validate --out is a file", ["validate", "--quick", "--out", str(a_file)], None),
        ("validate --out under a file", ["validate", "--quick", "--out", str(a_file / "sub")], None),
        ("validate --out unwritable", ["validate", "--quick", "--out", str(unwritable)], None),
        ("diagnose --json is a directory", ["diagnose", str(rec), "--json", str(a_dir)], None),
        ("diagnose --json unwritable", ["diagnose", str(rec), "--json", str(unwritable / "d.json")], None),
        ("diagnose --plot under a file", ["diagnose", str(rec), "--plot", str(a_file / "p.png")], None),
        ("diagnose --json onto the recording", ["diagnose", str(rec), "--json", str(rec)], rec),
        ("analytic --json onto --params", ["analytic", "--params", str(params), "--json", str(params)], params),
        ("diagnose --json /dev/null (a device)", ["diagnose", str(rec), "--json", "/dev/null"], None),
        ("export-step -o a directory", ["export-step", "--part", "output-shaft", "-o", str(a_dir)], None),
        ("export-step -o unwritable", ["export-step", "--part", "output-shaft", "-o", str(unwritable / "s.step")], None),
        ("diagnose missing recording", ["diagnose", str(work / "missing.csv")], None),
        ("--params a directory", ["analytic", "--params", str(a_dir)], None),
        ("--params missing", ["analytic", "--params", str(work / "missing.toml")], None),
        ("benchmark-diagnose --n 0", ["benchmark-diagnose", "--n", "0"], None),
        ("benchmark-diagnose --n -3", ["benchmark-diagnose", "--n", "-3"], None),
        ("sweep --workers 0", ["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--workers", "0",
                               "--out", str(work / "sw0")], None),
        ("sweep impossible grid point", ["sweep", "shaft-torsion", "--vary", "output_shaft.inner_diameter_mm=30,80",
                                         "--out", str(work / "sw1")], None),
        ("sweep unknown key", ["sweep", "shaft-torsion", "--vary", "gear.no_such=1,2", "--out", str(work / "sw2")], None),
        ("sweep --scheduler nothing listening", ["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150",
                                                 "--scheduler", "tcp://127.0.0.1:9", "--out", str(work / "sw3")], None),
        ("unknown flag", ["analytic", "--no-such-flag"], None),
        ("--order 3", ["solve", "shaft-torsion", "--order", "3"], None),
        *issue38_paths(work, rec, params),
    ]


def issue38_paths(work: Path, rec: Path, params: Path) -> list[tuple[str, list[str], Path | None]]:
    """Issue 38 (items 4, 5, 8-10, 15): outputs onto each other, an input or a foreign file; loops, over-long
    names and FIFOs; flags without bounds. Each must be refused before any work."""
    loop, fifo, out = work / "loop", work / "fifo", work / "o38"
    if not loop.is_symlink():
        loop.symlink_to(loop)
    if not fifo.exists():
        os.mkfifo(fifo)
    out.mkdir(exist_ok=True)
    samples = out / "sweep.csv"
    samples.write_text("output_shaft.length_mm\n100\n150\n")
    foreign = work / "README.md"
    foreign.write_text("# a tracked file\n")
    vary = ["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--out", str(work / "sw38")]
    return [
        ("sweep --out holds its --samples", ["sweep", "shaft-torsion", "--samples", str(samples), "--out", str(out)], samples),
        ("solve --vtu onto a foreign file", ["solve", "shaft-torsion", "--vtu", str(foreign)], foreign),
        ("diagnose --json x --plot x", ["diagnose", str(rec), "--json", str(work / "x"), "--plot", str(work / "x")], None),
        ("solve --json t.boundary.vtu beside --vtu t.vtu", ["solve", "shaft-torsion", "--vtu", str(work / "t.vtu"),
                                                            "--json", str(work / "t.boundary.vtu")], None),
        ("--json through a symlink loop", ["analytic", "--json", str(loop)], None),
        ("--out through a symlink loop", ["benchmark-diagnose", "--n", "1", "--out", str(loop / "o")], None),
        ("--json 300-character name", ["analytic", "--json", str(work / ("n" * 300 + ".json"))], None),
        ("--json path over 4096", ["analytic", "--json", str(work) + ("/" + "d" * 200) * 22 + "/a.json"], None),
        ("--params a FIFO", ["analytic", "--params", str(fifo)], None),
        ("recording a FIFO", ["diagnose", str(fifo)], None),
        ("--samples a FIFO", ["sweep", "shaft-torsion", "--samples", str(fifo), "--out", str(work / "sw4")], None),
        ("--workers 10000", [*vary, "--workers", "10000"], None),
        ("--scheduler tls, nothing listening", [*vary, "--scheduler", "tls://127.0.0.1:9"], None),
        ("--scheduler unix://", [*vary, "--scheduler", "unix:///tmp/strainwave-no"], None),
        ("benchmark-diagnose --seed -1", ["benchmark-diagnose", "--seed", "-1"], None),
        ("benchmark-diagnose --n 1e9", ["benchmark-diagnose", "--n", "1000000000"], None),
        ("ring --mesh-size-mm 10", ["solve", "ring-compression", "--mesh-size-mm", "10"], None),
        ("--mesh-size-mm 5e-324", ["solve", "shaft-torsion", "--mesh-size-mm", "5e-324"], None),
        ("--mesh abbreviation", ["solve", "shaft-torsion", "--mesh", "3"], None),
    ]


def resource_table(work: Path) -> list[tuple[str, list[str]]]:
    big = work / "big.toml"
    big.write_text("[output_shaft]\nlength_mm = 10000.0\nouter_diameter_mm = 10000.0\ninner_diameter_mm = 9990.0\n")
    teeth = work / "teeth.toml"
    teeth.write_text("[ewg_drive]\nflexspline_teeth = 10000\n")
    return [
        ("mesh budget: --mesh-size-mm 1e-6", ["solve", "shaft-torsion", "--mesh-size-mm", "1e-6"]),
        ("mesh budget: 10 m thin shaft", ["solve", "shaft-torsion", "--params", str(big)]),
        ("mesh budget: validate on a 10 m thin shaft", ["validate", "--quick", "--params", str(big),
                                                          "--out", str(work / "vbig")]),
        ("mesh budget: ring h = 1 um", ["solve", "ring-compression", "--mesh-size-mm", "0.001"]),
        ("CAD bound: 10,000 teeth", ["export-step", "--part", "ewg-flexspline-ring", "--params", str(teeth),
                                     "-o", str(work / "t.step")]),
        ("grid size: 1e8 points", ["sweep", "shaft-torsion", "--vary", "output_shaft.crack_depth_mm=1:5:100000000",
                                   "--out", str(work / "g1")]),
        ("grid size: 1000 x 1000", ["sweep", "shaft-torsion", "--vary", "output_shaft.crack_depth_mm=1:5:1000",
                                    "--vary", "output_shaft.length_mm=100:200:1000", "--out", str(work / "g2")]),
        ("input size: --params /dev/zero", ["analytic", "--params", "/dev/zero"]),
        ("input size: --params /dev/urandom", ["analytic", "--params", "/dev/urandom"]),
        ("input size: diagnose /dev/zero", ["diagnose", "/dev/zero"]),
        ("input size: --samples /dev/zero", ["sweep", "shaft-torsion", "--samples", "/dev/zero", "--out", str(work / "g3")]),
        *issue38_resources(work),
    ]


def issue38_resources(work: Path) -> list[tuple[str, list[str]]]:
    """Issue 38 (items 1-3, 14): parameters that meshed for minutes (pointed teeth, a metre-long contact patch,
    a micrometre wall on diagnose's FEA path) and undrawable teeth, refused by the budget and the tooth check."""
    files = {"pointed": "[ewg_drive]\npressure_angle_deg = 40.0\ndedendum_coefficient = 0.1\n",
             "patch": "[wave_generator]\ncontact_semi_axes_mm = [1e3, 3.0]\n",
             "two_teeth": "[ewg_drive]\nflexspline_teeth = 2\ntooth_difference = 1\n",
             "cup_teeth": "[flexspline_cup]\nteeth = 400\nmodule_mm = 0.01\n"}
    for name, body in files.items():
        (work / f"{name}.toml").write_text(body)
    rec = work / "thin_wall.csv"
    lines = _good_recording(random.Random(2)).splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    lines[first:first] = ["# [params.output_shaft]", "# inner_diameter_mm = 69.9979", "# crack_depth_mm = 0.001",
                          "# [params.crack_geometry]", "# slot_width_mm = 0.0001"]
    rec.write_text("\n".join(lines) + "\n")
    return [("pointed EWG teeth (meshed 270 s)", ["solve", "ring-compression", "--params", str(work / "pointed.toml")]),
            ("bearing contact patch 1 m long", ["solve", "bearing-ring", "--params", str(work / "patch.toml"),
                                                "--mesh-size-mm", "20"]),
            ("diagnose --baseline fea, 1 um wall", ["diagnose", str(rec), "--baseline", "fea"]),
            ("analytic with 2 EWG teeth", ["analytic", "--params", str(work / "two_teeth.toml")]),
            ("analytic with pointed cup teeth", ["analytic", "--params", str(work / "cup_teeth.toml")])]


def refusals(category: str, table) -> Row:
    row = Row(category)
    for entry in table:
        what, argv, kept = (entry + (None,))[:3]
        before = kept.read_bytes() if kept is not None else None
        run = cli(argv)
        if kept is not None and kept.read_bytes() != before:
            row.add("lost", f"{what}: {kept} was changed")
            continue
        outcome, note = classify_cli(run)
        if outcome == "accepted":
            outcome, note = "internal", "accepted, but must be refused"
        row.add(outcome, f"{what}: {note}")
    return row


# ---- interruption ---------------------------------------------------------------------------------

def _pgid_members(pgid: int) -> list[int]:
    members = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            fields = stat.rsplit(")", 1)[1].split()
            if int(fields[2]) == pgid and fields[0] != "Z":
                members.append(int(entry.name))
    return members


def _stat_fields(pid: int) -> list[str] | None:
    """/proc/PID/stat after the command name (field 3 onwards), or None when the process is gone."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None


def _start_time(pid: int) -> str | None:
    fields = _stat_fields(pid)
    return None if fields is None else fields[19]   # field 22: start time in clock ticks after boot


def _running(pid: int, start_time: str | None) -> bool:
    fields = _stat_fields(pid)
    return fields is not None and fields[0] != "Z" and fields[19] == start_time


def _leftovers(out: Path, temps: bool = True) -> list[str]:
    """Half files: a results.json that is not valid JSON, and (``temps``) temporary names left behind. A writer
    killed with -9 cannot remove its temporary file (the target is untouched): after SIGKILL the next run
    must remove them (the resume check), after SIGINT none may be left at all."""
    bad = [str(p) for p in out.rglob("*.tmp")] if out.exists() and temps else []
    results = out / "results.json"
    if results.exists():
        try:
            strict_json(results.read_text())
        except ValueError:
            bad.append(f"{results} is not valid JSON")
    return bad


def interrupt(argv: list[str], out: Path, after_s: float, sig: int, group: bool) -> tuple[str, str]:
    """Start ``strainwave argv`` in its own session, send ``sig`` after ``after_s`` (to the whole process
    group, or to the main process only), and judge: exit within 15 s, one line and no traceback, no
    process of the group left after 5 s, no half file."""
    proc = subprocess.Popen([str(BIN), *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                            start_new_session=True)
    time.sleep(after_s)
    if proc.poll() is not None:
        _, err = proc.communicate()
        return "accepted", f"finished (exit {proc.returncode}) before the signal at {after_s} s: {err[-3000:]}"
    from strainwave.compare.validate.isolated import descendants

    # every process of the run, whatever group it may have moved to, by (pid, start time): a pid reused by
    # someone else's process afterwards is not ours
    started = {pid: _start_time(pid) for pid in descendants(proc.pid)}
    sent = time.perf_counter()
    (os.killpg if group else os.kill)(proc.pid, sig)
    try:
        _, err = proc.communicate(timeout=15)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return "hangs", f"{argv[0]} still running 15 s after signal {sig}"
    took = time.perf_counter() - sent
    def alive() -> list[int]:
        return sorted(set(_pgid_members(proc.pid)) | {p for p, t in started.items() if _running(p, t)})

    deadline = time.perf_counter() + 5.0
    while alive() and time.perf_counter() < deadline:
        time.sleep(0.2)
    orphans = alive()
    if orphans:
        for pid in orphans:
            os.kill(pid, signal.SIGKILL)
        return "internal", f"{len(orphans)} orphan process(es) after signal {sig} to {argv[0]}"
    left = _leftovers(out, temps=sig != signal.SIGKILL)
    if left:
        return "lost", "; ".join(left[:3])
    if "Traceback" in err:
        return "internal", f"traceback after signal {sig}: {err[-300:]}"
    if sig == signal.SIGINT:
        lines = [ln for ln in err.splitlines() if ln.strip()]
        if proc.returncode != 130 or not lines or lines[-1] != "error: interrupted":
            return "internal", f"exit {proc.returncode}, last line {lines[-1:] if lines else ''}"
    return "refused", f"stopped in {took:.1f} s"


def interruption(work: Path, moments_s: tuple[float, ...], sweep: bool, resume: bool) -> Row:
    """SIGINT and SIGKILL (process group and main process alone) to validate --quick at each moment, and to
    a sweep; with ``resume``, a full rerun after the interruptions must reuse what was finished."""
    row = Row("interruption (SIGINT / SIGKILL, validate and sweep)")
    out = work / "validate"
    for after in moments_s:
        for sig, group in ((signal.SIGINT, False), (signal.SIGKILL, True), (signal.SIGKILL, False)):
            outcome, note = interrupt(["validate", "--quick", "--out", str(out)], out, after, sig, group)
            row.add(outcome, f"validate, {after} s, signal {sig}, {'group' if group else 'main'}: {note}")
    if sweep:
        sw = work / "sweep"
        for sig, group in ((signal.SIGINT, False), (signal.SIGKILL, True)):
            outcome, note = interrupt(["sweep", "shaft-torsion", "--quick", "--vary",
                                       "output_shaft.inner_diameter_mm=40,42,44,46", "--workers", "2",
                                       "--out", str(sw)], sw, 12.0, sig, group)
            row.add(outcome, f"sweep, signal {sig}: {note}")
    if resume:
        # after the interruptions: a complete run, then a rerun that must reuse every FEA case it finished
        first = cli(["validate", "--quick", "--out", str(out)], timeout_s=1200)
        again = cli(["validate", "--quick", "--out", str(out)], timeout_s=1200)
        counts = re.search(r"(\d+) FEA cases \((\d+) reused from cache\)", again.stdout)
        ok = (first.status in (0, 1) and again.status == first.status and counts is not None
              and counts.group(1) == counts.group(2) and not _leftovers(out) and "Traceback" not in first.stderr)
        row.add("accepted" if ok else "internal",
                f"resume: exit {first.status} then {again.status}, {counts.group(0) if counts else 'no case count'}")
    return row


# ---- determinism and side effects ---------------------------------------------------------------------

def _difference(a, b, rel: float = 1e-12, path: str = "") -> str | None:
    """Where ``a`` and ``b`` (parsed JSON) first differ beyond ``rel`` (per-key tolerances in _AMPLIFIED,
    keys in _VOLATILE skipped), or None when they agree."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return f"{path}: keys {sorted(set(a) ^ set(b))}"
        return next((d for k in a if k not in _VOLATILE
                     for d in [_difference(a[k], b[k], _AMPLIFIED.get(k, rel), f"{path}/{k}")] if d), None)
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{path}: lengths {len(a)} vs {len(b)}"
        return next((d for i, (x, y) in enumerate(zip(a, b)) for d in [_difference(x, y, rel, f"{path}[{i}]")] if d),
                    None)
    if isinstance(a, float) and isinstance(b, float):
        return None if a == b or abs(a - b) <= rel * max(abs(a), abs(b)) else f"{path}: {a!r} vs {b!r}"
    return None if a == b else f"{path}: {a!r} vs {b!r}"


def _close(a, b, rel: float = 1e-12) -> bool:
    return _difference(a, b, rel) is None


_VOLATILE = {"timings_s", "seconds", "fields", "total_s", "created_utc", "recording", "time_s",   # wall times, paths
             "residual"}   # CG's final residual norm: moves by ~2 % between runs while the solution agrees to 3e-14
# Numbers that amplify the round-off of the FEA values (two solves of the shaft differ by 3e-14: the order of
# BLAS sums follows memory alignment): the GCI and its band are differences of refinements ~1e-5 apart, so
# they move by ~1e-10.
_AMPLIFIED = {"gci_fine": 1e-6, "uncertainty": 1e-6}


def determinism(work: Path, solve: bool) -> Row:
    row = Row("determinism (two runs equal to 1e-12)")
    rec = work / "det.csv"
    rec.write_text(_good_recording(random.Random(1)))
    commands = [["analytic"], ["diagnose", str(rec)]] + ([["solve", "shaft-torsion", "--mesh-size-mm", "12"]] if solve else [])
    for argv in commands:
        outs = []
        for k in range(2):
            target = work / f"det_{argv[0]}_{k}.json"
            run = cli([*argv, "--json", str(target)], timeout_s=600)
            outs.append(strict_json(target.read_text()) if run.status == 0 else None)
        where = "a run failed" if None in outs else _difference(outs[0], outs[1])
        row.add("internal" if where else "accepted", f"{argv[0]}: {where}")
    return row


_TOOLCHAIN = ("ldconfig", "gcc", "cc", "ld", "objdump")


def _writes_outside(trace: Path, allowed: list[Path]) -> list[str]:
    """Paths opened for writing, created, renamed or removed outside ``allowed`` (strace -f output)."""
    allowed_text = [str(p) for p in allowed] + ["/dev/null", "/dev/shm", "/proc/", "/dev/pts", "/dev/tty"]
    stray = set()
    for line in trace.read_text(errors="replace").splitlines():
        if "= -1" in line:
            continue
        if "execve(" in line and any(f'/{tool}"' in line for tool in _TOOLCHAIN):
            # ctypes.util.find_library runs these (and gcc writes temporary files) to find a library
            stray.add("exec " + line.split('"')[1])
            continue
        write = ("openat(" in line and any(f in line for f in ("O_WRONLY", "O_RDWR", "O_CREAT"))) or \
            any(f"{call}(" in line for call in ("mkdir", "rename", "unlink", "rmdir", "creat"))
        if not write or '"' not in line:
            continue
        for path in line.split('"')[1::2]:
            if path.startswith("/") and not any(path.startswith(a) for a in allowed_text):
                stray.add(path)
    return sorted(stray)


# gmsh links FLTK, whose Fl_Preferences rewrites its prefs file (and creates ~/.fltk) at every gmsh.initialize,
# even without a GUI (fltk/fltk issue 37: reading an option writes the file); no gmsh option stops it. Listed,
# counted apart, and reported: fea/session.py would have to run gmsh with another HOME to avoid it.
DOCUMENTED_CACHES = ("ezdxf", "matplotlib")
KNOWN_STRAY = ("/.fltk", "/.fltk/fltk.org", "/fltk.org/fltk.prefs")


def _transient_temp(path: Path, tmp: Path) -> bool:
    if not path.is_relative_to(tmp) or path.exists():
        return False
    first = path.relative_to(tmp).parts[0]
    return first.startswith("pymp-") or (len(first) == 8 and first.replace("_", "").isalnum())


def side_effects(work: Path, solve: bool) -> Row:
    """Commands with HOME an empty folder, TMPDIR an empty folder and a working directory they may not
    write in; strace records every write. Outputs go under ``out``."""
    row = Row("writes outside the outputs (strace, HOME empty)")
    if shutil.which("strace") is None:
        row.notes.append("strace not installed: not tried")
        return row
    # a short root: the commands' scratch (and multiprocessing's sockets in it) stays under the outputs only
    # when its path fits an AF_UNIX address; deep folders legitimately fall back to the system temp
    short = Path(tempfile.mkdtemp(prefix="sw-se-"))
    try:
        _side_effects(row, work, short, solve)
    finally:
        for d in short.rglob("cwd"):
            d.chmod(0o755)
        shutil.rmtree(short, ignore_errors=True)
    return row


def _side_effects(row: Row, work: Path, short: Path, solve: bool) -> None:
    rec = work / "side.csv"
    rec.write_text(_good_recording(random.Random(2)))
    commands = [["analytic", "--json", "{out}/a.json"], ["diagnose", str(rec), "--json", "{out}/d.json"],
                ["export-step", "--part", "output-shaft", "-o", "{out}/s.step", "--png", "{out}/s.png"]]
    if solve:
        commands.append(["solve", "shaft-torsion", "--mesh-size-mm", "16", "--json", "{out}/s.json"])
    for i, argv in enumerate(commands):
        home, tmp, out, cwd = (short / f"se{i}" / name for name in ("home", "tmp", "out", "cwd"))
        for d in (home, tmp, out, cwd):
            d.mkdir(parents=True, exist_ok=True)
        cwd.chmod(0o555)
        trace = work / f"se{i}.trace"
        env = {**ENV, "HOME": str(home), "TMPDIR": str(tmp), "XDG_CACHE_HOME": str(home / ".cache")}
        args = [a.replace("{out}", str(out)) for a in argv]
        start = time.perf_counter()
        try:
            done = subprocess.run(["strace", "-f", "-qq", "-e", "trace=openat,creat,mkdir,rename,unlink,rmdir,execve",
                                   "-o", str(trace), str(BIN), *args], capture_output=True, text=True, env=env,
                                  cwd=cwd, timeout=600)
        except subprocess.TimeoutExpired:
            row.add("hangs", f"{argv[0]} over 600 s")
            continue
        # ezdxf (imported by build123d) and matplotlib keep their font lists in the XDG cache directory and
        # matplotlib creates its XDG config folder: the documented per-user places of both libraries; anything
        # else under HOME or TMPDIR counts as a stray write
        roots = [home / ".cache", home / ".config"]
        caches = [root / name for root in roots for name in DOCUMENTED_CACHES]
        stray = [p for p in _writes_outside(trace, [out, *caches]) if p not in map(str, roots)] + \
            [str(p) for p in (*home.rglob("*"), *tmp.rglob("*"))
             if p not in roots and not any(p == c or p.is_relative_to(c) for c in caches)]
        # multiprocessing's own socket folder (pymp-*, removed by it at exit) and tempfile's probe of TMPDIR
        # (an 8-character name, removed at once): transient use of the temporary directory, not scratch
        stray = [p for p in stray if not _transient_temp(Path(p), tmp)]
        known = [p for p in stray if any(p.endswith(k) for k in KNOWN_STRAY)]
        stray = [p for p in stray if p not in known]
        if known:
            row.notes.append(f"{argv[0]}: known, not fixed here (gmsh's FLTK): {', '.join(sorted(set(known)))}")
        if done.returncode != 0:
            row.add("internal", f"{argv[0]}: exit {done.returncode}: {done.stderr[-200:]}")
        elif stray:
            row.add("stray", f"{argv[0]} ({time.perf_counter() - start:.0f} s): " + ", ".join(stray[:6]))
        else:
            row.add("accepted")


# ---- table ----------------------------------------------------------------------------------------

def table(rows: list[Row]) -> str:
    head = f"| {'category':<52} | tried | accepted | clean refusals | internal errors | hangs | files lost | stray writes |"
    lines = [head, "|" + "|".join("-" * (len(c)) for c in head.split("|")[1:-1]) + "|"]
    for r in rows:
        lines.append(f"| {r.category:<52} | {r.tried:5d} | {r.accepted:8d} | {r.refused:14d} | {r.internal:15d} | "
                     f"{r.hangs:5d} | {r.lost:10d} | {r.stray:12d} |")
    for r in rows:
        lines += [f"  {r.category}: {n}" for n in r.notes]
    return "\n".join(lines)


CATEGORIES = ("params", "params-cli", "recordings", "paths", "resources", "interruption", "determinism",
              "side-effects")


def run(quick: bool, seed: int, work: Path, only: tuple[str, ...] = CATEGORIES) -> list[Row]:
    n_params, n_cli, n_rec = (300, 40, 400) if quick else (3000, 400, 5000)
    files = param_files(n_params, seed, work) if {"params", "params-cli"} & set(only) else []
    steps = {
        "params": lambda: params_in_process(files),
        "params-cli": lambda: params_cli(files[:n_cli], work),
        "recordings": lambda: recordings(n_rec, seed, diagnose_every=50 if quick else 20),
        "paths": lambda: refusals("flags and paths (exit 2, one line, before any work)", path_table(work)),
        "resources": lambda: refusals("resource bounds (mesh, CAD, grid, input size)", resource_table(work)),
        "interruption": lambda: interruption(work, (3.0, 10.0) if quick else (3.0, 10.0, 40.0), sweep=not quick,
                                             resume=not quick),
        "determinism": lambda: determinism(work, solve=not quick),
        "side-effects": lambda: side_effects(work, solve=not quick),
    }
    return [steps[name]() for name in CATEGORIES if name in only]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="reduced counts (what the test runs)")
    parser.add_argument("--seed", type=int, default=0, help="seed of every generated file")
    parser.add_argument("--only", default=",".join(CATEGORIES),
                        help=f"comma-separated categories to run (default: all of {', '.join(CATEGORIES)})")
    args = parser.parse_args(argv)
    only = tuple(c.strip() for c in args.only.split(","))
    unknown = set(only) - set(CATEGORIES)
    if unknown:
        parser.error(f"--only: unknown categories {sorted(unknown)}; choose from {', '.join(CATEGORIES)}")
    with tempfile.TemporaryDirectory(prefix="fuzz-reliability-") as tmp:
        work = Path(tmp)
        try:
            rows = run(args.quick, args.seed, work, only)
        finally:
            for d in work.rglob("cwd"):
                d.chmod(0o755)   # so the temporary folder can be removed
    print(table(rows))
    return 0 if all(r.clean for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
