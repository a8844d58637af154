"""The one way a user's file is read: a regular file only, a bounded read, a bounded sniff, a printable message.

A FIFO with no writer blocks ``open()`` forever, a device never ends, and a path can loop or exceed the
kernel's name limits; each is refused here (InputError, exit 2, one line) before a byte is read. Every
message strainwave prints goes through ``printable`` so text from a file (a TOML key holding terminal
control codes) cannot clear the screen or split the one error line.
"""
from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from strainwave.errors import InputError

__all__ = ["printable", "read_regular", "sniff_sample", "SNIFF_CHARS"]

# csv.Sniffer's regexes are quadratic in the sample; a delimiter shows within the header row and a few data rows,
# so it sees at most this many characters.
SNIFF_CHARS = 2048


def printable(text: str) -> str:
    """``text`` with every non-printable character (control codes, line breaks, bidi marks) escaped as
    ``\\xNN`` / ``\\uNNNN``, so a message stays one inert terminal line."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


def _path_error(exc: OSError) -> str:
    if exc.errno == errno.ELOOP:
        return "a symbolic link loop"
    if exc.errno == errno.ENAMETOOLONG:
        return "a file name or path longer than the system allows"
    return exc.strerror or str(exc)


def read_regular(path: Path | str, limit: int, what: str) -> bytes:
    """The bytes of ``path``, refused (InputError naming ``what``) unless it is a readable regular file of at
    most ``limit`` bytes. A FIFO, socket or device is refused from ``stat`` alone, never opened; the file is
    opened non-blocking and checked again on its descriptor, so a swap after the check cannot block."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise InputError(what, str(path), "is not a regular file (a FIFO, device, socket or folder); name a file")
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_NOCTTY", 0))
    except InputError:
        raise
    except OSError as exc:
        raise InputError(what, str(path), f"cannot read file ({_path_error(exc)})") from None
    except ValueError as exc:   # an embedded NUL in the path
        raise InputError(what, repr(str(path)), f"not a usable path ({exc})") from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise InputError(what, str(path), "is not a regular file; name a file")
        if os.fstat(fd).st_size > limit:
            raise InputError(what, str(path), f"larger than the {limit // 1024} KiB a file of this kind may have")
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise InputError(what, str(path), f"cannot read file ({_path_error(exc)})") from None
    finally:
        os.close(fd)
    if size > limit:
        raise InputError(what, str(path), f"larger than the {limit // 1024} KiB a file of this kind may have")
    return b"".join(chunks)


def sniff_sample(lines: list[str]) -> str:
    """At most ``SNIFF_CHARS`` characters of ``lines`` joined by newlines, for csv.Sniffer."""
    out, used = [], 0
    for line in lines:
        if used >= SNIFF_CHARS:
            break
        out.append(line[:SNIFF_CHARS - used])
        used += len(out[-1]) + 1
    return "\n".join(out)
