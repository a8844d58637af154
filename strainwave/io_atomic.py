"""Write outputs under a temporary name and rename them into place, so no half file is left behind.

The temporary file is created with mode 0666 filtered by the user's umask (as ``open()`` would), not
``mkstemp``'s 0600: a report written here must be readable by whoever the user's umask lets read it.
Before the rename the data is fsync'ed, and after it the directory, so a power cut leaves either the
old or the new file under the target name, never an empty or partial one.
"""
from __future__ import annotations

import os
import secrets
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_text", "atomic_write_bytes"]

_ATTEMPTS = 100


def _create_temp(target: Path) -> Path:
    """A new empty file next to ``target`` (O_EXCL, so never someone else's), mode 0666 & ~umask."""
    for _ in range(_ATTEMPTS):
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(6)}{target.suffix}.tmp")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name next to {target}")


def _fsync_path(path: Path, *, directory: bool = False) -> None:
    flags = os.O_RDONLY | (os.O_DIRECTORY if directory else 0)
    fd = os.open(path, flags)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextmanager
def atomic_path(target: Path):
    """Yield a temporary path next to ``target``; on success its data is flushed to disk and it
    replaces ``target`` atomically (then the directory entry is flushed too)."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp_path = _create_temp(target)
    try:
        yield tmp_path
        _fsync_path(tmp_path)
        os.replace(tmp_path, target)
        _fsync_path(target.parent, directory=True)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def atomic_write_text(target: Path, text: str) -> Path:
    with atomic_path(target) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(target)


def atomic_write_bytes(target: Path, data: bytes) -> Path:
    with atomic_path(target) as tmp:
        tmp.write_bytes(data)
    return Path(target)
