"""On-disk result cache keyed by the parameters and the code version.

A rerun of ``validate`` or a resumed ``sweep`` reuses finished cases. The code version is a hash of
the package's own source files, so editing any formula or solver invalidates every cached case.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from strainwave.io_atomic import atomic_write_text


@lru_cache(maxsize=1)
def code_version() -> str:
    """SHA-256 (16 hex) over the installed strainwave sources, in a stable order."""
    import strainwave
    from strainwave import analytic, compare, fea, geometry

    digest = hashlib.sha256()
    for package in (strainwave, analytic, compare, fea, geometry):
        root = Path(package.__file__).parent
        for path in sorted(root.rglob("*.py")) + sorted(root.glob("data/*.toml")):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def case_key(kind: str, payload: dict) -> str:
    """Stable key of one case: what is computed, with which inputs, by which code."""
    text = json.dumps({"kind": kind, "payload": payload, "code": code_version()}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


@dataclass(frozen=True)
class ResultCache:
    root: Path

    def path(self, key: str) -> Path:
        return Path(self.root) / f"{key}.json"

    def get(self, key: str) -> dict | None:
        path = self.path(key)
        if not path.exists():
            return None
        try:
            return json.loads(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError):
            return None  # a damaged entry is recomputed, never trusted

    def put(self, key: str, record: dict) -> None:
        atomic_write_text(self.path(key), json.dumps(record, default=str))
