"""Shared test set-up: one BLAS thread per process (2-core machine), off-screen rendering only."""
import importlib.util
import os
import signal
import sys
import warnings
from contextlib import contextmanager
from pathlib import Path

import pytest

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# A run started in the background of a non-interactive shell (`make test &`, nohup, some CI runners) inherits
# SIGINT ignored (POSIX), and an ignored signal stays ignored across exec: the interrupt tests, and the CLI
# processes they signal, would then never see the Ctrl-C they test (3 failures on such a run). The suite tests
# what an interactive user gets, so it restores Python's handler; its children then start with SIGINT default.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

STRAINWAVE = str(Path(sys.executable).with_name("strainwave"))


@pytest.fixture(scope="module")
def params():
    """The embedded default parameters. Its RangeWarnings are the seeds' own examples outside their recommended
    ranges (tested in test_params*.py); a module that tests them defines its own ``params``."""
    from strainwave.errors import RangeWarning
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        return load_params()


@pytest.fixture
def strainwave_cmd():
    """The installed console script, run in a subprocess exactly as a user runs it."""
    return [STRAINWAVE]


BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"


@contextmanager
def benchmark_module(name: str):
    """A script of benchmarks/ (scripts, not a package) imported as a module for the test's duration;
    registered in sys.modules while loaded because its dataclasses look their module up there."""
    spec = importlib.util.spec_from_file_location(name, BENCHMARKS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        sys.modules.pop(spec.name, None)


@pytest.fixture(autouse=True)
def _python_signal_dispositions():
    """Every test starts and ends with Python's own SIGINT and SIGPIPE dispositions, set in the kernel: a native
    library (gmsh.initialize resets both to their default actions behind Python's back, so signal.getsignal
    cannot tell) or a test that changes one must not let a later signal kill the run."""
    _resync_signals()
    yield
    _resync_signals()


def _resync_signals() -> None:
    handler = signal.getsignal(signal.SIGINT)
    signal.signal(signal.SIGINT, signal.default_int_handler if handler in (signal.SIG_DFL, None) else handler)
    signal.signal(signal.SIGPIPE, signal.SIG_IGN)
