"""STEP files of every part for the validation folder, built in a separate process while the FEA runs.

The toothed cup alone takes tens of seconds of OCC work; on a 2-core machine that overlaps with the
(single-threaded) FEA instead of adding to it. Parts whose STEP is in the cache (same parameters and
code) and still on disk are not rebuilt.
"""
from __future__ import annotations

import multiprocessing
import time
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ..geometry.part import PartName
from .cache import ResultCache, case_key


@dataclass(frozen=True)
class StepOutcome:
    part: str
    files: tuple[Path, ...]
    seconds: float
    cached: bool
    error: str = ""


def export_one(part: str, params, target: Path) -> tuple[list[str], float, str]:
    """Build and write one part (runs in the worker process); errors come back as text, not exceptions."""
    start = time.perf_counter()
    try:
        from ..geometry.export import export_part

        files = [str(p) for p in export_part(part, params, Path(target), crack_depth_mm=None, teeth=True, png=None)]
        return files, time.perf_counter() - start, ""
    except Exception as exc:  # noqa: BLE001 - one part that cannot be built is reported, the rest go on
        return [], time.perf_counter() - start, f"{type(exc).__name__}: {exc}"


class StepJob:
    """STEP export of every ``PartName`` (teeth on, uncracked: the parts as designed), started in the background."""

    def __init__(self, params, step_dir: Path, cache: ResultCache, progress: Callable[[str], None]):
        self.params, self.step_dir, self.cache, self.progress = params, Path(step_dir), cache, progress
        self.started = time.perf_counter()
        self.done: list[StepOutcome] = []
        self.pending: dict[str, tuple[str, Future]] = {}
        self.executor: ProcessPoolExecutor | None = None
        for part in PartName:
            key = case_key("validate-step", {"part": part.value, "params": params.to_dict()})
            hit = cache.get(key)
            if hit is not None and hit.get("files") and all(Path(p).exists() for p in hit["files"]):
                progress(f"  {part.value}: reusing cached STEP ({hit['seconds']:.1f} s originally)")
                self.done.append(StepOutcome(part.value, tuple(Path(p) for p in hit["files"]), hit["seconds"], True))
                continue
            if self.executor is None:
                # spawn, not fork: the parent may hold gmsh/VTK state by the time the worker needs it
                self.executor = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
            target = self.step_dir / f"{part.value}.step"
            self.pending[part.value] = (key, self.executor.submit(export_one, part.value, params, target))
        if self.pending:
            progress(f"  building {len(self.pending)} STEP part(s) in a background process: "
                     + ", ".join(self.pending))

    def result(self) -> tuple[list[StepOutcome], float]:
        """Wait for the background parts; returns every part's outcome and the wall time of the export."""
        for part, (key, future) in self.pending.items():
            files, seconds, error = future.result()
            if error:
                self.progress(f"  {part}: STEP FAILED ({error})")
                self.done.append(StepOutcome(part, (), seconds, False, error))
                continue
            self.cache.put(key, {"files": files, "seconds": seconds})
            self.progress(f"  {part}: wrote {', '.join(Path(p).name for p in files)} in {seconds:.1f} s")
            self.done.append(StepOutcome(part, tuple(Path(p) for p in files), seconds, False))
        if self.executor is not None:
            self.executor.shutdown()
        order = {p.value: i for i, p in enumerate(PartName)}
        self.done.sort(key=lambda s: order[s.part])
        return self.done, time.perf_counter() - self.started

    def cancel(self) -> None:
        if self.executor is not None:
            self.executor.shutdown(wait=False, cancel_futures=True)
