"""The fits shared with a forked copy of the process (parallel.py) give the answer one process gives."""
import dataclasses
import os

import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.effects import effects_for
from strainwave.compare.diagnose.parallel import FitTask, fit_all
from strainwave.compare.diagnose.pipeline import diagnose
from strainwave.compare.diagnose.recording import parse_text


def _same_fit(a, b):
    assert [e.label for e in a.effects] == [e.label for e in b.effects]
    assert a.bic == b.bic and a.nuisance == b.nuisance and a.at_bound == b.at_bound
    np.testing.assert_array_equal(a.theta, b.theta)
    np.testing.assert_array_equal(a.model, b.model)


@pytest.mark.heavy
def test_two_workers_give_the_diagnosis_one_gives(params):
    """A CHA gear with a friction loop: singles and pairs (dozens of fits) split between two processes."""
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=1200))
    one, _ = diagnose(rec, params, workers=1)
    two, _ = diagnose(rec, params, workers=2)
    assert one.named == two.named and set(one.named) == {"hysteresis", "nonlinear_stiffness"}
    assert (one.verdict, one.bic_after, one.margin_bic, one.ambiguous) == \
        (two.verdict, two.bic_after, two.margin_bic, two.ambiguous)
    assert one.quantities == two.quantities and one.explanation == two.explanation


def test_fits_a_copy_did_not_send_are_done_by_the_parent(params, tmp_path):
    """The forked copy dies on its first fit (as a process killed by the OOM killer would): every fit still
    comes back, in task order, equal to the fit made in one process."""
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=600))
    ctx = build_context(rec, analytic_baseline(rec, params))
    forms = [e for e in effects_for(rec.kind.value) if e.applicable(ctx)][:6]
    parent = os.getpid()

    def dies_in_the_copy(e):
        def contribution(c, theta):
            if os.getpid() != parent:
                (tmp_path / "copy-died").touch()
                os._exit(3)
            return e.contribution(c, theta)
        return dataclasses.replace(e, contribution=contribution)

    tasks = [FitTask((dies_in_the_copy(e),)) for e in forms]
    serial = fit_all(ctx, tasks, 1e-3, 0.3, workers=1)
    shared = fit_all(ctx, tasks, 1e-3, 0.3, workers=2)
    assert (tmp_path / "copy-died").exists()          # the copy did take a fit, and died on it
    assert len(shared) == len(tasks)
    for a, b in zip(serial, shared):
        _same_fit(a, b)


def test_ctrl_c_mid_diagnosis_stops_both_processes_and_writes_nothing(tmp_path, strainwave_cmd):
    """A terminal's Ctrl-C reaches the whole process group, the forked copy too: one line, exit 130, no JSON
    file, and no process of the group left behind."""
    import signal
    import subprocess
    import time
    rec = tmp_path / "cha.csv"
    rec.write_text(cha_recording(cha_rows()[10], hysteresis=True, n=10_000))
    out = tmp_path / "d.json"
    proc = subprocess.Popen([*strainwave_cmd, "diagnose", str(rec), "--json", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(2.5)          # past the imports (about 1.1 s), among the fits
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err.strip().splitlines()[-1] == "error: interrupted", err
    assert not out.exists()
    deadline = time.monotonic() + 5.0
    while time.monotonic() < deadline:
        try:
            os.killpg(proc.pid, 0)       # some process of the group still exists
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        raise AssertionError("a process of the diagnosis outlived it")


def test_where_no_copy_can_start_the_fits_run_here(params, monkeypatch):
    """A container without /dev/shm (no POSIX semaphore) or at its process limit: the same fits, in one process."""
    import multiprocessing.context
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=400))
    ctx = build_context(rec, analytic_baseline(rec, params))
    tasks = [FitTask((e,)) for e in [e for e in effects_for(rec.kind.value) if e.applicable(ctx)][:4]]
    serial = fit_all(ctx, tasks, 1e-3, 0.3, workers=1)

    def refuse(*args, **kwargs):
        raise OSError(38, "Function not implemented")
    for target in ("Value", "Process"):
        with monkeypatch.context() as m:
            if target == "Value":
                m.setattr(multiprocessing.context.ForkContext, "Value", refuse, raising=False)
            else:
                m.setattr(multiprocessing.context.ForkProcess, "start", refuse)
            for a, b in zip(serial, fit_all(ctx, tasks, 1e-3, 0.3, workers=2)):
                _same_fit(a, b)
