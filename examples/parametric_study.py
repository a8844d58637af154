"""A parametric study in a few lines: the output shaft's torsional flexibility against its outer diameter,
FEA (with its GCI) beside the Saint-Venant closed form 32 L / (pi G (d^4 - d_i^4)).

    python examples/parametric_study.py [--diameters-mm 60,70,80] [--quick]
"""
import argparse
import math
import warnings

import strainwave as sw
from strainwave.errors import MaterialWarning


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--diameters-mm", default="60,70,80", help="outer diameters to solve, comma-separated")
    parser.add_argument("--mesh-size-mm", type=float, default=None, help="finest element size (default: the study's)")
    parser.add_argument("--order", type=int, default=2, choices=(1, 2), help="element order")
    args = parser.parse_args()
    base = sw.load_params()   # its warnings (the seed's material) print here, once, before the table
    print(f"strainwave {sw.__version__}")
    print(f"{'d (mm)':>7} {'FEA (rad/N mm)':>15} {'GCI':>7} {'closed form':>12} {'FEA/closed - 1':>15}")
    for d in (float(x) for x in args.diameters_mm.split(",")):
        with warnings.catch_warnings():   # the material warning above, not once per row (the material is unchanged)
            warnings.simplefilter("ignore", MaterialWarning)
            params = base.with_value("output_shaft.outer_diameter_mm", d)
        result = sw.run_study("shaft-torsion", params, quick=True, mesh_size_mm=args.mesh_size_mm, order=args.order)
        q = result["flexibility_rad_per_Nmm"]
        shaft, material = params.output_shaft, params.material
        shear_MPa = material.youngs_modulus_MPa / (2 * (1 + material.poisson_ratio))
        exact = 32 * shaft.length_mm / (math.pi * shear_MPa * (d ** 4 - shaft.inner_diameter_mm ** 4))
        gci = q.convergence.gci_fine if q.convergence else float("nan")
        print(f"{d:7.4g} {q.value:15.6g} {100 * gci:6.2g}% {exact:12.6g} {q.value / exact - 1:+15.2e}")


if __name__ == "__main__":
    main()
