"""Issue 52: no command runs silent for more than a few seconds: counted work says k/N and the time left,
uncounted work (a STEP export, a diagnosis) says it is still going."""
from __future__ import annotations

import time
from types import SimpleNamespace

from strainwave.progress import Counter, ticking


def test_counter_says_k_of_n_and_the_time_left():
    lines = []
    counter = Counter("work", 4, lines.append, terminal=False)
    counter.step("a")
    time.sleep(0.02)
    counter.step("b")
    assert lines[0].startswith("work 1/4 a, about ") and lines[1].startswith("work 2/4 b, about ")
    left = float(lines[1].split("about ")[1].split()[0])
    assert 0.0 <= left < 5.0
    assert Counter("bar", 2, lines.append, terminal=True).step("x").startswith("bar 1/2 x")
    assert "━" in lines[-1] or "\x1b[" in lines[-1]   # the rich bar on a terminal


def test_ticking_says_it_is_still_working_and_when_it_is_done():
    lines = []
    with ticking("export", lines.append, every_s=0.05):
        time.sleep(0.18)
    assert lines[0].startswith("export: still working, ") and lines[-1].startswith("export done in ")
    assert sum("still working" in line for line in lines) >= 2
    quick = []
    with ticking("export", quick.append, every_s=5.0):   # done (or refused) before the first tick: silent
        pass
    assert quick == []
    late = []
    with ticking("export", late.append, every_s=0.05, first_s=0.3):   # the first line waits first_s
        time.sleep(0.2)
    assert late == []


def test_benchmark_diagnose_reports_each_recording(monkeypatch, capsys):
    import strainwave.compare.diagnose.generators.benchmark as bench
    from strainwave import cli

    def fake(**kw):
        for name in ("f1-clean-000", "f1-clean-001"):
            kw["progress"](SimpleNamespace(name=name, verdict="agrees"))
        return SimpleNamespace(summary=lambda: "done", to_dict=lambda: {}, meets_targets=True)

    monkeypatch.setattr(bench, "run_benchmark", fake)
    monkeypatch.setattr(cli, "_benchmark_counter", lambda n, f: Counter("benchmark-diagnose", 2, cli._progress,
                                                                        terminal=False))
    assert cli.main(["benchmark-diagnose", "--n", "1"]) == 0
    err = capsys.readouterr().err
    assert "benchmark-diagnose 1/2 f1-clean-000: agrees" in err and "benchmark-diagnose 2/2 f1-clean-001" in err


def _short_recording(tmp_path):
    """The shipped sample's header and its first 200 rows (enough for the fits, a second's work)."""
    from pathlib import Path

    lines = (Path(__file__).parents[1] / "examples" / "rig.csv").read_text().splitlines()
    head = [line for line in lines if line.startswith("#") or not line[:1].isdigit() and not line.startswith("-")]
    rows = [line for line in lines if line not in head]
    path = tmp_path / "rig200.csv"
    path.write_text("\n".join(head + rows[:200]) + "\n")
    return path


def test_diagnose_says_its_stage_on_stderr_when_it_takes_longer_than_the_tick(monkeypatch, capsys, tmp_path):
    """A diagnosis longer than TICK_S names its stage on stderr (here the tick is shortened, so a second's work is
    'long'); one shorter than the tick prints no progress at all, and stdout holds only the result."""
    import strainwave.progress as progress
    from strainwave import cli

    path = _short_recording(tmp_path)
    monkeypatch.setattr(progress, "TICK_S", 0.02)
    assert cli.main(["diagnose", str(path)]) == 0
    out, err = capsys.readouterr()
    assert "diagnose rig200.csv: " in err and ": still working, " in err and "diagnose rig200.csv done in " in err
    assert "fitting the effects to 200 rows" in err or "the analytic baseline" in err
    assert "still working" not in out and "rig200.csv" in out   # stdout: the diagnosis alone
    monkeypatch.setattr(progress, "TICK_S", 600.0)
    assert cli.main(["diagnose", str(path)]) == 0
    out, err = capsys.readouterr()
    assert "still working" not in err and "done in" not in err and out
