"""``strainwave sweep`` machinery on real dask.distributed LocalClusters: resume after kill, cache keys, bad input.

The resume test injects ``closed_form_probe`` (the hollow-shaft compliance, a real closed form that
costs nothing) through run_sweep's ``task`` seam, so its timing is controlled; ``test_sweep_fea.py``
runs the FEA study itself (outputs, a bad point, the --scheduler path, a cached rerun).
"""
import functools
import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time

import pandas as pd

from strainwave import cache
from strainwave.compare.sweep.pipeline import run_sweep
from strainwave.compare.sweep.task import PointSpec, closed_form_probe, point_key
from strainwave.params import default_dict, load_params

def _compliance(inner_mm, length_mm=200.0, outer_mm=70.0, mu_MPa=8.0e4):
    """lambda_so0 with the bore (Seed 000; formula audit): 32 L / (pi mu (D^4 - d^4))."""
    return 32 * length_mm / (math.pi * mu_MPa * (outer_mm ** 4 - inner_mm ** 4))


_SCRIPT = """
import functools, sys
from pathlib import Path
from strainwave import cache
from strainwave.compare.sweep.pipeline import run_sweep
from strainwave.compare.sweep.task import closed_form_probe

if __name__ == "__main__":
    cache.code_version = lambda: "pinned-for-the-resume-test"
    run_sweep("shaft-torsion", vary=["output_shaft.inner_diameter_mm=20:50:6"], workers=1,
              out_dir=Path(sys.argv[1]), task=functools.partial(closed_form_probe, delay_s=float(sys.argv[2])),
              progress=lambda msg: print(msg, file=sys.stderr, flush=True))
"""


def test_resume_after_kill_recomputes_nothing_cached(tmp_path, monkeypatch):
    # Both runs pin the code version: in the shared tree other sources change every few seconds, which
    # rightly invalidates the cache; this test is about resuming, not about invalidation.
    monkeypatch.setattr(cache, "code_version", lambda: "pinned-for-the-resume-test")
    out, script = tmp_path / "sweep", tmp_path / "sweep_script.py"
    script.write_text(textwrap.dedent(_SCRIPT))
    delay_s = 0.8   # long enough that the kill lands after the first points and well before the sixth
    proc = subprocess.Popen([sys.executable, str(script), str(out), str(delay_s)], start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env={**os.environ, "OMP_NUM_THREADS": "1"})
    cache_dir = out / "cache"
    deadline = time.monotonic() + 60
    try:
        while time.monotonic() < deadline and len(list(cache_dir.glob("*.json"))) < 2:
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)   # the sweep, its nanny and its worker: the group this test started
        proc.wait(timeout=30)
    before = {p.name: p.read_bytes() for p in cache_dir.glob("*.json")}
    assert 2 <= len(before) < 6, "the kill must land part-way"
    assert not (out / "sweep.parquet").exists()

    partial = functools.partial(closed_form_probe, delay_s=delay_s)
    outcome = run_sweep("shaft-torsion", vary=["output_shaft.inner_diameter_mm=20:50:6"], workers=2,
                        out_dir=out, task=partial)
    assert (outcome.n_points, outcome.n_ok, outcome.n_cached) == (6, 6, len(before))
    after = {p.name: p.read_bytes() for p in cache_dir.glob("*.json")}
    assert len(after) == 6
    # the points cached before the kill are untouched (same pid and timestamp inside), the rest are new
    assert all(after[name] == data for name, data in before.items())
    records = json.loads((out / "points.json").read_text())
    killed_pids = {json.loads(data)["pid"] for data in before.values()}
    assert sum(r["cached"] for r in records) == len(before)
    assert all(r["pid"] not in killed_pids for r in records if not r["cached"])
    frame = pd.read_parquet(out / "sweep.parquet")
    assert frame["output_shaft.inner_diameter_mm"].tolist() == [20.0, 26.0, 32.0, 38.0, 44.0, 50.0]
    assert frame["fea"].tolist() == [_compliance(d) for d in (20.0, 26.0, 32.0, 38.0, 44.0, 50.0)]


def test_code_version_is_part_of_the_point_key(monkeypatch):
    spec = PointSpec("shaft-torsion", (("output_shaft.crack_depth_mm", 0.2),), default_dict())
    monkeypatch.setattr(cache, "code_version", lambda: "A")
    first, same = point_key(spec, None), point_key(spec, None)
    probe = point_key(spec, closed_form_probe)
    monkeypatch.setattr(cache, "code_version", lambda: "B")
    assert first == same and first != point_key(spec, None)
    assert probe != first   # a probe record never answers for an FEA point


def test_bad_vary_exits_2_with_one_line(strainwave_cmd, tmp_path):
    for vary, fragment in (("output_shaft.bore_mm=1:2:3", "unknown key"),
                           ("output_shaft.length_mm=100:50:-1", "N after the second ':'")):
        run = subprocess.run([*strainwave_cmd, "sweep", "shaft-torsion", "--vary", vary, "--out", str(tmp_path)],
                             capture_output=True, text=True, timeout=60)
        assert run.returncode == 2
        assert run.stderr.count("\n") == 1 and fragment in run.stderr and "Traceback" not in run.stderr
        assert run.stdout == ""


def test_bad_scheduler_address_exits_2(strainwave_cmd, tmp_path):
    run = subprocess.run([*strainwave_cmd, "sweep", "shaft-torsion", "--vary", "output_shaft.length_mm=100,200",
                          "--scheduler", "nonsense://host:8786", "--out", str(tmp_path)],
                         capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("error: --scheduler = 'nonsense://host:8786': no Dask scheduler answered")


def test_impossible_grid_points_are_refused_before_any_worker(strainwave_cmd, tmp_path, monkeypatch):
    """A bore wider than the 70 mm shaft is a mistake in the grid: exit 2 naming the points, nothing run."""
    from strainwave.compare.sweep import pipeline
    from strainwave.errors import InputError

    def no_cluster(*args, **kwargs):
        raise AssertionError("a Dask cluster was started for an impossible grid")

    monkeypatch.setattr(pipeline, "dask_client", no_cluster)
    out = tmp_path / "sweep"
    try:
        run_sweep("shaft-torsion", vary=["output_shaft.inner_diameter_mm=40,75,80", "output_shaft.length_mm=100,200"],
                  out_dir=out, task=closed_form_probe)
    except InputError as exc:
        message = str(exc)
    else:
        raise AssertionError("the impossible grid was accepted")
    assert message.startswith("--vary = '4 of 6 points': impossible, nothing was run: point 2 (")
    assert "output_shaft.inner_diameter_mm=75.0, output_shaft.length_mm=100.0" in message
    assert "point 5 (output_shaft.inner_diameter_mm=80.0, output_shaft.length_mm=200.0)" in message
    assert "outer_diameter_mm" in message and "point 0" not in message and "point 1 " not in message
    assert not out.exists()

    run = subprocess.run([*strainwave_cmd, "sweep", "shaft-torsion", "--vary", "output_shaft.inner_diameter_mm=40,75",
                          "--out", str(out)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and run.stdout == "" and not out.exists()
    errors = [line for line in run.stderr.splitlines() if line.startswith("error:")]
    assert len(errors) == 1 and "point 1 (output_shaft.inner_diameter_mm=75.0)" in errors[0]


def journal_length(study, params, quick, *, journal: str):
    """closed_form_probe that appends the point's shaft length when it runs (one worker: one line at a time)."""
    with open(journal, "a") as fh:
        fh.write(f"{params.output_shaft.length_mm}\n")
    return closed_form_probe(study, params, quick)


def test_points_are_submitted_largest_first(tmp_path):
    """Longest first: the element estimate of a shaft grows with its length, so on one worker the points run
    300, 200, 100 mm whatever the grid's order; the table keeps the grid's order."""
    journal = tmp_path / "journal.txt"
    task = functools.partial(journal_length, journal=str(journal))
    outcome = run_sweep("shaft-torsion", vary=["output_shaft.length_mm=100,300,200"], workers=1,
                        out_dir=tmp_path / "sweep", task=task)
    assert (outcome.n_points, outcome.n_ok) == (3, 3)
    assert [float(x) for x in journal.read_text().split()] == [300.0, 200.0, 100.0]
    frame = pd.read_parquet(tmp_path / "sweep" / "sweep.parquet")
    assert frame["output_shaft.length_mm"].tolist() == [100.0, 300.0, 200.0]
    assert frame["fea"].tolist() == [_compliance(45.0, length) for length in (100.0, 300.0, 200.0)]


def test_own_workers_import_the_pipeline_before_any_point(tmp_path):
    from strainwave.compare.sweep.pipeline import dask_client
    from strainwave.compare.sweep.task import warm_modules

    assert warm_modules("shaft-torsion", closed_form_probe) == ()      # a probe needs none of the FEA's libraries
    base = load_params().to_dict()
    plain = PointSpec("shaft-torsion", (("output_shaft.length_mm", 80.0),), base, True)
    seam = PointSpec("shaft-torsion", (("output_shaft.crack_depth_mm", 2.0), ("crack_geometry.shaft_arc_deg", 90.0)),
                     base, True, True)
    full = PointSpec("shaft-torsion", (("output_shaft.crack_depth_mm", 2.0),), base, True, True)   # axisymmetric
    fea = warm_modules("shaft-torsion", None, [plain, full])
    assert "strainwave.fea.shaft_torsion" in fea and "gmsh" in fea and "OCP.BRepAlgoAPI" in fea
    assert "build123d" not in fea    # the uncracked shaft is a bare OCC solid
    assert "build123d" in warm_modules("shaft-torsion", None, [plain, seam])     # a part-through seam is not
    assert "build123d" in warm_modules("cup-torsion", None)
    # a light module stands for the FEA's here (build123d alone costs a worker 2.4 s)
    with dask_client(None, 1, tmp_path / "scratch", warm=("strainwave.analytic.summary",)) as (client, _):
        loaded = client.run(lambda: "strainwave.analytic.summary" in sys.modules)
    assert list(loaded.values()) == [True]


def _forked_worker_state():
    import gc
    return {"parent": os.getppid(), "sigint_ignored": signal.getsignal(signal.SIGINT) == signal.SIG_IGN,
            "omp": os.environ.get("OMP_NUM_THREADS"), "frozen": gc.get_freeze_count() > 0,
            "distributed": "distributed.worker" in sys.modules}


_FORKED_CHECK = """
import json, os, signal, sys
from pathlib import Path
from strainwave.compare.sweep import pipeline
sys.path.insert(0, {tests!r})
from test_sweep import _forked_worker_state
assert pipeline._start_fork_server(("strainwave.analytic.summary",))
with pipeline.dask_client(None, 2, Path({scratch!r}), ("strainwave.analytic.summary",), forked=True) as (client, n):
    states = list(client.run(_forked_worker_state).values())
    loaded = list(client.run(lambda: "strainwave.analytic.summary" in sys.modules).values())
print(json.dumps({{"n": n, "loaded": loaded, "states": states, "pid": os.getpid(),
                  "driver_sigint_ignored": signal.getsignal(signal.SIGINT) is signal.SIG_IGN,
                  "env_left": "STRAINWAVE_SWEEP_PRELOAD" in os.environ}}))
"""


def test_own_workers_are_forked_from_the_fork_server(tmp_path):
    """The own LocalCluster's workers are forks of the fork server (prefork.py), which imported their libraries
    once (its heap frozen, as a worker's at teardown), runs with one BLAS thread and leaves Ctrl-C to the driver.
    In its own interpreter, as a sweep runs: a fork server is one per process and keeps its first start, and
    earlier tests of this session may have started one (the full suite did: its workers kept SIGINT)."""
    code = _FORKED_CHECK.format(tests=os.path.dirname(os.path.abspath(__file__)), scratch=str(tmp_path / "scratch"))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    got = json.loads(out.stdout.strip().splitlines()[-1])
    states = got["states"]
    assert got["n"] == 2 and got["loaded"] == [True, True]
    assert all(state["parent"] != got["pid"] for state in states)    # not spawned by the driver
    assert states[0]["parent"] == states[1]["parent"]                 # ... but forked by one server
    assert all(state["sigint_ignored"] and state["omp"] == "1" and state["frozen"] and state["distributed"]
               for state in states), states
    assert not got["driver_sigint_ignored"]                           # the driver still takes Ctrl-C
    assert not got["env_left"]


def test_sweep_worker_plugin_freezes_the_heap_at_teardown():
    import gc

    from strainwave.compare.sweep.worker import SweepWorker

    sys.modules.pop("tabnanny", None)
    plugin = SweepWorker(("strainwave.no_such_module", "tabnanny"))
    assert gc.get_freeze_count() == 0
    plugin.setup()   # the missing module is left to the points that need it; the next one still loads
    assert "tabnanny" in sys.modules
    try:
        plugin.teardown()
        assert gc.get_freeze_count() > 0
    finally:
        gc.unfreeze()
