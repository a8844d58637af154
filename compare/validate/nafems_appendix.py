"""The report's NAFEMS appendix: the coarse LE1, LE10 and LE11 cases run here (a few seconds of CPU), the fine
ones quoted from ``make bench``'s record (reports/bench/nafems.json, benchmarks/bench_nafems.py) when it exists."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Callable

from strainwave.errors import StrainwaveError
from strainwave.fea import nafems
from strainwave.fea.meshing import MeshingFailed

# where ``make bench`` writes its record, relative to validate's --out folder (reports/validate -> reports/bench)
BENCH_RECORD = Path("..") / "bench" / "nafems.json"


def nafems_appendix(out_dir: Path, progress: Callable[[str], None] = lambda m: None) -> dict:
    """{"cases": [NafemsResult.to_dict(), ...], "notes": [str, ...]}: coarse runs, then any fine record."""
    notes = [nafems.LE11_NOTE_TEXT]
    try:
        cases = [r.to_dict() for r in nafems.run_all("coarse", progress=progress)]
    except (StrainwaveError, MeshingFailed) as exc:     # the appendix says so; the checks above stand alone
        cases = []
        notes.append(f"coarse NAFEMS cases did not run: {exc}")
    record = (Path(out_dir) / BENCH_RECORD).resolve()
    if record.exists():
        fine = json.loads(record.read_text())
        cases += fine["cases"]
        notes.append(f"fine cases: `make bench` record of {fine['created_utc']} ({record.name})")
    else:
        notes.append("fine cases: not run here; `make bench` (benchmarks/bench_nafems.py) writes reports/bench/nafems.json")
    return {"cases": cases, "notes": notes}
