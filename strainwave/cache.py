"""On-disk result cache keyed by the parameters and the code version.

A rerun of ``validate`` or a resumed ``sweep`` reuses finished cases. The code version is a hash of
the package's own source files, so editing any formula or solver invalidates every cached case. Each
reader states the schema of its entries (``ResultCache.get(key, schema)``): an entry that is not a JSON
object meeting it (damaged, truncated, hand-edited, of another layout) is recomputed, never trusted.
"""
from __future__ import annotations

import fcntl
import hashlib
import json
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Callable, Mapping, TypeVar, Union

T = TypeVar("T")

from strainwave.io_atomic import atomic_write_text


@lru_cache(maxsize=1)
def code_version() -> str:
    """SHA-256 (16 hex) over the installed strainwave sources, in a stable order."""
    from strainwave import analytic, compare, fea, geometry

    digest = hashlib.sha256()
    # this file's own folder for strainwave itself: a folder named strainwave in the working directory (an output
    # folder, say) makes `strainwave` a namespace package without __file__ in a case's child process
    roots = [Path(__file__).parent] + [Path(package.__file__).parent for package in (analytic, compare, fea, geometry)]
    for root in roots:
        for path in sorted(root.rglob("*.py")) + sorted(root.glob("data/*.toml")):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def case_key(kind: str, payload: dict) -> str:
    """Stable key of one case: what is computed, with which inputs, by which code."""
    text = json.dumps({"kind": kind, "payload": payload, "code": code_version()}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


# An entry's schema: each required key and the type(s) its value must have, or a predicate over the entry.
Schema = Union[Mapping[str, Union[type, tuple]], Callable[[dict], bool]]
NUMBER = (int, float)


def meets(record, schema: Schema | None) -> bool:
    """True if ``record`` is a JSON object meeting ``schema`` (numbers finite, bools not numbers)."""
    if not isinstance(record, dict):
        return False
    if schema is None:
        return True
    if callable(schema):
        try:
            return bool(schema(record))
        except (KeyError, TypeError, ValueError, AttributeError):
            return False
    for name, kind in schema.items():
        value = record.get(name)
        if not isinstance(value, kind) or (isinstance(value, bool) and bool not in _types(kind)):
            return False
        if isinstance(value, float) and not math.isfinite(value):
            return False
    return True


def _types(kind) -> tuple:
    return kind if isinstance(kind, tuple) else (kind,)


@dataclass(frozen=True)
class ResultCache:
    root: Path

    def path(self, key: str) -> Path:
        return Path(self.root) / f"{key}.json"

    def get(self, key: str, schema: Schema | None = None) -> dict | None:
        """The entry under ``key`` if it is a JSON object that meets ``schema``; None (recomputed) otherwise."""
        path = self.path(key)
        if not path.exists():
            return None
        try:
            record = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None  # a damaged entry is recomputed, never trusted
        return record if meets(record, schema) else None

    def put(self, key: str, record: dict) -> None:
        atomic_write_text(self.path(key), json.dumps(record, default=str))


def shared_entry(path: Path | None, read: Callable[[Path], T], compute: Callable[[], T],
                 write: Callable[[Path, T], None]) -> T:
    """What the cases of one run share: ``read(path)`` if it is there, else ``compute()`` kept by ``write``.

    Two cases that run at once and need the same entry would each compute it; an exclusive lock on a file beside
    it makes the second wait for the first's and read it (the kernel drops the lock if the first dies). A damaged
    entry is computed again, never trusted. ``path`` None: computed, nothing kept."""
    if path is None:
        return compute()
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path.with_name(path.name + ".lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if path.exists():
            try:
                return read(path)
            except (OSError, KeyError, ValueError):
                pass
        value = compute()
        write(path, value)
        return value
