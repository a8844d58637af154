"""One progress line per finished FEA case: its id, k/N and the estimated time left.

The estimate is ``fea.budget``'s element-count cost model: each case's finest-mesh element count, times
seconds per element calibrated on the cases finished so far in this run (before the first one, on
DEFAULT_S_PER_ELEMENT), over the two workers. On a terminal the line carries a rich progress bar; in a
pipe it is plain text. Every line names its case, so lines of cases running side by side stay apart.
"""
from __future__ import annotations

import io
import sys
import threading
from typing import Callable, Sequence

# Seconds per finest-mesh element of a case (three refinements, assembly and solve), the starting rate
# before a case of this run has finished
DEFAULT_S_PER_ELEMENT = 2e-4


def case_elements(case, params, quick: bool) -> int:
    """The cost model's element count of a case's finest mesh (at least 1)."""
    from strainwave.fea.budget import estimate
    try:
        return max(1, estimate(case.study, params, case.mesh_size_mm, quick).elements)
    except ValueError:   # a study the cost model does not know: counted as one element
        return 1


class CaseProgress:
    """Thread-safe: ``done(case, seconds, status)`` from each worker prints that case's line."""

    def __init__(self, cases: Sequence, params, *, quick: bool, workers: int, progress: Callable[[str], None],
                 terminal: bool | None = None):
        self._elements = {c.label: case_elements(c, params, quick) for c in cases}
        self._left = dict(self._elements)
        self._workers = max(1, workers)
        self._progress = progress
        self._terminal = sys.stderr.isatty() if terminal is None else terminal
        self._lock = threading.Lock()
        self._done_s = 0.0
        self._done_elements = 0

    @property
    def elements(self) -> dict[str, int]:
        """The cost model's finest-mesh element count by case label."""
        return dict(self._elements)

    def seconds_left(self) -> float:
        """Estimated wall seconds for the cases not yet finished."""
        rate = self._done_s / self._done_elements if self._done_elements else DEFAULT_S_PER_ELEMENT
        return rate * sum(self._left.values()) / self._workers

    def done(self, label: str, seconds: float, status: str) -> str:
        with self._lock:
            elements = self._left.pop(label, 0)
            if status != "cached":    # a reused case costs nothing: it must not calibrate the rate
                self._done_s += seconds
                self._done_elements += elements
            k, n = len(self._elements) - len(self._left), len(self._elements)
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
