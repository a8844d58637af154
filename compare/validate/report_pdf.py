"""report.pdf: report.html printed by headless Chromium (the browser the report tests drive), A4.

The page is self-contained (images embedded), so Chromium reads nothing but the one file; its print style
hides the interactive 3D canvases (a PDF cannot rotate them) and says where they are. Chromium runs with the
flags this machine needs (no sandbox as root, no background networking: the network is closed) and a fresh
profile folder inside the run's scratch.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from strainwave.io_atomic import atomic_path

__all__ = ["CHROMIUM_FLAGS", "PRINT_FLAGS", "chromium", "print_pdf", "PDF_TIMEOUT_S"]

CHROMIUM_CANDIDATES = ("/usr/bin/chromium", "chromium", "chromium-browser", "google-chrome")
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--no-pdf-header-footer")
# the print hides the WebGL canvases: without 3D APIs the page skips the software GL set-up and draws, same PDF
PRINT_FLAGS = ("--disable-3d-apis",)
PDF_TIMEOUT_S = 180.0


def chromium() -> str | None:
    """The headless browser that prints the report, or None when none is installed."""
    for name in CHROMIUM_CANDIDATES:
        found = shutil.which(name)
        if found:
            return found
    return None


def print_pdf(html: Path, pdf: Path, *, timeout_s: float = PDF_TIMEOUT_S) -> Path:
    """Print ``html`` to ``pdf`` (atomically). Raises RuntimeError with Chromium's last words on failure."""
    browser = chromium()
    if browser is None:
        raise RuntimeError("no Chromium found (Debian: apt-get install chromium)")
    # Chromium puts its singleton socket under TMPDIR: a deep output folder's scratch space passes the 108-byte
    # limit of a socket path and Chromium aborts, so its profile and TMPDIR sit in the system's short /tmp
    short = "/tmp" if os.path.isdir("/tmp") and os.access("/tmp", os.W_OK) else None
    with tempfile.TemporaryDirectory(prefix="strainwave-chromium-", dir=short) as profile, atomic_path(pdf) as tmp:
        cmd = [browser, *CHROMIUM_FLAGS, *PRINT_FLAGS, f"--user-data-dir={profile}", "--virtual-time-budget=5000",
               f"--print-to-pdf={tmp}", Path(html).resolve().as_uri()]
        env = {**os.environ, "TMPDIR": profile}
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout_s, stdin=subprocess.DEVNULL,
                                  env=env)
        except subprocess.TimeoutExpired:
            raise RuntimeError(f"Chromium did not print {html.name} within {timeout_s:g} s") from None
        if proc.returncode != 0 or not Path(tmp).exists() or Path(tmp).stat().st_size == 0:
            raise RuntimeError(f"Chromium exit {proc.returncode}: {proc.stderr.strip()[-300:]}")
    return Path(pdf)
