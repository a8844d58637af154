"""The one output guard: every output of a command checked together before any work, and written together.

Checked (InputError, exit 2, one line): a path that loops or exceeds the system's name limits; a file
whose extension is not what is written there; two outputs on one path (``--json x --plot x``, or
``--json t.boundary.vtu`` beside ``--vtu t.vtu``); an output on an input (``--samples o/sweep.csv`` with
``--out o``), refused even with ``--force``; an existing file strainwave did not write (``--vtu
README.md``), refused unless ``--force``.

Recognising strainwave's own files: every folder strainwave writes a file into keeps a manifest,
``.strainwave-outputs.json``, naming each file with the size and modification time it had when written.
A file is strainwave's while it still matches its entry; a file edited since, or never listed, is the
user's. An empty file holds nothing to lose and may be replaced. A folder given as ``--out`` is
strainwave's when it carries the manifest (made when the command starts writing there) or is empty.

Written together: the command writes its files into a staging folder beside each target
(``.strainwave-stage-PID-*``); only when the command has finished are they renamed into place, so a
failure (a full disk on the JSON after the PNG) leaves none of them, and the old files stay.
"""
from __future__ import annotations

import errno
import json
import os
import re
import shutil
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from strainwave.errors import InputError

__all__ = ["MANIFEST", "Planned", "check_outputs", "marked_folder", "remove_stale", "staged_outputs", "unstage_text"]

MANIFEST = ".strainwave-outputs.json"
STAGE_PREFIX = ".strainwave-stage-"
# An --out folder is strainwave's when it holds the manifest, or (written before the manifest existed) the
# index file its command always writes: validate's results.json, a sweep's points.json, the benchmark's JSON.
FOLDER_MARKS = (MANIFEST, "results.json", "points.json", "benchmark_diagnose.json")
# What each flag writes: a file named otherwise would be read by the wrong program.
SUFFIXES = {"--json": (".json",), "--plot": (".png",), "--png": (".png",), "--vtu": (".vtu",), "-o": (".step", ".stp")}


@dataclass(frozen=True)
class Planned:
    """One output: the flag that names it, the path as given, and whether it is a folder."""
    flag: str
    path: str
    directory: bool = False
    derived: bool = False   # written beside another output (FILE.boundary.vtu): its suffix is fixed by strainwave


def _name_limits(folder: str) -> tuple[int, int]:
    try:
        return os.pathconf(folder, "PC_NAME_MAX"), os.pathconf(folder, "PC_PATH_MAX")
    except (OSError, ValueError):
        return 255, 4096


def resolve(flag: str, path: str) -> Path:
    """The absolute, symlink-free path of an output; loops and over-long names refused in one line."""
    text = os.fspath(path)
    if "\x00" in text:
        raise InputError(flag, text, "a path cannot contain a NUL character")
    name_max, path_max = _name_limits("/")
    absolute = os.path.abspath(text)
    if len(os.fsencode(absolute)) >= path_max:
        raise InputError(flag, text, f"the path is longer than the system's {path_max} bytes")
    for part in (*Path(text).parts, *Path(absolute).parts):   # "LONG/../a.json" too: the kernel sees LONG
        if len(os.fsencode(part)) > name_max:
            raise InputError(flag, text, f"a name in the path is longer than the system's {name_max} bytes")
    try:
        os.stat(absolute)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(flag, text, "the path runs through a symbolic link loop") from None
        if exc.errno == errno.ENAMETOOLONG:
            raise InputError(flag, text, "the path is longer than the system allows") from None
    return Path(os.path.realpath(absolute))


def _manifest(folder: Path) -> dict:
    try:
        data = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    files = data.get("files") if isinstance(data, dict) else None
    return files if isinstance(files, dict) else {}


def _signature(path: Path) -> list[int]:
    st = path.stat()
    return [st.st_size, st.st_mtime_ns]


def is_ours(path: Path) -> bool:
    """True if ``path`` is a file strainwave wrote and nobody changed since (its folder's manifest says so)."""
    entry = _manifest(path.parent).get(path.name)
    return isinstance(entry, list) and entry == _signature(path)


def _write_manifest(folder: Path, files: dict) -> None:
    from strainwave.io_atomic import atomic_write_text
    atomic_write_text(folder / MANIFEST, json.dumps({"written_by": "strainwave", "files": files}, indent=1) + "\n")


def record_written(paths: list[Path]) -> None:
    """Add ``paths`` (just written) to their folders' manifests."""
    by_folder: dict[Path, list[Path]] = {}
    for p in paths:
        by_folder.setdefault(p.parent, []).append(p)
    for folder, members in by_folder.items():
        files = _manifest(folder)
        files.update({p.name: _signature(p) for p in members if p.is_file()})
        _write_manifest(folder, files)


@contextmanager
def marked_folder(folder: Path) -> Iterator[None]:
    """``folder`` (an --out folder) carries the manifest while the command runs, so a later run (a resume
    after a kill) knows it as strainwave's; a command that wrote nothing there takes the mark away again."""
    folder = Path(folder)
    made = not (folder / MANIFEST).exists()
    if made:
        folder.mkdir(parents=True, exist_ok=True)
        _write_manifest(folder, {})
    try:
        yield
    finally:
        if made and not [p for p in folder.iterdir() if p.name != MANIFEST and not _OWNED.match(p.name)]:
            (folder / MANIFEST).unlink(missing_ok=True)


def _same(a: Path, b: Path) -> bool:
    if a == b:
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _check_file(out: Planned, target: Path, force: bool) -> None:
    suffixes = SUFFIXES.get(out.flag)
    if suffixes and not out.derived and target.suffix.lower() not in suffixes:
        raise InputError(out.flag, out.path, f"must end in {' or '.join(suffixes)}: that is what is written there")
    if target.is_file() and target.stat().st_size > 0 and not force and not is_ours(target):
        raise InputError(out.flag, out.path, "exists and was not written by strainwave (or was changed since); "
                                             "pass --force to replace it")


def _check_folder(out: Planned, target: Path, inputs: dict[str, Path], force: bool) -> None:
    for flag, source in inputs.items():
        if target == source or target in source.parents:
            raise InputError(out.flag, out.path, f"holds the input {flag} {source}; the command writes there and "
                                                 f"could replace it: choose another folder")
    if target.is_dir() and not force and not any((target / name).exists() for name in FOLDER_MARKS) \
            and any(target.iterdir()):
        raise InputError(out.flag, out.path, "is a folder with files strainwave did not write; name an empty or "
                                             "new folder, or pass --force to write into it")


def check_outputs(planned: list[Planned], inputs: dict[str, str | None], *, force: bool) -> dict[str, Path]:
    """Refuse the command's outputs as a whole (module docstring); returns flag/path -> resolved path."""
    sources = {flag: resolve(flag, p) for flag, p in inputs.items() if p is not None}
    seen: dict[Path, Planned] = {}
    resolved = {}
    for out in planned:
        target = resolve(out.flag, out.path)
        for other_target, other in seen.items():
            if _same(target, other_target):
                raise InputError(out.flag, out.path, f"is also the output of {other.flag} {other.path}; "
                                                     f"each output needs its own path")
        for flag, source in sources.items():
            if _same(target, source):
                raise InputError(out.flag, out.path, f"is the input {flag} {source}; writing it would destroy the input")
        if out.directory:
            _check_folder(out, target, sources, force)
        else:
            _check_file(out, target, force)
        seen[target] = out
        resolved[f"{out.flag} {out.path}"] = target
    return resolved


# staging folder -> the folder its files go to, for the paths a command prints while it is staged
_STAGED: dict[str, str] = {}
_TEMP = re.compile(r"^\..+\.[0-9a-f]{12}(\.[^.]*)?\.tmp$")


def unstage_text(text: str) -> str:
    """``text`` with each staging folder replaced by the folder its files go to."""
    for stage, final in _STAGED.items():
        text = text.replace(stage, final)   # its random name occurs nowhere else
    return text


@contextmanager
def staged_outputs(args, names: tuple[str, ...]) -> Iterator[None]:
    """Point each file output ``args.<name>`` into a staging folder beside it; after the block, rename every
    staged file into place and record it in the manifest; on any exception remove the staging folders."""
    stages: dict[Path, Path] = {}
    for name in names:
        value = getattr(args, name, None)
        if value in (None, "-"):
            continue
        final = Path(os.path.realpath(os.path.abspath(value)))
        if final.parent not in stages:
            final.parent.mkdir(parents=True, exist_ok=True)
            stages[final.parent] = Path(tempfile.mkdtemp(prefix=f"{STAGE_PREFIX}{os.getpid()}-", dir=final.parent))
            _STAGED[str(stages[final.parent])] = str(final.parent)
        setattr(args, name, str(stages[final.parent] / final.name))
    try:
        yield
        written = []
        for parent, stage in stages.items():
            for staged_file in sorted(stage.iterdir()):
                if staged_file.is_file() and not _TEMP.match(staged_file.name):
                    os.replace(staged_file, parent / staged_file.name)
                    written.append(parent / staged_file.name)
        record_written(written)
    finally:
        for stage in stages.values():
            shutil.rmtree(stage, ignore_errors=True)
            _STAGED.pop(str(stage), None)


# ".strainwave-scratch-PID-*" (the CLI's scratch) and ".strainwave-stage-PID-*" (staged outputs); a run killed
# with -9 cannot remove its own, so the next run into the same folder removes those whose process is gone.
_OWNED = re.compile(r"^\.?strainwave-(scratch|stage|solve|mesh)-(\d+)-")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:   # someone else's process: alive
        return True
    return True


def remove_stale(folder: Path | str) -> int:
    """Remove the scratch and staging folders of killed strainwave runs in ``folder``; returns how many."""
    removed = 0
    try:
        entries = list(Path(folder).iterdir())
    except OSError:
        return 0
    for entry in entries:
        m = _OWNED.match(entry.name)
        if m and entry.is_dir() and not entry.is_symlink() and int(m.group(2)) != os.getpid() \
                and not _alive(int(m.group(2))):
            shutil.rmtree(entry, ignore_errors=True)
            removed += 1
    return removed
