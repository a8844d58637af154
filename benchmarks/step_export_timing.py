"""Seconds per part of validate's background STEP export (build, STEP, face index, preview), as validate runs it.

One process exports every part in validate's order, so the first part also pays the imports (build123d,
OCP, gmsh, pyvista), as the background process does. Run it in two checkouts in turn to compare them:

    OMP_NUM_THREADS=1 nice -n 10 .venv/bin/python benchmarks/step_export_timing.py [--params second_gear.toml]
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import warnings
from pathlib import Path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--params", metavar="FILE.toml", help="parameter file (default: the embedded default gear)")
    ap.add_argument("--out", metavar="DIR", help="keep the files here (default: a temporary folder)")
    args = ap.parse_args(argv)

    from strainwave.compare.validate.step_export import PREVIEWED, export_one
    from strainwave.geometry.part import PartName
    from strainwave.params import load_params

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params(args.params) if args.params else load_params()
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out or tmp)
        out.mkdir(parents=True, exist_ok=True)
        for part in (p.value for p in PartName):
            png = out / f"{part}_preview.png" if part in PREVIEWED else None
            _, seconds, error = export_one(part, params, out / f"{part}.step", png)
            print(json.dumps({"part": part, "seconds": round(seconds, 2), "error": error}), flush=True)
            if error:
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
