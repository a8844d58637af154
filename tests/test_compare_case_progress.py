"""Validate's per-case progress lines: id, k/N and the time left from fea.budget's element-count model."""
from __future__ import annotations

import re

from strainwave.compare.validate.case_progress import DEFAULT_S_PER_ELEMENT, CaseProgress, case_elements
from strainwave.compare.validate.runner import Case
from strainwave.params import load_params

CASES = (Case("cup-a1.12", "cup-torsion", 1.12), Case("shaft-a0.5", "shaft-torsion", 0.5), Case("ring", "ring-compression"))


def test_one_line_per_case_with_id_count_and_time_left_calibrated_on_finished_cases():
    params = load_params()
    lines = []
    tracker = CaseProgress(CASES, params, quick=True, workers=2, progress=lines.append, terminal=False)
    elements = {c.label: case_elements(c, params, True) for c in CASES}
    first_left = DEFAULT_S_PER_ELEMENT * sum(elements.values()) / 2
    assert tracker.seconds_left() == first_left
    tracker.done("shaft-a0.5", 10.0, "solved")
    rate = 10.0 / elements["shaft-a0.5"]
    assert tracker.seconds_left() == rate * (elements["cup-a1.12"] + elements["ring"]) / 2
    tracker.done("ring", 99.0, "cached")      # a reused case leaves the rate alone
    assert tracker.seconds_left() == rate * elements["cup-a1.12"] / 2
    tracker.done("cup-a1.12", 5.0, "FAILED")
    assert tracker.seconds_left() == 0.0
    assert [re.match(r"fea (\d)/3 (\S+): (\w+) in", line).groups() for line in lines] == [
        ("1", "shaft-a0.5", "solved"), ("2", "ring", "cached"), ("3", "cup-a1.12", "FAILED")]
    assert all("s left" in line and "\x1b[" not in line for line in lines)     # plain text in a pipe


def test_a_terminal_gets_a_rich_bar_before_the_same_line():
    lines = []
    tracker = CaseProgress(CASES[:1], load_params(), quick=True, workers=2, progress=lines.append, terminal=True)
    plain = tracker.done("cup-a1.12", 3.0, "solved")
    assert lines[0].endswith(plain) and "\x1b[" in lines[0]
