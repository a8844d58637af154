"""STEP files of every part for the validation folder, built in a separate process while the FEA runs.

The toothed cup alone takes tens of seconds of OCC work; on a 2-core machine that overlaps with the
(single-threaded) FEA instead of adding to it. Parts whose STEP is in the cache (same parameters and
code) and still on disk are not rebuilt.
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from strainwave.geometry.part import PartName
from strainwave.cache import NUMBER, ResultCache, case_key
from strainwave.io_atomic import remove_stale_temps
from strainwave.output_guard import reuse_output


@dataclass(frozen=True)
class StepOutcome:
    part: str
    files: tuple[Path, ...]          # the STEP file(s)
    seconds: float
    cached: bool
    error: str = ""
    preview: Path | None = None      # the part's PNG preview (the report's inputs section), if drawn


def _outcome(part: str, written, seconds: float, cached: bool) -> StepOutcome:
    paths = [Path(p) for p in written]
    previews = [p for p in paths if p.suffix == ".png"]
    return StepOutcome(part, tuple(p for p in paths if p.suffix != ".png"), seconds, cached, "",
                       previews[0] if previews else None)


# The export yields the cores to the FEA cases and fills the time they leave idle (the images, the last case).
NICENESS = 10

# The parts the FEA studies mesh get a preview (the report's inputs section shows it); the EWG cam does not.
PREVIEWED = ("flexspline-cup", "ewg-flexspline-ring", "output-shaft", "wg-bearing-ring")


def export_one(part: str, params, target: Path, png: Path | None = None) -> tuple[list[str], float, str]:
    """Build and write one part and its preview (runs in the worker process); errors come back as text."""
    start = time.perf_counter()
    try:
        from strainwave.geometry.export import export_part

        files = [str(p) for p in export_part(part, params, Path(target), crack_depth_mm=None, teeth=True, png=png)]
        return files, time.perf_counter() - start, ""
    except Exception as exc:  # noqa: BLE001 - one part that cannot be built is reported, the rest go on
        return [], time.perf_counter() - start, f"{type(exc).__name__}: {exc}"


def _worker(conn, jobs: list[tuple[str, Path, Path | None]], params) -> None:
    """Background process: export each part in turn and send (part, files, seconds, error) back.
    It dies with the run and leaves Ctrl-C to it (the run cancels it): no KeyboardInterrupt traceback."""
    from strainwave.compare.validate.isolated import bind_to_parent, send_or_exit

    bind_to_parent()
    os.nice(NICENESS)
    for part, target, png in jobs:
        send_or_exit(conn, (part, *export_one(part, params, target, png)))
    conn.close()


class StepJob:
    """STEP export of every ``PartName`` (teeth on, uncracked: the parts as designed), started in the background."""

    def __init__(self, params, step_dir: Path, cache: ResultCache, progress: Callable[[str], None],
                 preview_dir: Path | None = None, parts: tuple[PartName, ...] | None = None):
        self.cache, self.progress = cache, progress
        self.done: list[StepOutcome] = []
        self.keys: dict[str, str] = {}
        self.folders = tuple(Path(d) for d in (step_dir, preview_dir) if d is not None)
        jobs = []
        for part in PartName if parts is None else parts:
            png = Path(preview_dir) / f"{part.value}_preview.png" if preview_dir and part.value in PREVIEWED else None
            key = case_key("validate-step", {"part": part.value, "params": params.to_dict(),
                                             "preview": png is not None})
            hit = cache.get(key, lambda r: isinstance(r["seconds"], NUMBER) and all(isinstance(p, str)
                                                                                    for p in r["files"]))
            reused = [reuse_output(p) for p in hit["files"]] if hit is not None and hit.get("files") else [None]
            if all(p is not None for p in reused):   # the previous run's files, into this run's set
                progress(f"  {part.value}: reusing cached STEP ({hit['seconds']:.1f} s originally)")
                self.done.append(_outcome(part.value, [str(p) for p in reused], hit["seconds"], True))
                continue
            self.keys[part.value] = key
            jobs.append((part.value, Path(step_dir) / f"{part.value}.step", png))
        self.process = None
        if jobs:
            # from the cases' fork server: a clean interpreter for OCC with build123d already imported (a spawned
            # one re-imports it); a daemon, so it never outlives the run
            from strainwave.compare.validate.isolated import fork_server_context
            ctx = fork_server_context()
            self.conn, child = ctx.Pipe(duplex=False)
            self.process = ctx.Process(target=_worker, args=(child, jobs, params), daemon=True)
            self.process.start()
            child.close()
            progress(f"  building {len(jobs)} STEP part(s) in a background process: "
                     + ", ".join(p for p, _, _ in jobs))

    def result(self) -> tuple[list[StepOutcome], float]:
        """Wait for the background parts; returns every part's outcome and the export's wall time (the
        worker's seconds over the parts it built; 0 when every part came from the cache or none was asked for)."""
        received = set()
        while self.process is not None and len(received) < len(self.keys):
            try:
                part, files, seconds, error = self.conn.recv()
            except EOFError:
                break  # the worker died: the parts not received are reported below
            received.add(part)
            if error:
                self.progress(f"  {part}: STEP FAILED ({error})")
                self.done.append(StepOutcome(part, (), seconds, False, error))
                continue
            self.cache.put(self.keys[part], {"files": files, "seconds": seconds})
            self.progress(f"  {part}: wrote {', '.join(Path(p).name for p in files)} in {seconds:.1f} s")
            self.done.append(_outcome(part, files, seconds, False))
        for part in self.keys:
            if part not in received:
                code = None if self.process is None else self.process.exitcode
                self.done.append(StepOutcome(part, (), 0.0, False, f"STEP worker died (exit code {code})"))
        self.cancel()
        order = {p.value: i for i, p in enumerate(PartName)}
        self.done.sort(key=lambda s: order[s.part])
        # the worker's own time per part: the wait for result() after the export finished is not the export's
        return self.done, sum(s.seconds for s in self.done if not s.cached)

    def cancel(self) -> None:
        """Stop the background export (on an interrupted run; harmless after it finished)."""
        if self.process is not None:
            if self.process.is_alive():
                self.process.kill()   # OCC ignores SIGTERM while it builds; nothing it holds needs saving
                self.process.join(5)
                # a file it was writing stays under its temporary name: the target was never touched
                for folder in self.folders:
                    remove_stale_temps(folder)
            self.process.join(5)
