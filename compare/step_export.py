"""STEP files of every part for the validation folder, reused from the cache when the inputs are unchanged."""
from __future__ import annotations

import time
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


def export_steps(params, step_dir: Path, cache: ResultCache, progress: Callable[[str], None]) -> list[StepOutcome]:
    """``step/<part>.step`` for every ``PartName`` (teeth on, uncracked: the parts as designed)."""
    out = []
    for part in PartName:
        target = Path(step_dir) / f"{part.value}.step"
        key = case_key("validate-step", {"part": part.value, "params": params.to_dict()})
        hit = cache.get(key)
        if hit is not None and all(Path(p).exists() for p in hit.get("files", [])) and hit.get("files"):
            progress(f"  {part.value}: reusing cached STEP ({hit['seconds']:.1f} s originally)")
            out.append(StepOutcome(part.value, tuple(Path(p) for p in hit["files"]), hit["seconds"], True))
            continue
        start = time.perf_counter()
        try:
            from ..geometry.export import export_part

            files = tuple(Path(p) for p in export_part(part.value, params, target, crack_depth_mm=None, teeth=True,
                                                       png=None))
        except Exception as exc:  # noqa: BLE001 - one part that cannot be built is reported, the rest go on
            seconds = time.perf_counter() - start
            progress(f"  {part.value}: STEP FAILED ({type(exc).__name__}: {exc})")
            out.append(StepOutcome(part.value, (), seconds, False, f"{type(exc).__name__}: {exc}"))
            continue
        seconds = time.perf_counter() - start
        cache.put(key, {"files": [str(p) for p in files], "seconds": seconds})
        progress(f"  {part.value}: wrote {', '.join(p.name for p in files)} in {seconds:.1f} s")
        out.append(StepOutcome(part.value, files, seconds, False))
    return out
