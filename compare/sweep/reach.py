"""Reach a Dask scheduler by address, or fail fast in one line: never a hang, never a giant allocation.

``distributed.Client(address)`` trusts the peer: a silent listener or an HTTP server make it wait for a
handshake that never comes, and a peer answering arbitrary bytes has its first 8 bytes read as a frame
length (``MemoryError: Unable to allocate 3.07 EiB``). So before the client connects, a plain socket
connects with a timeout and reads the scheduler's opening handshake with a bounded size and a deadline:
a Dask TCP comm starts with an 8-byte little-endian length of a small msgpack frame set naming its
``pickle-protocol``. Only then does the client connect, with its own connect timeout set in a
``dask.config.set`` context (no global configuration is changed).
"""
from __future__ import annotations

import socket
import struct
import time
from urllib.parse import urlsplit

from strainwave.errors import InputError

__all__ = ["CONNECT_TIMEOUT_S", "check_scheduler"]

CONNECT_TIMEOUT_S = 3.0          # TCP connect, handshake read and Client connect each; total stays < 10 s
MAX_HANDSHAKE_BYTES = 1 << 16    # a scheduler's handshake is ~100 bytes; anything bigger is not one
HANDSHAKE_MARK = b"pickle-protocol"


def _host_port(address: str) -> tuple[str, int]:
    parts = urlsplit(address)
    try:
        port = parts.port
    except ValueError:
        port = None
    if not parts.hostname or port is None:
        raise InputError("--scheduler", address, "no Dask scheduler answered: expected tcp://HOST:PORT")
    return parts.hostname, port


def _recv_exactly(sock: socket.socket, n: int, deadline: float) -> bytes:
    data = bytearray()
    while len(data) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError
        sock.settimeout(left)
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise ConnectionResetError("closed by the peer")
        data.extend(chunk)
    return bytes(data)


def check_scheduler(address: str, timeout_s: float = CONNECT_TIMEOUT_S) -> None:
    """Raise ``InputError`` (one line naming ``address``) unless a Dask scheduler's handshake arrives there
    within ``timeout_s`` for the connect and ``timeout_s`` for the handshake. ``tls://`` addresses are probed
    up to the connect (their handshake is the TLS one, made by the client with the user's credentials); any
    other scheme is refused here, before the sweep announces its work."""
    scheme = urlsplit(address).scheme
    if scheme not in ("tcp", "tls"):
        raise InputError("--scheduler", address, "no Dask scheduler answered: only tcp://HOST:PORT and tls://HOST:PORT "
                                                 "are allowed (docs/reliability.md: securing your own cluster)")
    host, port = _host_port(address)
    try:
        sock = socket.create_connection((host, port), timeout=timeout_s)
    except TimeoutError:
        raise InputError("--scheduler", address, f"no Dask scheduler answered: connect timed out after "
                         f"{timeout_s:g} s") from None
    except OSError as exc:
        reason = "nothing listening" if isinstance(exc, ConnectionRefusedError) else (exc.strerror or str(exc))
        raise InputError("--scheduler", address, f"no Dask scheduler answered: {reason}") from None
    if scheme == "tls":
        sock.close()
        return
    with sock:
        deadline = time.monotonic() + timeout_s
        try:
            (size,) = struct.unpack("<Q", _recv_exactly(sock, 8, deadline))
            if not 0 < size <= MAX_HANDSHAKE_BYTES:
                raise ValueError(f"its first 8 bytes announce {size} bytes")
            body = _recv_exactly(sock, size, deadline)
            if HANDSHAKE_MARK not in body:
                raise ValueError("its first message is no Dask handshake")
        except TimeoutError:
            raise InputError("--scheduler", address, f"not a Dask scheduler: connected, but no handshake within "
                             f"{timeout_s:g} s") from None
        except (OSError, ValueError) as exc:
            raise InputError("--scheduler", address, f"not a Dask scheduler: {exc}") from None
