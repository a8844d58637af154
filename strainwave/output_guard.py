"""The one output guard: every output of a command checked together before any work, and written together.

Checked (InputError, exit 2, one line): a path that loops or exceeds the system's name limits; a file
whose extension is not what is written there; two outputs on one path (``--json x --plot x``, or
``--json t.boundary.vtu`` beside ``--vtu t.vtu``); an output on an input (``--samples o/sweep.csv`` with
``--out o``), refused even with ``--force``; an existing file strainwave did not write (``--vtu
README.md``), refused unless ``--force``.

Ownership by record, never by name: every folder strainwave writes a file into keeps a manifest,
``.strainwave-outputs.json``, naming each file (by its path relative to the folder) with its size and
SHA-256 as written. A file is strainwave's while its content still matches its entry; a file edited since,
or never listed, is the user's: it is never removed, and replaced only with ``--force``. A folder given as
``--out`` is strainwave's when it carries the manifest (made when the command starts writing there) or is
empty. A temporary folder strainwave makes (scratch, staging, a solve's or a mesher's) carries a record
inside it (``.strainwave-owner``: the process and its start time); only such a folder, of a process that is
gone, is ever removed by a later run.

Written together: single files are written into a staging folder beside each target; an ``--out`` folder's
whole run is written into one staging folder inside it (its ``cache`` shared with the folder's own). Only
when the command has finished are the files renamed into place (the index file last) and the previous
run's files it no longer writes removed, so an interrupted run leaves the previous complete set.
One run at a time writes an ``--out`` folder (a lock on the folder; a second run is refused in one line).
"""
from __future__ import annotations

import errno
import fcntl
import glob
import hashlib
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

__all__ = ["MANIFEST", "OWNER", "Planned", "check_outputs", "folder_lock", "is_ours", "make_owned_dir",
           "marked_folder", "remove_stale", "reuse_output", "staged_outputs", "staged_run", "unstage_text"]

MANIFEST = ".strainwave-outputs.json"
OWNER = ".strainwave-owner"           # the record inside each temporary folder strainwave made
STAGE_PREFIX = ".strainwave-stage-"
# What each flag writes: a file named otherwise would be read by the wrong program.
SUFFIXES = {"--json": (".json",), "--plot": (".png",), "--png": (".png",), "--vtu": (".vtu",), "-o": (".step", ".stp")}
_MANIFEST_LOOKUP_DEPTH = 4            # a file's manifest is in its folder or an --out folder up to this far above


@dataclass(frozen=True)
class Planned:
    """One output: the flag that names it, the path as given, and whether it is a folder."""
    flag: str
    path: str
    directory: bool = False
    derived: bool = False   # written beside another output (FILE.boundary.vtu): its suffix is fixed by strainwave
    writes: tuple[str, ...] = ()   # an --out folder: the index files its command always writes there


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


# ---- the manifest ----------------------------------------------------------------------------------------

def _manifest(folder: Path) -> dict:
    try:
        data = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    files = data.get("files") if isinstance(data, dict) else None
    return files if isinstance(files, dict) else {}


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _record(path: Path) -> dict:
    return {"size": path.stat().st_size, "sha256": _sha256(path)}


def _matches(entry, path: Path) -> bool:
    """``path``'s content is what ``entry`` recorded (size first, then the hash)."""
    try:
        if not path.is_file() or path.is_symlink():
            return False
        if isinstance(entry, dict):
            return entry.get("size") == path.stat().st_size and entry.get("sha256") == _sha256(path)
        if isinstance(entry, list):   # a manifest of 0.x: size and modification time as written
            st = path.stat()
            return entry == [st.st_size, st.st_mtime_ns]
    except OSError:
        return False
    return False


def _entry_of(path: Path):
    """(the manifest entry naming ``path``, the folder holding that manifest), or (None, None)."""
    for folder in list(path.parents)[:_MANIFEST_LOOKUP_DEPTH]:
        files = _manifest(folder)
        key = path.relative_to(folder).as_posix()
        if key in files:
            return files[key], folder
    return None, None


def is_ours(path: Path) -> bool:
    """True if ``path`` is a file strainwave wrote and nobody changed since (a manifest's hash says so)."""
    entry, _ = _entry_of(Path(path))
    return entry is not None and _matches(entry, Path(path))


def _write_manifest(folder: Path, files: dict) -> None:
    from strainwave.io_atomic import atomic_write_text
    atomic_write_text(folder / MANIFEST, json.dumps({"written_by": "strainwave", "files": files}, indent=1) + "\n")


_WRITTEN: set[Path] = set()   # every file this process renamed into place: never a previous run's to remove


def record_written(paths: list[Path]) -> None:
    """Add ``paths`` (just written) to their folders' manifests, each under its folder's lock."""
    by_folder: dict[Path, list[Path]] = {}
    _WRITTEN.update(paths)
    for p in paths:
        by_folder.setdefault(p.parent, []).append(p)
    for folder, members in by_folder.items():
        with folder_lock(folder, wait=True):
            files = _manifest(folder)
            files.update({p.name: _record(p) for p in members if p.is_file()})
            _write_manifest(folder, files)


# ---- one run per folder ----------------------------------------------------------------------------------

_HELD: dict[Path, int] = {}   # folder -> descriptor this process locks it with (a lock taken twice is held once)


@contextmanager
def folder_lock(folder: Path, *, wait: bool, flag: str = "--out") -> Iterator[None]:
    """An exclusive lock on ``folder`` (flock on the folder itself: no file left behind; the kernel drops it
    when the process dies). ``wait`` False: a folder another run holds is refused in one line."""
    folder = Path(os.path.realpath(folder))
    if folder in _HELD:
        yield
        return
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            raise InputError(flag, str(folder), "another strainwave run is writing into this folder; wait for "
                                                "it to finish or choose another folder") from None
        _HELD[folder] = fd
        try:
            yield
        finally:
            del _HELD[folder]
    finally:
        os.close(fd)


# ---- temporary folders owned by record ------------------------------------------------------------------

def _start_time(pid: int) -> str | None:
    """The process's start time in clock ticks since boot (/proc/PID/stat field 22): a reused PID differs."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text.rsplit(")", 1)[-1].split()[19]


def make_owned_dir(prefix: str, dir: Path | str | None = None) -> Path:
    """A new temporary folder (``tempfile.mkdtemp``) holding its owner record, so a later run may remove it
    once this process is gone, and nobody else's folder of a similar name."""
    folder = Path(tempfile.mkdtemp(prefix=prefix, dir=dir))
    record = {"written_by": "strainwave", "pid": os.getpid(), "start": _start_time(os.getpid())}
    (folder / OWNER).write_text(json.dumps(record), encoding="utf-8")
    return folder


def _owner_gone(folder: Path) -> bool:
    """True if ``folder`` holds an owner record of a strainwave process that is no longer running."""
    try:
        record = json.loads((folder / OWNER).read_text(encoding="utf-8"))
        pid, start = int(record["pid"]), record.get("start")
    except (OSError, ValueError, KeyError, TypeError):
        return False   # no record: not ours, whatever its name
    if record.get("written_by") != "strainwave" or pid == os.getpid():
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except PermissionError:   # someone else's process: alive
        return False
    return start is not None and _start_time(pid) not in (None, start)   # the PID was reused


def remove_stale(folder: Path | str) -> int:
    """Remove the temporary folders of killed strainwave runs in ``folder`` (each known by its owner record,
    never by its name alone); returns how many."""
    removed = 0
    try:
        entries = list(Path(folder).iterdir())
    except OSError:
        return 0
    for entry in entries:
        if entry.is_dir() and not entry.is_symlink() and entry.name.lstrip(".").startswith("strainwave-") \
                and _owner_gone(entry):
            shutil.rmtree(entry, ignore_errors=True)
            removed += 1
    return removed


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
        if made and not [p for p in folder.iterdir() if p.name != MANIFEST and not _owned_temp(p)]:
            (folder / MANIFEST).unlink(missing_ok=True)


def _owned_temp(path: Path) -> bool:
    return path.is_dir() and (path / OWNER).is_file()


# ---- checks before any work ------------------------------------------------------------------------------

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
    if not target.is_dir() or force:
        return
    if not (target / MANIFEST).is_file():
        if any(p for p in target.iterdir() if not _owned_temp(p)):
            raise InputError(out.flag, out.path, "is a folder with files strainwave did not write; name an empty "
                                                 "or new folder, or pass --force to write into it")
        return
    files = _manifest(target)
    for name, entry in sorted(files.items()):   # a file of ours the user edited since: the run would replace it
        path = target / name
        if path.exists() and not _matches(entry, path):
            raise InputError(out.flag, out.path, f"holds {name}, changed since strainwave wrote it; the run "
                                                 f"would replace it: move it away or pass --force")
    for name in out.writes:   # a file the user put where the run writes its index
        path = target / name
        if path.is_file() and name not in files and path.stat().st_size > 0:
            raise InputError(out.flag, out.path, f"holds {name}, which strainwave did not write (or an earlier "
                                                 f"version wrote without listing it); the run would replace it: "
                                                 f"move it away or pass --force")


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


# ---- staging ---------------------------------------------------------------------------------------------

# staging folder -> the folder its files go to, while it is staged; _NAMES keeps every pair of the process, so a
# message printed after a failure removed the stage (a full disk) still names where the files were going
_STAGED: dict[str, str] = {}
_NAMES: dict[str, str] = {}
_TEMP = re.compile(r"^\..+\.[0-9a-f]{12}(\.[^.]*)?\.tmp$")


def target_of(path: str) -> str:
    """The output a staged or temporary path stands for: its staging folder replaced by the folder its files go
    to, a writer's temporary name (``.NAME.<12 hex>.SUFFIX.tmp``, io_atomic) by NAME."""
    text = unstage_text(str(path))
    head, _, name = text.rpartition("/")
    m = re.match(r"^\.(.+)\.[0-9a-f]{12}(\.[^.]*)?\.tmp$", name)
    return f"{head}/{m.group(1)}" if m and head else (m.group(1) if m else text)


def unstage_text(text: str) -> str:
    """``text`` with each staging folder replaced by the folder its files go to."""
    for stage, final in {**_NAMES, **_STAGED}.items():
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
            stages[final.parent] = make_owned_dir(f"{STAGE_PREFIX}{os.getpid()}-", final.parent)
            _STAGED[str(stages[final.parent])] = _NAMES[str(stages[final.parent])] = str(final.parent)
        setattr(args, name, str(stages[final.parent] / final.name))
    try:
        yield
        written = []
        for parent, stage in stages.items():
            with folder_lock(parent, wait=True):
                for staged_file in sorted(stage.iterdir()):
                    if staged_file.is_file() and staged_file.name != OWNER and not _TEMP.match(staged_file.name):
                        os.replace(staged_file, parent / staged_file.name)
                        written.append(parent / staged_file.name)
        record_written(written)
    finally:
        for stage in stages.values():
            shutil.rmtree(stage, ignore_errors=True)
            _STAGED.pop(str(stage), None)


def _staged_files(stage: Path) -> list[Path]:
    """Every file the run wrote in ``stage``, relative to it (not the shared cache, not temporaries)."""
    out = []
    for root, dirs, files in os.walk(stage):
        dirs[:] = [d for d in dirs if not (Path(root) / d).is_symlink() and not d.startswith(".")]
        for name in files:
            path = Path(root) / name
            if name != OWNER and not _TEMP.match(name) and not path.is_symlink():
                out.append(path.relative_to(stage))
    return out


def _commit_run(stage: Path, final: Path, index: tuple[str, ...], force: bool, flag: str, old: dict) -> None:
    """Rename the run's files from ``stage`` into ``final`` (its index files last), remove the previous run's
    files (``old``, the manifest as the run found it) this one did not write while they are still as written, and
    record the new set in the manifest, beside what the run's single-file outputs added to it meanwhile."""
    new = _staged_files(stage)
    for rel in new:   # refused before anything moves: the previous set stays complete
        dest = final / rel
        if dest.is_file() and dest.stat().st_size > 0 and not force and not _matches(old.get(rel.as_posix()), dest):
            raise InputError(flag, str(final), f"holds {rel.as_posix()}, which strainwave did not write (or which "
                                               f"was changed since); move it away or pass --force")
    new.sort(key=lambda rel: rel.as_posix() in index)
    with _signals_deferred():
        records = {}
        for rel in new:
            (final / rel).parent.mkdir(parents=True, exist_ok=True)
            records[rel.as_posix()] = _record(stage / rel)
            os.replace(stage / rel, final / rel)
        for name, entry in old.items():   # the previous run's files, unless the user changed them since
            path = final / name
            if name not in records and path not in _WRITTEN and _matches(entry, path):
                path.unlink()
                _prune_empty(path.parent, final)
        added = {k: v for k, v in _manifest(final).items()   # the run's --json FILE, written beside it meanwhile
                 if k not in records and (k not in old or final / k in _WRITTEN)}
        _write_manifest(final, {**added, **records})


@contextmanager
def _signals_deferred() -> Iterator[None]:
    """SIGINT and SIGTERM held while a run's files are renamed into place, then acted on: the set is whole."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    saved = {s: signal.signal(s, lambda signum, frame: received.append(signum)) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in saved.items():
            signal.signal(s, handler)
    for signum in received[:1]:
        handler = saved[signum]
        if callable(handler):
            handler(signum, None)
        elif handler == signal.SIG_DFL:
            signal.raise_signal(signum)


def _prune_empty(folder: Path, top: Path) -> None:
    while folder != top and top in folder.parents:
        try:
            folder.rmdir()
        except OSError:
            return
        folder = folder.parent


@contextmanager
def staged_run(args, *, force: bool, index: tuple[str, ...] = (), flag: str = "--out") -> Iterator[None]:
    """The whole run of an --out command into one staging folder inside it (``args.out`` points there while
    the block runs; its ``cache`` is the folder's own); committed at the end (``_commit_run``), removed on
    any exception, so an interrupted run leaves the previous complete set."""
    final = Path(os.path.realpath(os.path.abspath(args.out)))
    final.mkdir(parents=True, exist_ok=True)
    cache = final / "cache"
    made_cache = not cache.exists()
    cache.mkdir(exist_ok=True)
    stage = make_owned_dir(f"{STAGE_PREFIX}{os.getpid()}-", final)
    before = _manifest(final)
    os.symlink(os.path.join("..", "cache"), stage / "cache")   # finished cases are kept even if the run stops
    _STAGED[str(stage)] = _NAMES[str(stage)] = str(final)
    saved = args.out
    args.out = str(stage)
    try:
        yield
        _commit_run(stage, final, index, force, flag, before)
    finally:
        args.out = saved
        _STAGED.pop(str(stage), None)
        shutil.rmtree(stage, ignore_errors=True)
        if made_cache:   # a run refused before it computed anything leaves no empty cache behind
            try:
                cache.rmdir()
            except OSError:
                pass


def reuse_output(recorded: str | Path) -> Path | None:
    """A file an earlier run wrote (its path as that run recorded it, perhaps inside its since-removed
    staging folder) made available where this run writes it: linked into this run's staging folder when it
    is still strainwave's and unchanged, with the files written beside it (NAME.* : NAME.boundary.vtu).
    None when it is gone or was changed."""
    path = Path(recorded)
    final = Path(*[part for part in path.parts if not part.startswith(STAGE_PREFIX)])
    for stage, final_dir in sorted(_STAGED.items(), key=lambda kv: -len(kv[1])):
        try:
            rel = final.relative_to(final_dir)
        except ValueError:
            continue
        target = Path(stage) / rel
        if target.is_file():
            return target
        if not (final.is_file() and is_ours(final)):
            return None
        for companion in [final, *final.parent.glob(f"{glob.escape(final.stem)}.*")]:
            if companion == final or (companion.is_file() and is_ours(companion)):
                _link(companion, Path(stage) / companion.relative_to(final_dir))
        return target
    return path if path.is_file() else None


def _link(source: Path, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    if target.exists():
        return
    try:
        os.link(source, target)
    except OSError:   # another file system, or one without hard links
        shutil.copy2(source, target)
