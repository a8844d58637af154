"""CPU cost of the tooth-mesh study per gear as `make validate` runs it (issue 48: <= 30 CPU-s per gear).

Each gear runs in its own process; its CPU is the process's own plus its reaped children's (the gmsh
children of fea/session.mesh_in_child), read from ``resource.getrusage``. Prints the load average beside it:
on the shared 2-core machine the load says how far wall times are inflated (CPU much less so).

    python benchmarks/bench_tooth_mesh.py
"""
from __future__ import annotations

import json
import os
import resource
import subprocess
import sys

GEARS = (("default", None), ("second gear", "strainwave/data/second_gear.toml"))
GOAL_CPU_S = 30.0


def one(params_file: str | None) -> dict:
    import time
    from strainwave.fea.studies import run_study
    from strainwave.params import load_params
    t0 = time.perf_counter()
    r = run_study("tooth-mesh", load_params(params_file))
    wall = time.perf_counter() - t0
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime
    return {"cpu_s": cpu, "wall_s": wall, "dofs": r.mesh.dofs,
            "K3": r.quantities["K3_Nmm_per_rad"].value, "timings": r.timings_s}


def main() -> int:
    if len(sys.argv) > 2 and sys.argv[1] == "--one":
        print(json.dumps(one(None if sys.argv[2] == "-" else sys.argv[2])))
        return 0
    worst = 0.0
    for name, f in GEARS:
        out = subprocess.run([sys.executable, __file__, "--one", f or "-"], capture_output=True, text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        worst = max(worst, r["cpu_s"])
        print(f"tooth-mesh {name}: {r['cpu_s']:.1f} CPU-s (incl. gmsh children), {r['wall_s']:.1f} s wall, "
              f"{r['dofs']} dofs, load average {os.getloadavg()[0]:.2f}", flush=True)
    print(f"tooth-mesh CPU per gear {worst:.1f} s <= {GOAL_CPU_S:g} s: {'PASS' if worst <= GOAL_CPU_S else 'MISS'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
