"""The report's NAFEMS appendix: the coarse LE1, LE10 and LE11 cases run here (a few seconds of CPU), the fine
ones quoted from ``make bench``'s record (reports/bench/nafems.json, benchmarks/bench_nafems.py) when it exists.

The coarse cases take no parameter, so validate runs them beside the FEA cases (``NafemsJob``: a forked process
at low priority, which fills the cores the cases leave idle) and keeps them in the run's cache under the code
version (``strainwave.cache.case_key``): a rerun with the same code reads them back.
"""
from __future__ import annotations

import json
import multiprocessing
import os
import signal
import time
from pathlib import Path
from typing import Callable

from strainwave.cache import ResultCache, case_key
from strainwave.errors import StrainwaveError
from strainwave.fea import nafems
from strainwave.fea.meshing import MeshingFailed

__all__ = ["BENCH_RECORD", "coarse_cases", "nafems_appendix", "NafemsJob"]

# where ``make bench`` writes its record, relative to validate's --out folder (reports/validate -> reports/bench)
BENCH_RECORD = Path("..") / "bench" / "nafems.json"
NICE = 10     # the background coarse cases yield the cores to the FEA cases


def coarse_cases(progress: Callable[[str], None] = lambda m: None) -> tuple[list[dict], str | None]:
    """(the coarse cases as ``NafemsResult.to_dict()``, None) or ([], why they did not run)."""
    try:
        return [r.to_dict() for r in nafems.run_all("coarse", progress=progress)], None
    except (StrainwaveError, MeshingFailed) as exc:     # the appendix says so; the checks above stand alone
        return [], f"coarse NAFEMS cases did not run: {exc}"


def nafems_appendix(out_dir: Path, progress: Callable[[str], None] = lambda m: None,
                    coarse: tuple[list[dict], str | None] | None = None) -> dict:
    """{"cases": [NafemsResult.to_dict(), ...], "notes": [str, ...]}: coarse runs (``coarse``: ``coarse_cases``'
    answer made elsewhere; None: run here), then any fine record."""
    notes = [nafems.LE11_NOTE_TEXT]
    cases, error = coarse if coarse is not None else coarse_cases(progress)
    cases = list(cases)
    if error:
        notes.append(error)
    from strainwave.output_guard import unstage_text
    # from the folder the run's files go to, not its staging folder inside it
    record = (Path(unstage_text(str(Path(out_dir).resolve()))) / BENCH_RECORD).resolve()
    if record.exists():
        fine = json.loads(record.read_text())
        cases += fine["cases"]
        notes.append(f"fine cases: `make bench` record of {fine['created_utc']} ({record.name})")
    else:
        notes.append("fine cases: not run here; `make bench` (benchmarks/bench_nafems.py) writes reports/bench/nafems.json")
    return {"cases": cases, "notes": notes}


def _worker(conn) -> None:
    """In the forked child: the coarse cases, niced, their answer down the pipe."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)   # not the CLI's unwinding handler: just die
    os.nice(NICE)
    try:
        conn.send(coarse_cases())
    except BaseException as exc:   # noqa: BLE001 - any failure goes back as the appendix's note
        conn.send(([], f"coarse NAFEMS cases did not run: {type(exc).__name__}: {exc}"))
    finally:
        conn.close()


class NafemsJob:
    """The coarse cases, from the run's cache or started in a background process; ``appendix`` waits for them."""

    KEY_KIND = "validate-nafems-coarse"

    def __init__(self, cache: ResultCache, progress: Callable[[str], None]):
        self.cache, self.progress = cache, progress
        self.key = case_key(self.KEY_KIND, {"level": "coarse", "sizes_mm": nafems.COARSE_SIZES_MM})
        self.started = time.perf_counter()
        self.process = None
        hit = cache.get(self.key, {"cases": list})
        self.coarse = (hit["cases"], None) if hit is not None and isinstance(hit.get("cases"), list) else None
        if self.coarse is not None:
            progress(f"  nafems: reusing the cached coarse cases ({hit.get('seconds', 0.0):.1f} s originally)")
            return
        # fork: the cases need only what this process has loaded; no thread runs here yet
        ctx = multiprocessing.get_context("fork")
        self.conn, child = ctx.Pipe(duplex=False)
        self.process = ctx.Process(target=_worker, args=(child,), daemon=True)
        self.process.start()
        child.close()
        progress("  nafems: coarse cases in a background process, beside the FEA")

    def appendix(self, out_dir: Path) -> dict:
        """The appendix (``nafems_appendix``) once the coarse cases are in; caches them when they all ran."""
        if self.coarse is None:
            try:
                self.coarse = self.conn.recv()
            except EOFError:
                code = self.process.exitcode if self.process is not None else None
                self.coarse = ([], f"coarse NAFEMS cases did not run: the worker died (exit code {code})")
            self.cancel()
            seconds = time.perf_counter() - self.started
            if self.coarse[1] is None:
                self.cache.put(self.key, {"cases": self.coarse[0], "seconds": seconds})
            self.progress(f"  nafems: {len(self.coarse[0])} coarse case(s) in {seconds:.1f} s, beside the FEA")
        return nafems_appendix(out_dir, self.progress, coarse=self.coarse)

    def cancel(self) -> None:
        """Stop the background cases (on an interrupted run; harmless after they finished)."""
        if self.process is not None:
            if self.process.is_alive():
                self.process.kill()
            self.process.join(5)
            self.process = None
