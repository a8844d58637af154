"""Issue 38's guards: the input guard (regular files, bounded reads and sniffing, escaped messages), the output
guard (one check of all outputs, strainwave's own files recognised, written together), the meshing guard (a
limited child that dies with its parent), SIGTERM unwinding, the secured local cluster, and the one tooth-shape
check every command shares. Each is fuzzed (hypothesis) where inputs vary; all run in seconds."""
import errno
import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from strainwave.cli import main
from strainwave.compare.diagnose.recording import RecordingKind, format_recording
from strainwave.errors import InputError
from strainwave.output_guard import MANIFEST, OWNER, Planned, check_outputs, make_owned_dir, remove_stale

_LOAD = np.linspace(0.0, 1000.0, 40)
_GOOD = format_recording(RecordingKind.TORSION, "output_shaft", _LOAD, _LOAD / 4.0e8 + 1e-10 * np.sin(np.arange(40)))
_FUZZ = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _one_line_refusal(capsys, status) -> str:
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and err.startswith("error: "), err
    assert "internal error" not in err and "\x1b" not in err, err
    return err


# ---- input guard ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("argv", [["analytic", "--params", "{f}"], ["diagnose", "{f}"],
                                  ["sweep", "shaft-torsion", "--samples", "{f}", "--out", "{d}/o"]])
def test_a_fifo_without_writer_is_refused_at_once(tmp_path, capsys, argv):
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    start = time.perf_counter()
    status = main([a.format(f=fifo, d=tmp_path) for a in argv])
    assert time.perf_counter() - start < 10
    assert "not a regular file" in _one_line_refusal(capsys, status)


def test_quadratic_sniffing_is_bounded(tmp_path, capsys):
    """A data line of ',"a' repeated took 26 s at 100 KB in csv.Sniffer; the sniff sees a bounded prefix."""
    rec = tmp_path / "r.csv"
    lines = _GOOD.splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#")) + 1
    rec.write_text("\n".join(lines[:first] + [',"a' * 35_000] + lines[first:]) + "\n")
    start = time.perf_counter()
    status = main(["diagnose", str(rec)])
    assert time.perf_counter() - start < 5
    _one_line_refusal(capsys, status)


def test_cells_beyond_the_csv_field_limit_are_input_errors(tmp_path, capsys):
    rec = tmp_path / "r.csv"
    lines = _GOOD.splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    lines[first] = '"' + "t" * 140_000 + '",twist_rad'
    rec.write_text("\n".join(lines) + "\n")
    _one_line_refusal(capsys, main(["diagnose", str(rec)]))
    samples = tmp_path / "s.csv"
    samples.write_text('output_shaft.length_mm\n"' + "1" * 140_000 + '"\n')
    _one_line_refusal(capsys, main(["sweep", "shaft-torsion", "--samples", str(samples), "--out", str(tmp_path / "o")]))


def test_deep_toml_nesting_is_refused(tmp_path, capsys):
    params = tmp_path / "p.toml"
    params.write_text("[material." + ".".join(["x"] * 5000) + "]\n")
    _one_line_refusal(capsys, main(["analytic", "--params", str(params)]))


@_FUZZ
@given(key=st.text(st.characters(codec="utf-8", exclude_characters='"\\'), min_size=1, max_size=12))
def test_every_message_is_one_printable_line(tmp_path_factory, capsys, key):
    """A TOML key of terminal control codes ("\\u001b[2J\\u000bX" cleared the screen) is echoed escaped."""
    params = tmp_path_factory.mktemp("k") / "p.toml"
    escaped = "".join(c if c.isprintable() else f"\\u{ord(c):04x}" for c in key)
    params.write_text(f'[material]\n"{escaped}" = 1\n', encoding="utf-8")
    err = _one_line_refusal(capsys, main(["analytic", "--params", str(params)]))
    assert err[:-1].isprintable()


@pytest.mark.parametrize("cell", ["1_00", "\u0661\u0660\u0660", "\uff11\uff10\uff10"])
def test_sweep_numbers_are_ascii_without_underscores(tmp_path, capsys, cell):
    samples = tmp_path / "s.csv"
    samples.write_text(f"output_shaft.length_mm\n{cell}\n", encoding="utf-8")
    _one_line_refusal(capsys, main(["sweep", "shaft-torsion", "--samples", str(samples), "--out", str(tmp_path / "o")]))


# ---- output guard ---------------------------------------------------------------------------------------

def test_outputs_on_one_path_or_on_an_input_are_refused(tmp_path, capsys):
    rec = tmp_path / "r.csv"
    rec.write_text(_GOOD)
    out = tmp_path / "o"
    out.mkdir()
    samples = out / "sweep.csv"
    samples.write_text("output_shaft.length_mm\n100\n150\n")
    cases = [["diagnose", str(rec), "--json", str(tmp_path / "x"), "--plot", str(tmp_path / "x")],
             ["solve", "shaft-torsion", "--vtu", str(tmp_path / "s.vtu"), "--json", str(tmp_path / "s.vtu")],
             ["solve", "shaft-torsion", "--vtu", str(tmp_path / "t.vtu"), "--json", str(tmp_path / "t.boundary.vtu")],
             ["export-step", "--part", "output-shaft", "-o", str(tmp_path / "s.step"), "--png", str(tmp_path / "s.step")],
             ["sweep", "shaft-torsion", "--samples", str(samples), "--quick", "--out", str(out)]]
    for argv in cases:
        _one_line_refusal(capsys, main(argv))
    assert samples.read_text() == "output_shaft.length_mm\n100\n150\n"
    with pytest.raises(InputError, match="also the output of"):
        check_outputs([Planned("--json", str(tmp_path / "a.json")), Planned("--json", str(tmp_path / "b" / ".." / "a.json"))],
                      {}, force=False)


def test_a_foreign_file_is_kept_unless_forced_and_strainwave_files_are_replaced(tmp_path, capsys):
    target = tmp_path / "README.json"
    target.write_text("the user's own notes\n")
    _one_line_refusal(capsys, main(["params", "--json", str(target)]))
    assert target.read_text() == "the user's own notes\n"
    assert main(["params", "--json", str(target), "--force"]) == 0
    assert json.loads(target.read_text())["material"]
    assert main(["params", "--json", str(target)]) == 0, "strainwave's own file, unchanged since, is replaced"
    capsys.readouterr()
    target.write_text(target.read_text() + " ")   # edited by the user: theirs again
    _one_line_refusal(capsys, main(["params", "--json", str(target)]))
    folder = tmp_path / "notes"
    folder.mkdir()
    (folder / "mine.txt").write_text("x")
    _one_line_refusal(capsys, main(["benchmark-diagnose", "--n", "1", "--out", str(folder)]))


def _adversarial_paths(tmp_path):
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    return [("--json", str(loop)), ("--json", str(loop / "a.json")), ("--out", str(loop)),
            ("--json", str(tmp_path / ("n" * 300 + ".json"))), ("--json", str(tmp_path) + ("/" + "d" * 200) * 25 + "/a.json"),
            ("--json", str(tmp_path / "a.txt")), ("--json", str(tmp_path / "nul\x00.json"))]


def test_adversarial_output_paths_exit_2_in_one_line(tmp_path, capsys):
    for flag, path in _adversarial_paths(tmp_path):
        argv = ["benchmark-diagnose", "--n", "1", "--out", path] if flag == "--out" else ["params", "--json", path]
        _one_line_refusal(capsys, main(argv))
    assert not list(tmp_path.glob("*.json"))


@_FUZZ
@given(parts=st.lists(st.sampled_from(["a", "..", ".", "loop", "f.json", "x" * 260, "\x1b[2J", "d/"]), min_size=1,
                      max_size=4), suffix=st.sampled_from([".json", ".JSON", ".png", ""]))
def test_fuzzed_output_paths_are_written_or_refused_in_one_line(tmp_path_factory, capsys, parts, suffix):
    root = tmp_path_factory.mktemp("p")
    (root / "loop").symlink_to(root / "loop")
    path = str(root.joinpath(*parts)) + suffix
    status = main(["params", "--json", path])
    err = capsys.readouterr().err
    assert (status == 0 and err.count("\n") <= 1) or (status == 2 and err.count("\n") == 1), (path, err)
    assert "internal error" not in err and "\x1b" not in err
    assert not [p for p in root.rglob("*") if ".strainwave-stage-" in p.name or p.name.endswith(".tmp")]


def test_a_failed_command_leaves_none_of_its_outputs(tmp_path, capsys, monkeypatch):
    """diagnose wrote the PNG, then failed on the JSON (disk full): now neither appears, exit 1 naming the path."""
    from strainwave import io_atomic
    rec = tmp_path / "r.csv"
    rec.write_text(_GOOD)
    real = io_atomic.atomic_write_text

    def full(target, text):
        if str(target).endswith(".json"):
            raise OSError(errno.ENOSPC, "No space left on device", str(target))
        return real(target, text)

    monkeypatch.setattr(io_atomic, "atomic_write_text", full)
    status = main(["diagnose", str(rec), "--json", str(tmp_path / "d.json"), "--plot", str(tmp_path / "d.png")])
    err = capsys.readouterr().err
    assert status == 1 and err.startswith("error: disk full: ") and err.count("\n") == 1, err
    assert err == f"error: disk full: {tmp_path / 'd.json'}\n", "the target, not its staging folder (issue 53)"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv"]


def test_a_full_disk_under_a_temporary_name_names_the_target():
    from strainwave.output_guard import target_of
    assert target_of("/x/out/.results.json.0123456789ab.json.tmp") == "/x/out/results.json"
    assert target_of("/x/out/report.md") == "/x/out/report.md"


def test_stale_scratch_of_killed_runs_is_removed(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    pid = int(dead.stdout)
    stale = [tmp_path / f".strainwave-scratch-{pid}-abc", tmp_path / f".strainwave-stage-{pid}-abc"]
    for folder in stale:
        folder.mkdir()
        (folder / "half.vtu").write_text("x")
        (folder / OWNER).write_text(json.dumps({"written_by": "strainwave", "pid": pid, "start": None}))
    mine = make_owned_dir(f".strainwave-scratch-{os.getpid()}-", tmp_path)
    named_alike = tmp_path / f".strainwave-scratch-{pid}-user"   # the same name pattern, but no owner record
    named_alike.mkdir()
    assert remove_stale(tmp_path) == 2
    assert not any(p.exists() for p in stale) and mine.exists() and named_alike.exists()


# ---- options ---------------------------------------------------------------------------------------------

def test_options_are_not_abbreviated_and_take_no_positional(tmp_path, capsys):
    _one_line_refusal(capsys, main(["solve", "shaft-torsion", "--mesh", "3"]))
    # --json does not swallow the study name: the study is parsed and its budget refuses the size
    err = _one_line_refusal(capsys, main(["solve", "--json", "shaft-torsion", "--mesh-size-mm", "1e-300"]))
    assert "shaft-torsion would need" in err


def test_each_warning_prints_once_per_run(capsys):
    assert main(["analytic"]) == 0
    err = capsys.readouterr().err
    assert err.count("warning: material:") == 1, err


@pytest.mark.parametrize("argv,key", [
    (["benchmark-diagnose", "--seed", "-1"], "--seed"), (["benchmark-diagnose", "--n", "1000000000"], "--n"),
    (["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--workers", "10000"], "--workers"),
    (["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--scheduler", "unix:///tmp/x"], "--scheduler"),
    (["sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,150", "--scheduler", "tls://127.0.0.1:9"], "--scheduler"),
    (["solve", "ring-compression", "--mesh-size-mm", "10"], "--mesh-size-mm"),
    (["solve", "ring-compression", "--mesh-size-mm", "5e-324"], "--mesh-size-mm")])
def test_former_internal_errors_are_refusals(tmp_path, capsys, argv, key):
    if argv[0] == "sweep":
        argv = [*argv, "--out", str(tmp_path / "o")]
    assert f"error: {key} = " in _one_line_refusal(capsys, main(argv))


# ---- physics: one geometric check, one budget --------------------------------------------------------

@pytest.mark.parametrize("body,key", [
    ("[ewg_drive]\nflexspline_teeth=2\ntooth_difference=1\n", "ewg_drive.flexspline_teeth"),
    ("[ewg_drive]\npressure_angle_deg=40.0\ndedendum_coefficient=0.1\n", "ewg_drive.flexspline_teeth"),
    ("[flexspline_cup]\nteeth=400\nmodule_mm=0.01\n", "flexspline_cup.module_mm")])
def test_every_command_refuses_an_undrawable_tooth_alike(tmp_path, capsys, body, key):
    params = tmp_path / "p.toml"
    params.write_text(body)
    lines = set()
    for argv in (["analytic"], ["solve", "ring-compression"], ["export-step", "--part", "ewg", "-o", str(tmp_path / "e.step")]):
        lines.add(_one_line_refusal(capsys, main([*argv, "--params", str(params)])))
    assert len(lines) == 1 and f"error: {key} = " in lines.pop()


def test_the_check_fails_on_a_perturbed_drawable_tooth():
    """The default teeth pass; the same teeth with the tip thinned below 0.2 m by the pressure angle fail."""
    from strainwave.geometry.involute import check_teeth, ewg_tooth_spec, tip_thickness_mm
    from strainwave.params import load_params
    import dataclasses
    spec = ewg_tooth_spec(load_params())
    check_teeth(spec, "k", 1, "ring")
    steep = dataclasses.replace(spec, pressure_angle_deg=40.0)
    assert tip_thickness_mm(steep) < 0.2 * spec.module_mm
    with pytest.raises(InputError, match="pointed"):
        check_teeth(steep, "k", 1, "ring")


def test_the_bearing_budget_counts_the_contact_patch():
    from strainwave.fea.budget import MAX_ELEMENTS, estimate
    from strainwave.params import load_params
    base = load_params()
    # an impossible drive (the guard refuses it: the ring would be 4 m wide), built past the guard: the budget alone
    long_patch = base.with_value("wave_generator.contact_semi_axes_mm", [1e3, 3.0])
    assert estimate("bearing-ring", base, None).elements < MAX_ELEMENTS
    assert estimate("bearing-ring", long_patch, 20.0).elements > MAX_ELEMENTS


def test_diagnose_fea_baseline_is_budgeted(tmp_path, capsys):
    lines = _GOOD.splitlines()
    lines.insert(next(i for i, ln in enumerate(lines) if not ln.startswith("#")), "# [params.output_shaft]\n# inner_diameter_mm = 69.9979\n# crack_depth_mm = 0.001\n"
                    "# [params.crack_geometry]\n# slot_width_mm = 0.0001")
    rec = tmp_path / "r.csv"
    rec.write_text("\n".join(lines) + "\n")
    start = time.perf_counter()
    status = main(["diagnose", str(rec), "--baseline", "fea"])
    assert time.perf_counter() - start < 10
    assert "would need that many" in _one_line_refusal(capsys, status)


# ---- meshing guard --------------------------------------------------------------------------------------

@pytest.fixture
def tiny_limits(monkeypatch):
    from strainwave.fea import budget
    monkeypatch.setattr(budget, "MESH_BASE_S", 1.0)
    monkeypatch.setattr(budget, "MESH_S_PER_ELEMENT", 0.0)
    monkeypatch.setattr(budget, "MESH_BASE_BYTES", 256 << 20)
    monkeypatch.setattr(budget, "MESH_BYTES_PER_ELEMENT", 0)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    with open(f"/proc/{pid}/stat") as stream:
        return stream.read().split(")")[-1].split()[0] != "Z"


def test_a_hanging_mesher_is_stopped_at_its_wall_time(tmp_path, tiny_limits):
    from strainwave.fea.meshing import MeshLimitExceeded
    from strainwave.fea.session import mesh_in_child
    marker = tmp_path / "pid"

    def hang(model):
        marker.write_text(str(os.getpid()))
        time.sleep(60)

    start = time.perf_counter()
    with pytest.raises(MeshLimitExceeded, match="took longer than 1 s"):
        mesh_in_child(hang)
    assert time.perf_counter() - start < 15   # 1 s, and a fork of a large process on a loaded machine
    assert not _alive(int(marker.read_text()))


def test_a_mesher_past_its_memory_limit_fails_with_a_reason(tiny_limits, monkeypatch):
    from strainwave.fea import budget
    from strainwave.fea.meshing import MeshingFailed
    from strainwave.fea.session import mesh_in_child
    monkeypatch.setattr(budget, "MESH_BASE_S", 60.0)   # the memory limit is tested, not the wall time
    with pytest.raises(MeshingFailed) as failure:
        mesh_in_child(lambda model: bytearray(1 << 30))
    assert "memory" in str(failure.value)


def test_a_real_gmsh_failure_is_reported_and_a_mesh_comes_back():
    from strainwave.fea.meshing import MeshingFailed
    from strainwave.fea.session import mesh_in_child

    def square(model):
        model.occ.addRectangle(0, 0, 0, 1, 1)
        model.occ.synchronize()
        model.mesh.generate(2)
        return int(model.mesh.getNodes()[0].size)

    assert mesh_in_child(square) > 4
    with pytest.raises(MeshingFailed, match=r"Exception: \w"):   # gmsh's own message comes back
        mesh_in_child(lambda model: model.mesh.getNodes(3, 12345))


_PARENT = textwrap.dedent("""
    import os, sys, time
    from strainwave.fea.session import mesh_in_child
    def build(model):
        open(sys.argv[1], "w").write(str(os.getpid()))
        time.sleep(60)
    try:
        mesh_in_child(build)
    except KeyboardInterrupt:
        sys.exit(130)
""")


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGKILL])
def test_the_mesher_dies_with_its_parent_and_on_ctrl_c(tmp_path, sig):
    marker = tmp_path / "pid"
    proc = subprocess.Popen([sys.executable, "-c", _PARENT, str(marker)])
    deadline = time.time() + 60
    while not (marker.exists() and marker.read_text()) and time.time() < deadline:
        time.sleep(0.1)
    child = int(marker.read_text())
    proc.send_signal(sig)
    proc.wait(10)
    time.sleep(0.5)
    assert not _alive(child)
    if sig == signal.SIGINT:
        assert proc.returncode == 130


# ---- SIGTERM --------------------------------------------------------------------------------------------

_SLOW_COMMAND = textwrap.dedent("""
    import sys, time
    from strainwave import cli
    def slow(args):
        print("working", flush=True)
        time.sleep(60)
    cli._cmd_params = slow
    parser = cli.build_parser
    def patched():
        p = parser()
        for action in p._subparsers._group_actions[0].choices.values():
            if action.prog.endswith(" params"):
                action.set_defaults(func=slow)
        return p
    cli.build_parser = patched
    sys.exit(cli.main(sys.argv[1:]))
""")


def test_sigterm_unwinds_like_ctrl_c(tmp_path):
    out = tmp_path / "o.json"
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_COMMAND, "params", "--json", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "working\n"
    assert any(p.name.startswith(".strainwave-") and p.is_dir() for p in tmp_path.iterdir())
    proc.terminate()
    _, err = proc.communicate(timeout=60)   # the unwinding is tested here, not its time on a loaded machine
    assert proc.returncode == 143 and err.strip().splitlines()[-1] == "error: terminated", err
    assert sorted(p.name for p in tmp_path.iterdir()) == []


# ---- the local cluster ----------------------------------------------------------------------------------

_INTRUDER = textwrap.dedent("""
    import pathlib, sys
    from distributed import Client
    client = Client(sys.argv[1], timeout="3s")
    client.submit(pathlib.Path(sys.argv[2]).write_text, "ran").result(timeout=10)
""")


def test_the_local_scheduler_refuses_a_client_without_credentials(tmp_path):
    from strainwave.compare.sweep.pipeline import dask_client
    with dask_client(None, 1, tmp_path / "scratch") as (client, n):
        address = client.scheduler.address
        assert address.startswith("tls://") and n == 1
        assert client.submit(sum, [1, 2]).result(timeout=60) == 3
        from tests.test_reliability_dask_http import _http_ports, _listening
        assert not [p for p in _http_ports(client) if _listening(p)], "no HTTP server without --dashboard (issue 53)"
        # Another local user is another process: a failed Client left to the garbage collector in this one
        # can deadlock distributed's shared loop runner.
        for intruder in (address, address.replace("tls://", "tcp://")):
            marker = tmp_path / "ran"
            attempt = subprocess.run([sys.executable, "-c", _INTRUDER, intruder, str(marker)],
                                     capture_output=True, text=True, timeout=120)
            assert attempt.returncode != 0 and not marker.exists(), (intruder, attempt.stderr[-500:])
