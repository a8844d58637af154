"""Write outputs under a temporary name and rename them into place, so no half file is left behind.

The temporary file is created with mode 0666 filtered by the user's umask (as ``open()`` would), not
``mkstemp``'s 0600: a report written here must be readable by whoever the user's umask lets read it.
Before the rename the data is fsync'ed, and after it the directory, so a power cut leaves either the
old or the new file under the target name, never an empty or partial one.
"""
from __future__ import annotations

import math
import os
import re
import secrets
import stat
from contextlib import contextmanager
from pathlib import Path

from strainwave.errors import InputError

__all__ = ["atomic_path", "atomic_write_text", "atomic_write_bytes", "check_output_path", "json_ready",
           "remove_stale_temps"]

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


# ".<target name>.<12 hex>.<suffix>.tmp", as _create_temp names them: nothing else in a folder matches
_TEMP_NAME = re.compile(r"^\..+\.[0-9a-f]{12}(\.[^.]*)?\.tmp$")


def json_ready(x):
    """``x`` with every non-finite float (an unbounded fitted stiffness, a target with no cases) as None: JSON has
    no inf or NaN, and a writer that emits them (Python's default) leaves a file other readers reject."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: json_ready(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_ready(v) for v in x]
    return x


def remove_stale_temps(folder: Path) -> int:
    """Remove the temporary files a killed writer left in ``folder`` (a process killed with -9 between
    creating its temporary file and the rename cannot remove it itself); the targets were never touched.
    Returns how many were removed. Call it where no other writer of the same outputs runs."""
    removed = 0
    if not Path(folder).is_dir():
        return 0
    for entry in Path(folder).iterdir():
        if _TEMP_NAME.match(entry.name) and entry.is_file():
            entry.unlink(missing_ok=True)
            removed += 1
    return removed


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


def _probe_writable(directory: Path) -> str | None:
    """None if a file can be created in ``directory`` (tried, then removed), else why not. Asking the
    file system is the only honest test: os.access says yes to root on a read-only mount."""
    for _ in range(_ATTEMPTS):
        probe = directory / f".strainwave-probe-{secrets.token_hex(6)}"
        try:
            os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        except FileExistsError:
            continue
        except OSError as exc:
            return exc.strerror or str(exc)
        os.unlink(probe)
        return None
    return "no free probe name"


def check_output_path(path: Path | str, flag: str, *, directory: bool = False,
                      inputs: tuple[Path | str | None, ...] = ()) -> None:
    """Refuse (InputError naming ``flag`` and the path) an output that cannot be written, BEFORE any work:
    a file target that is a directory (or a directory target that is a file), a parent that is a file,
    a folder the user may not write in, or a target that is one of the command's ``inputs``."""
    target = Path(path)
    if target.exists():
        if directory and not target.is_dir():
            raise InputError(flag, str(path), "exists and is not a directory; name a folder")
        if not directory and target.is_dir():
            raise InputError(flag, str(path), "is a directory; name a file inside it")
        if not directory and not stat.S_ISREG(target.stat().st_mode):
            raise InputError(flag, str(path), "is not a regular file (a device or pipe); name a file")
    for source in inputs:
        if source is not None and target.exists() and Path(source).exists() and os.path.samefile(source, target):
            raise InputError(flag, str(path), f"is the input {source}; writing it would destroy the input")
    existing = target if directory and target.is_dir() else target.parent
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        raise InputError(flag, str(path), f"{existing} is a file, not a directory")
    why = _probe_writable(existing)
    if why is not None:
        raise InputError(flag, str(path), f"cannot write in {existing} ({why})")
