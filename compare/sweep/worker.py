"""What the workers of the sweep's own LocalCluster do as they start and as they stop.

A worker's first point is nearly all imports, and a process exiting with build123d loaded spends long
collecting its heap (docs/decisions/013-sweep-worker-start-up.md).
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
    ending, and that collection was most of its exit's cost.
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
