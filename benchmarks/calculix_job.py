"""CalculiX (``ccx``) on strainwave's own shaft-torsion problem: the same curved P2 mesh, supports and load.

Used by ``bench_calculix.py`` and ``tests/test_calculix.py``. The job is the discrete problem strainwave
solves, not a re-modelled one: gmsh's tet10 nodes (geometry-following mid nodes) become C3D10 elements,
the ``fixed`` face's nodes are clamped, and the Saint-Venant end shear enters as strainwave's own
consistent nodal forces (``*CLOAD``), since CalculiX has no distributed tangential traction keyword.
Both programs integrate C3D10 / P2 stiffness with the same 4-point rule (a = 0.1381966, w = 1/24), so
the two stiffness matrices agree to round-off and the two flexibilities differ only by the solvers'
tolerances. The flexibility of a CalculiX result is computed with strainwave's own
``torsion_load.mean_rotation_rad`` from the displacements CalculiX prints for the loaded face's nodes.
"""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

# gmsh tet10 mid nodes: edges 01 12 20 30 32 31; CalculiX C3D10 (Abaqus): 01 12 20 03 13 23.
# The first four edges coincide; gmsh's 32 and 31 are CalculiX's 23 and 13, so slots 8 and 9 swap.
GMSH_TO_CCX_TET10 = np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])
# *STATIC solver names of CalculiX 2.20 (Debian's build has SPOOLES and its own iterative solvers)
# "read" is the same deck without the solve (*NO ANALYSIS): ccx reads and checks the input only, so
# total - read is what CalculiX spends assembling, solving and writing (it prints no phase times).
SOLVERS = {"spooles": "*STATIC, SOLVER=SPOOLES", "iterative": "*STATIC, SOLVER=ITERATIVE CHOLESKY",
           "read": "*NO ANALYSIS"}
# CalculiX reads each number from at most 20 characters (Fortran f20.0 on the field): "%.13e" is 14
# significant digits in 20 characters with the sign and a two-digit exponent; %.17g was cut and refused.
REAL = "%.13e"
APT_INSTALL = "apt-get update -qq && apt-get install -y -qq calculix-ccx"


def ensure_ccx(*, install: bool = True) -> str | None:
    """Path of ``ccx``; installs Debian's ``calculix-ccx`` when missing and this process is root with
    apt-get. None only when it is missing and cannot be installed here (not root, no apt-get, apt failed)."""
    found = shutil.which("ccx")
    if found or not install:
        return found
    if os.geteuid() != 0 or shutil.which("apt-get") is None:
        return None
    subprocess.run(["sh", "-c", APT_INSTALL], check=False, stdout=subprocess.DEVNULL,
                   env={**os.environ, "DEBIAN_FRONTEND": "noninteractive"})
    return shutil.which("ccx")


@dataclass(frozen=True)
class LoadedFace:
    """What the flexibility of a displacement field needs: the loaded face's quadrature and the torque."""

    nodes: np.ndarray      # (nf, 6) MeshData node indices of the loaded facets
    N: np.ndarray          # (nq, 6) facet shape functions at the quadrature points
    x: np.ndarray          # (nf, nq, 3) quadrature points, mm
    dA: np.ndarray         # (nf, nq) weights x area, mm^2
    n_nodes: int
    torque_Nmm: float

    def save(self, path: Path) -> None:
        np.savez(path, nodes=self.nodes, N=self.N, x=self.x, dA=self.dA, n_nodes=self.n_nodes,
                 torque_Nmm=self.torque_Nmm)

    @classmethod
    def load(cls, path: Path) -> "LoadedFace":
        z = np.load(path)
        return cls(z["nodes"], z["N"], z["x"], z["dA"], int(z["n_nodes"]), float(z["torque_Nmm"]))

    def flexibility(self, nodal_u_mm: np.ndarray) -> float:
        """twist / T with strainwave's own mean rotation of the loaded face (rad / (N mm))."""
        from strainwave.fea.surface import SurfaceQuadrature
        from strainwave.fea.torsion_load import mean_rotation_rad
        q = SurfaceQuadrature(self.nodes, self.N, self.x, self.dA)
        return mean_rotation_rad(_NodalField(q, nodal_u_mm), "loaded") / self.torque_Nmm


@dataclass(frozen=True)
class _NodalField:
    """The two things ``mean_rotation_rad`` reads from a solution, for a field that came from CalculiX."""

    quadrature: object
    u_mm: np.ndarray

    def surface(self, group: str):
        return self.quadrature

    def nodal_u(self) -> np.ndarray:
        return self.u_mm


def shaft_problem(params):
    """(part, E, nu, torque, traction) of the uncracked shaft-torsion study."""
    from strainwave.fea.torsion_load import saint_venant_traction
    from strainwave.geometry.parts import build_part
    sh = params.output_shaft
    J_mm4 = math.pi / 32.0 * (sh.outer_diameter_mm ** 4 - sh.inner_diameter_mm ** 4)
    T = params.gear.output_torque_Nmm
    part = build_part("output-shaft", params)
    return part, params.material.youngs_modulus_MPa, params.material.poisson_ratio, T, saint_venant_traction(T, J_mm4)


def nodal_load(md, traction) -> np.ndarray:
    """(N, 3) consistent nodal forces of the traction on ``loaded``, N per MeshData node (what strainwave
    assembles into its load vector, in MeshData numbering)."""
    from strainwave.fea.surface import SurfaceQuadrature
    n = md.nodes_mm.shape[0]
    identity = np.arange(n)
    return SurfaceQuadrature.of(md, "loaded").load_vector(traction, identity, 3, 3 * n).reshape(n, 3)


def loaded_face(md, torque_Nmm: float) -> LoadedFace:
    from strainwave.fea.surface import SurfaceQuadrature
    q = SurfaceQuadrature.of(md, "loaded")
    return LoadedFace(q.nodes, q.N, q.x, q.dA, md.nodes_mm.shape[0], torque_Nmm)


def mesh_signature(md) -> str:
    """Node and cell counts plus coordinate sums: equal for the mesh a job was written from and the mesh a
    timed strainwave run made (HXT in one thread is deterministic), so both programs solve the same mesh."""
    return f"{md.nodes_mm.shape[0]}:{md.cells.shape[0]}:{md.nodes_mm.sum():.9e}:{md.cells.sum()}"


def _block(lines: list[str], rows: np.ndarray, fmt: str) -> None:
    lines.extend(fmt % tuple(r) for r in rows.tolist())


def write_inp(path: Path, md, nodal_force_N: np.ndarray, *, youngs_modulus_MPa: float, poisson_ratio: float,
              solver: str) -> None:
    """The C3D10 job: nodes (ids = MeshData index + 1), elements in CalculiX order, ``fixed`` clamped,
    the nodal forces as *CLOAD, the step of ``solver`` (a key of SOLVERS), and the displacements
    of the loaded face's nodes printed to the .dat file."""
    if md.order != 2 or md.dim != 3:
        raise ValueError("write_inp: curved P2 tetrahedra (gmsh tet10) only")
    ids = np.arange(1, md.nodes_mm.shape[0] + 1)
    out = ["*HEADING", "strainwave shaft torsion, same mesh, supports and load", "*NODE, NSET=NALL"]
    _block(out, np.column_stack([ids, md.nodes_mm]), "%d," + ",".join([REAL] * 3))
    out.append("*ELEMENT, TYPE=C3D10, ELSET=EALL")
    conn = md.cells[:, GMSH_TO_CCX_TET10] + 1
    _block(out, np.column_stack([np.arange(1, conn.shape[0] + 1), conn]), ",".join(["%d"] * 11))
    for name, group in (("NFIXED", "fixed"), ("NLOADED", "loaded")):
        out.append(f"*NSET, NSET={name}")
        nodes = md.group_nodes(group) + 1
        pad = (-nodes.size) % 8
        _block(out, np.concatenate([nodes, np.full(pad, -1)]).reshape(-1, 8), ",".join(["%d"] * 8))
        if pad:   # the last line of an NSET holds fewer ids
            out[-1] = ",".join(str(v) for v in nodes[-(8 - pad):])
    out += ["*BOUNDARY", "NFIXED,1,3,0.",
            "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{youngs_modulus_MPa:.13e},{poisson_ratio:.13e}",
            "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL",
            "*STEP", SOLVERS[solver], "*CLOAD"]
    node, comp = np.nonzero(nodal_force_N)
    for n, c in zip(node.tolist(), comp.tolist()):
        out.append(f"{n + 1},{c + 1},{nodal_force_N[n, c]:.13e}")
    out += ["*NODE PRINT, NSET=NLOADED", "U", "*END STEP", ""]
    path.write_text("\n".join(out))


def read_dat_displacements(path: Path, n_nodes: int) -> np.ndarray:
    """(n_nodes, 3) displacements from the .dat file's ``displacements`` block (NaN where not printed)."""
    u = np.full((n_nodes, 3), np.nan)
    inside = False
    for line in path.read_text().splitlines():
        if line.strip().startswith("displacements"):
            inside = True
            continue
        if inside:
            parts = line.split()
            if len(parts) == 4 and re.fullmatch(r"\d+", parts[0]):
                u[int(parts[0]) - 1] = [float(p) for p in parts[1:]]
            elif parts:
                inside = False
    return u


@dataclass(frozen=True)
class Measured:
    wall_s: float
    peak_GB: float        # the program's own maximum resident set
    returncode: int


GNU_TIME = "/usr/bin/time"


def run_measured(cmd: list[str], *, cwd: Path, env: dict, stdout, timeout_s: float = 3600.0) -> Measured:
    """Run ``cmd`` under GNU time and return wall time and ITS peak RSS.

    Not os.wait4 on a child of this process: Linux keeps the pre-exec memory's high-water mark in the
    child's rusage, so a program started from a 0.7 GB Python read 0.67 GB for a 12k-dof ccx job. GNU
    time is a small process, so the program it forks starts from a few MB."""
    with open(cwd / ".peak", "w+") as peak:
        t0 = time.perf_counter()
        proc = subprocess.run([GNU_TIME, "-f", "%M", "-o", peak.name, *cmd], cwd=cwd, env=env, stdout=stdout,
                              stderr=subprocess.STDOUT, timeout=timeout_s)
        wall = time.perf_counter() - t0
    lines = (cwd / ".peak").read_text().split()
    kB = float(lines[-1]) if lines and lines[-1].isdigit() else float("nan")
    return Measured(wall, kB / 1e6, proc.returncode)


def ccx_env(threads: int) -> dict:
    return {**os.environ, "OMP_NUM_THREADS": str(threads), "CCX_NPROC_EQUATION_SOLVER": str(threads),
            "CCX_NPROC_STIFFNESS": str(threads), "CCX_NPROC_RESULTS": str(threads)}


def run_ccx(inp: Path, *, threads: int, ccx: str = "ccx", timeout_s: float = 3600.0) -> tuple[Measured, str]:
    """Run ``ccx -i JOB`` in the job's folder: (wall time and ccx's own peak RSS, its log)."""
    log_path = inp.with_suffix(".log")
    with open(log_path, "w") as log:
        run = run_measured([ccx, "-i", inp.stem], cwd=inp.parent, env=ccx_env(threads), stdout=log,
                           timeout_s=timeout_s)
    text = log_path.read_text(errors="replace")
    # ccx leaves a *NO ANALYSIS deck through its stop path: status 201, the same as after an *ERROR,
    # so only the log tells the two apart
    stopped = run.returncode == 201 and "No analysis was selected" in text
    if (run.returncode != 0 and not stopped) or "*ERROR" in text:
        raise RuntimeError(f"ccx {inp.name} failed (status {run.returncode}): {text[-800:]}")
    return run, text


def ccx_flexibility(job_dir: Path, job: str, face: LoadedFace) -> float:
    u = read_dat_displacements(job_dir / f"{job}.dat", face.n_nodes)
    if np.isnan(u[np.unique(face.nodes)]).any():
        raise RuntimeError(f"{job}.dat lacks displacements of loaded-face nodes")
    return face.flexibility(np.nan_to_num(u))
