"""One progress line per finished FEA case: its id, k/N and the estimated time left.

The estimate is ``fea.budget``'s element-count cost model: each case's finest-mesh element count times its
study's CPU seconds per element (``StudyFacts.cpu_s_per_element``), scaled by the wall seconds per estimated
second of the cases finished so far in this run (1 before the first), over the two workers. On a terminal
the line carries a rich progress bar; in a pipe it is plain text. Every line names its case, so lines of cases
running side by side stay apart.
"""
from __future__ import annotations

import io
import sys
import threading
from typing import Callable, Sequence

# CPU seconds per element of a study that states none (the median over the shipped studies)
DEFAULT_S_PER_ELEMENT = 2e-4


def case_cost_s(case, params, quick: bool) -> float:
    """The cost model's CPU seconds of a case: its finest mesh's element count (at least 1) times its study's
    ``cpu_s_per_element`` for the run's mode."""
    from strainwave.fea.budget import estimate
    from strainwave.registry import STUDIES
    try:
        elements = max(1, estimate(case.study, params, case.mesh_size_mm, quick).elements)
    except ValueError:   # a study the cost model does not know: counted as one element
        elements = 1
    facts = STUDIES[case.study].facts() if case.study in STUDIES else None
    return elements * (facts.cpu_s_per_element[bool(quick)] if facts is not None else DEFAULT_S_PER_ELEMENT)


class CaseProgress:
    """Thread-safe: ``done(case, seconds, status)`` from each worker prints that case's line."""

    def __init__(self, cases: Sequence, params, *, quick: bool, workers: int, progress: Callable[[str], None],
                 terminal: bool | None = None):
        self._cost = {c.label: case_cost_s(c, params, quick) for c in cases}
        self._left = dict(self._cost)
        self._workers = max(1, workers)
        self._progress = progress
        self._terminal = sys.stderr.isatty() if terminal is None else terminal
        self._lock = threading.Lock()
        self._done_s = 0.0
        self._done_cost = 0.0

    @property
    def costs(self) -> dict[str, float]:
        """The cost model's CPU seconds by case label."""
        return dict(self._cost)

    def seconds_left(self) -> float:
        """Estimated wall seconds for the cases not yet finished."""
        rate = self._done_s / self._done_cost if self._done_cost else 1.0
        return rate * sum(self._left.values()) / self._workers

    def done(self, label: str, seconds: float, status: str) -> str:
        with self._lock:
            cost = self._left.pop(label, 0.0)
            if status != "cached":    # a reused case costs nothing: it must not calibrate the rate
                self._done_s += seconds
                self._done_cost += cost
            k, n = len(self._cost) - len(self._left), len(self._cost)
            line = (f"fea {k}/{n} {label}: {status} in {seconds:.1f} s, "
                    f"about {self.seconds_left():.0f} s left")
            self._progress(self._bar(k, n) + line if self._terminal else line)
            return line

    @staticmethod
    def _bar(k: int, n: int) -> str:
        from rich.console import Console
        from rich.progress_bar import ProgressBar
        buf = io.StringIO()
        Console(file=buf, force_terminal=True, width=24).print(ProgressBar(total=n, completed=k, width=20), end="")
        return buf.getvalue() + " "
