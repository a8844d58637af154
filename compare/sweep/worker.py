"""What the workers of the sweep's own LocalCluster do as they start and as they stop.

Measured on the 16-point quick shaft sweep (benchmarks/bench_sweep.py, 2 shared cores): a worker's first
point cost ~2.9 s against ~0.3 s for the next ones, nearly all of it imports (build123d alone 2.4 s: OCP
1.0 s, scikit-learn 0.7 s), and closing the cluster took 1.0 s (1 worker) to 1.9 s (2 workers), because a
process exiting with build123d loaded spends 0.75 s collecting its heap.
"""
from __future__ import annotations

import gc
import importlib

from distributed import WorkerPlugin


class SweepWorker(WorkerPlugin):
    """Imports ``modules`` (``task.warm_modules``) as the worker starts; skips the heap's collection as it stops.

    The imports run before the worker registers, so they are part of starting the cluster, as they are
    on every worker anyway, instead of each worker's first point. ``gc.freeze()`` at teardown moves every
    object to the permanent generation, which the collection at interpreter exit skips: the process is
    ending, and that collection is what made its exit cost 0.75 s (0.06 s frozen).
    """

    name = "strainwave-sweep-worker"

    def __init__(self, modules: tuple[str, ...] = ()):
        self.modules = tuple(modules)

    def setup(self, worker=None) -> None:
        for module in self.modules:
            try:
                importlib.import_module(module)
            except Exception:  # noqa: BLE001 - a broken library fails the points that need it, each with its message
                pass

    def teardown(self, worker=None) -> None:
        gc.freeze()
