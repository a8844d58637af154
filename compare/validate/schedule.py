"""Order FEA cases longest first, from the durations of the last run in the same output folder.

Two workers share the cases. Started in plan order, the run ended with one worker idle while the
other finished a long case it had picked up last; longest-processing-time-first bounds the wall time
by 4/3 of the optimum. Durations come from ``durations.json`` (``durations-quick.json``) next to the
result cache (written after every run, by case label, whatever the code version); cases never timed before go first, since an
unknown case is the likeliest to be long.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from strainwave.io_atomic import atomic_write_text


def durations_file(folder: Path, quick: bool) -> Path:
    """One file per mode: --quick cases share labels with the full run's but are far shorter."""
    return Path(folder) / ("durations-quick.json" if quick else "durations.json")


def load_durations(path: Path) -> dict[str, float]:
    """Seconds per case label from the last run; empty when there is none or it is unreadable."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError):
        return {}
    return {str(k): float(v) for k, v in data.items() if isinstance(v, (int, float))} if isinstance(data, dict) else {}


def longest_first(cases: Sequence, durations: Mapping[str, float], costs: Mapping[str, float] | None = None) -> list:
    """Cases sorted by last duration, descending; untimed cases first, in plan order (stable sort), or with
    ``costs`` (a cost model's estimate by label, e.g. fea.budget's element count) largest estimate first."""
    costs = costs or {}
    return sorted(cases, key=lambda c: (c.label in durations, -durations.get(c.label, costs.get(c.label, 0.0))))


def save_durations(path: Path, measured: Iterable[tuple[str, float]], previous: Mapping[str, float]) -> None:
    """Merge this run's computed (not cached) case times into the file."""
    merged = {**previous, **{label: round(seconds, 2) for label, seconds in measured}}
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(Path(path), json.dumps(merged, indent=1, sort_keys=True))
