"""Validate's per-case progress lines: id, k/N and the time left from fea.budget's element-count model."""
from __future__ import annotations

import re

from strainwave.compare.validate.case_progress import CaseProgress, case_cost_s
from strainwave.compare.validate.runner import Case
from strainwave.params import load_params

CASES = (Case("cup-a1.12", "cup-torsion", 1.12), Case("shaft-a0.5", "shaft-torsion", 0.5), Case("ring", "ring-compression"))


def test_one_line_per_case_with_id_count_and_time_left_calibrated_on_finished_cases():
    params = load_params()
    lines = []
    tracker = CaseProgress(CASES, params, quick=True, workers=2, progress=lines.append, terminal=False)
    costs = {c.label: case_cost_s(c, params, True) for c in CASES}
    first_left = sum(costs.values()) / 2     # before any case finished: one wall second per estimated CPU second
    assert tracker.seconds_left() == first_left
    tracker.done("shaft-a0.5", 10.0, "solved")
    rate = 10.0 / costs["shaft-a0.5"]
    assert tracker.seconds_left() == rate * (costs["cup-a1.12"] + costs["ring"]) / 2
    tracker.done("ring", 99.0, "cached")      # a reused case leaves the rate alone
    assert tracker.seconds_left() == rate * costs["cup-a1.12"] / 2
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


def test_a_case_costs_its_study_s_cpu_seconds_per_element_not_its_element_count():
    """The wave generator's few 27-node hexahedra cost more than the shaft's many tetrahedra: the schedule
    must start it first, which a bare element count would not."""
    from strainwave.fea.budget import estimate
    from strainwave.registry import STUDIES

    params = load_params()
    wg, shaft = Case("cup-wave-generator", "cup-wave-generator"), Case("shaft-a0.1", "shaft-torsion", 0.1)
    assert estimate(wg.study, params, None).elements < estimate(shaft.study, params, None).elements
    assert case_cost_s(wg, params, False) > case_cost_s(shaft, params, False)
    for case in (wg, shaft):
        full, quick = STUDIES[case.study].facts().cpu_s_per_element
        assert case_cost_s(case, params, False) == estimate(case.study, params, None).elements * full
        assert case_cost_s(case, params, True) == estimate(case.study, params, None, True).elements * quick
