"""The two shipped gears, for a benchmark that measures something per gear (imported, not run by make bench)."""
from __future__ import annotations

import os
import warnings
from pathlib import Path

GEARS = {"default": None, "second": str(Path(__file__).resolve().parents[1] / "strainwave/data/second_gear.toml")}


def shipped_params():
    """(gear name, its parameters) for each shipped gear, after printing the machine's load average."""
    from strainwave.api import load_params
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    for gear, path in GEARS.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")         # the material's G vs E/2(1+nu) note, not the benchmark's matter
            yield gear, load_params(path)
