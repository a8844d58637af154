"""Shared test set-up: one BLAS thread per process (2-core machine), off-screen rendering only."""
import os
import sys
from pathlib import Path

import pytest

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

STRAINWAVE = str(Path(sys.executable).with_name("strainwave"))


@pytest.fixture
def strainwave_cmd():
    """The installed console script, run in a subprocess exactly as a user runs it."""
    return [STRAINWAVE]
