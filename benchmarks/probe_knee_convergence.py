"""The tooth-mesh study's knees (K1, K2, K3, T1, T2) against the history's step and the reader's grid (decision 073).

Builds the study's systems on its finest validate mesh (all WG angles, as `make validate` does), solves the headline
angle's loop on 40 / 80 / 160 steps a leg, and reads it three ways: the old reading (the reader on the history's
steps, raw twist), the raw exact loop on ever finer reading grids (where today's reading goes in the limit), and
the adopted one (the exact loop with the dead band taken out, on 200 / 400 / 800 torques a leg).

    python benchmarks/probe_knee_convergence.py [PARAMS] [--cache DIR]
"""
from __future__ import annotations

import argparse
import os
import pickle
import time
from pathlib import Path

import numpy as np

KEYS = ("K1", "K2", "K3", "T1", "T2")


def headline(params_file: str | None, cache: Path | None, kind: str = "system"):
    """The study's headline-angle contact system (``kind``: "system", the torque-only MeshSystem, or "bands", the
    true-slip BandSystem) and the rated torque, on the finest validate mesh (cached: ~10 CPU-s)."""
    f = cache / f"{kind}_{Path(params_file).stem if params_file else 'default'}.pkl" if cache else None
    if f is not None and f.exists():
        return pickle.loads(f.read_bytes())
    from strainwave.analytic.mesh_engagement import study_loads
    from strainwave.fea import tooth_mesh as tm
    from strainwave.params import load_params
    params = load_params(params_file)
    mesh = study_loads(params, quick=False)["mesh"]
    mesh["angles"] = mesh["angles"][:1]
    infl, _ = tm.influences(params, mesh, tm.refinements(params.flexspline_cup.module_mm, False)[0])
    build = tm.systems if kind == "system" else tm.band_systems
    out = (build(infl, mesh)[0], float(mesh["rated_torque_Nmm"]))
    if f is not None:
        f.write_bytes(pickle.dumps(out))
    return out


def table(params_file: str | None, cache: Path | None) -> None:
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_contact import solve_torque_path, torque_history
    system, rated = headline(params_file, cache)
    print(f"# {params_file or 'default'}  rated {rated:.6g} N mm  dead band {system and tm_band(system)} rad  "
          f"load {os.getloadavg()[0]:.2f}")
    print("| reading | steps a leg | grid a leg | " + " | ".join(KEYS) + " | CPU-s |")
    for steps in (40, 80, 160):
        t0 = time.process_time()
        path = solve_torque_path(system, torque_history(rated, steps))
        t1 = time.process_time()
        rows = [("old: steps, raw", "-", tm.read_knees(path.torque_Nmm, path.twist_rad, rated))]
        for n in (400, 1600):
            T, th = tm.resampled_loop(_raw(path), n)
            rows.append(("exact loop, raw", n, tm.read_knees(T, th, rated)))
        for n in (200, 400, 800):
            rows.append(("exact loop, dead band out", n, tm.knee_values(path, rated, n)))
        for name, n, v in rows:
            print(f"| {name} | {steps} | {n} | " + " | ".join(f"{v[k]:.6g}" for k in KEYS)
                  + f" | {t1 - t0:.2f} |")
        print(f"| (knots) | {steps} | | {len(path.knots)} knots, {len(path.torque_Nmm)} steps | | | | | |")


def tm_band(system):
    from strainwave.fea.mesh_contact import dead_band
    return tuple(round(x, 9) for x in dead_band(system))


def _raw(path):
    """The same path with its dead band zeroed: the reading sees the raw twist."""
    from dataclasses import replace
    return replace(path, dead_band_rad=(0.0, 0.0))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("params", nargs="?", default=None)
    ap.add_argument("--cache", default=None, help="a folder to keep the built system in between runs")
    a = ap.parse_args(argv)
    table(a.params, Path(a.cache) if a.cache else None)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
