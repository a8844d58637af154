"""A validate case process runs every thread pool in one thread: two cases share the two cores."""
import json
import os
import subprocess
import sys

PROBE = """
import json, numpy
from threadpoolctl import threadpool_info
from strainwave.compare.validate.isolated import one_thread_per_case
before = {i["internal_api"]: i["num_threads"] for i in threadpool_info()}
one_thread_per_case()
after = {i["internal_api"]: i["num_threads"] for i in threadpool_info()}
print(json.dumps([before, after]))
"""


def _pools(env_extra: dict) -> tuple[dict, dict]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}
    env.update(env_extra)
    out = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, check=True)
    before, after = json.loads(out.stdout.strip().splitlines()[-1])
    return before, after


def test_a_case_limits_openblas_to_one_thread():
    before, after = _pools({})
    assert after.get("openblas") == 1 and os.environ.get("MKL_NUM_THREADS", "1") == "1"
    if (os.cpu_count() or 1) > 1:
        assert before.get("openblas", 1) > 1      # the pool it limits was wider: the call did the work


def test_a_users_thread_setting_is_kept():
    _, after = _pools({"OPENBLAS_NUM_THREADS": "2"})
    assert after.get("openblas") == min(2, os.cpu_count() or 1) or after.get("openblas") == 2
