"""compare/validate/image_workers.run_tasks: the pictures shared by this process and a forked worker come back as
typed records in the order asked for; a worker that dies leaves its tasks reported, never lost or hung."""
from __future__ import annotations

import os
import time

from strainwave.compare.validate.image_workers import run_tasks


def test_both_processes_draw_and_the_records_come_back_in_order():
    parent = os.getpid()

    def one(k):
        time.sleep(0.1)
        return {"k": k, "by_worker": os.getpid() != parent}
    checks = []
    out = run_tasks(20, one, lambda: checks.append(1), lambda k, why: {"k": k, "died": why})
    assert [r["k"] for r in out] == list(range(20))
    assert any(r["by_worker"] for r in out) and not all(r["by_worker"] for r in out)
    assert len(checks) >= sum(not r["by_worker"] for r in out)     # a checkpoint before each task here


def test_a_worker_that_dies_leaves_its_task_reported():
    parent = os.getpid()

    def one(k):
        if os.getpid() != parent:
            os._exit(3)
        time.sleep(0.05)
        return k
    out = run_tasks(6, one, lambda: None, lambda k, why: why)
    died = [r for r in out if isinstance(r, str)]
    assert len(died) == 1 and "exit code 3" in died[0]
    assert all(r == k for k, r in enumerate(out) if not isinstance(r, str))
