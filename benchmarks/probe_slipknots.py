"""The tooth-mesh study's true-slip loop against the history's step, before and after decision 078-slipknots48.

Builds the headline angle's band systems on the study's finest validate mesh (cached with --cache), solves
`mesh_friction.torque_path` on 40 and 80 history steps a leg: before, 4 increments a step (decision
073-slipstudy48) with the increments' ends as knots (``exact=False``); after, every state change split out on
`tooth_mesh.INCREMENTS` increments a step (decision 078); and
prints the study's readings (K1, K2, K3, T1, T2, lost motion, friction's work per cycle), the CPU-s and the load.

    python benchmarks/probe_slipknots.py [PARAMS] [--cache DIR]
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))   # the sibling probe's system builder

KEYS = ("K1_Nmm_per_rad", "K2_Nmm_per_rad", "K3_Nmm_per_rad", "T1_Nmm", "T2_Nmm", "lost_motion_arcmin",
        "friction_loss_per_cycle_Nmm")


def headline_bands(params_file: str | None, cache: Path | None):
    """The headline angle's BandSystem and rated torque on the finest validate mesh (cached)."""
    from probe_knee_convergence import headline
    return headline(params_file, cache, "bands")


def table(params_file: str | None, cache: Path | None) -> None:
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import torque_history
    from strainwave.fea.mesh_friction import torque_path
    bands, rated = headline_bands(params_file, cache)
    print(f"# {params_file or 'default'}  rated {rated:.6g} N mm  mu {bands.friction_coefficient}  "
          f"load {os.getloadavg()[0]:.2f}")
    print("| knots | steps a leg | " + " | ".join(KEYS) + " | knots | CPU-s |")
    rows = {}
    for exact in (False, True):
        for steps in (40, 80):
            t0 = time.process_time()
            path = torque_path(bands, torque_history(rated, steps), tm.INCREMENTS if exact else 4, exact=exact)[0]
            cpu = time.process_time() - t0
            v = tm.loop_values([path], rated)
            rows[exact, steps] = v
            print(f"| {'exact' if exact else 'ends'} | {steps} | " + " | ".join(f"{v[k]:.6g}" for k in KEYS)
                  + f" | {len(path.knots)} | {cpu:.2f} |")
        a, b = rows[exact, 40], rows[exact, 80]
        print(f"| {'exact' if exact else 'ends'} | 40->80 rel | "
              + " | ".join(f"{(b[k] - a[k]) / abs(a[k]):+.2e}" for k in KEYS) + " | | |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("params", nargs="?", default=None)
    ap.add_argument("--cache", default=None, help="a folder to keep the built band system in between runs")
    a = ap.parse_args(argv)
    table(a.params, Path(a.cache) if a.cache else None)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
