"""CalculiX on strainwave's OWN discrete contact problem: each flank's contact as strainwave's band.

benchmarks/mesh_ccx_job.py puts a rigid flat punch on the flank: a geometric contact, a different discrete problem
from strainwave's (a unit parabolic pressure band per flank, its work-conjugate displacement the gap's). Here
CalculiX is handed strainwave's band itself (decision 070-ccx2pct48): per flank pair a reference node R at the
contact point whose displacement is, by *EQUATION,

    u_R = -n (f . u) + t (g . u)        f: strainwave's unit band load (fe.flank_loads), g: the same band turned
                                        to the flank's tangent t (unit resultant along +t)

so a force -N n + Q t on R reaches the tooth as N f + Q g: the band's pressure and, from friction, the band's
tangential traction. R touches its rigid punch (node-to-surface, penalty, *FRICTION): the normal gap is exactly
strainwave's (clearance - lever theta + C F), and the slip is R's TRUE relative slip against the punch's rigid
slide. Frictionless, the two codes solve one discrete problem; with friction, what differs is strainwave's friction
model (a torque mu |slide| F along the kinematic slide, no tangential load on the teeth).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import mesh_ccx_job as mj

EQ_DROP = 1e-12        # a band weight below this (relative to the largest) is no term of R's equation


def band_vectors(problem: mj.Problem, module_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """(f, g): strainwave's unit normal band loads of the pairs (columns, interleaved x/y dofs of the sector's
    P2 nodes) and the same bands as tangential tractions along +t (each column's resultant a unit +t)."""
    from strainwave.fea.mesh_friction import turned_bands
    side = problem.side if problem.side is not None else np.ones(problem.teeth.size, int)
    F = mj.band_loads(problem.model, problem.teeth, problem.radius_mm, 0.2 * module_mm, side)
    return F, turned_bands(F, _tangent(problem))


def _tangent(problem: mj.Problem) -> np.ndarray:
    return np.column_stack([-problem.normal[:, 1], problem.normal[:, 0]])


def band_system(problem: mj.Problem, module_mm: float, *, friction: bool = True):
    """strainwave's true-slip system of the problem: the band flexibility [[Cff, Cfg], [Cgf, Cgg]] of the
    sector's FE, the levers and the punches' slide at their faces ((P + c n) x t per unit twist)."""
    from strainwave.fea import tooth_mesh_fe as fe
    from strainwave.fea.mesh_friction import BandSystem
    F, G = band_vectors(problem, module_mm)
    flex = fe.compliance(problem.model, np.column_stack([F, G]))
    face = problem.point_mm + problem.clearance_mm[:, None] * problem.normal
    t = _tangent(problem)
    w = face[:, 0] * t[:, 1] - face[:, 1] * t[:, 0]
    mu = problem.system.friction_coefficient if friction else 0.0
    return BandSystem(problem.clearance_mm, flex, problem.system.lever_mm, w, mu)


def strainwave_true_slip(problem: mj.Problem, module_mm: float, torque_Nmm: float, *, unload_to: float = 0.5,
                         friction: bool = True, increments: int = 20) -> dict:
    """strainwave's true-slip solve (fea/mesh_friction.py) to ``torque_Nmm`` and back down to ``unload_to`` of
    it, in ``mj.strainwave_solve``'s form (``unloaded``: the second step)."""
    import time
    from strainwave.fea.mesh_friction import twists_for_torques
    t0 = time.perf_counter()
    system = band_system(problem, module_mm, friction=friction)
    legs = twists_for_torques(system, [torque_Nmm, unload_to * torque_Nmm], increments)
    dt = time.perf_counter() - t0
    for r in legs:
        r["teeth_in_contact"] = int((r["forces_N"] > 0).sum())
    return legs[0] | {"unloaded": legs[1], "solve_s": dt}


def strainwave_study_path(problem: mj.Problem, module_mm: float, torque_Nmm: float, *, unload_to: float = 0.5,
                          steps_per_leg: int = 40, increments: int | None = None) -> dict:
    """The tooth-mesh STUDY's own friction solve on the problem (decision 073-slipstudy48): fea/mesh_friction's
    torque_path with the study's torque steps (``steps_per_leg`` steps to ``torque_Nmm``, the same steps back down
    to ``unload_to`` of it) and its increments per step (fea/tooth_mesh.INCREMENTS), in ``strainwave_true_slip``'s
    form."""
    from strainwave.fea import tooth_mesh as tm
    from strainwave.fea.mesh_friction import torque_path
    system = band_system(problem, module_mm)
    down = int(round(steps_per_leg * (1.0 - unload_to)))
    hist = np.concatenate([np.linspace(0.0, torque_Nmm, steps_per_leg + 1),
                           np.linspace(torque_Nmm, unload_to * torque_Nmm, down + 1)[1:]])
    path, Q = torque_path(system, hist, tm.INCREMENTS if increments is None else increments)
    legs = []
    for k in (steps_per_leg, hist.size - 1):
        N = path.forces_N[k]
        legs.append({"twist_rad": float(path.twist_rad[k]), "torque_Nmm": float(hist[k]), "forces_N": N,
                     "tangential_N": Q[k], "share": N / N.sum(), "teeth_in_contact": int((N > 0).sum())})
    return legs[0] | {"unloaded": legs[1]}


def strainwave_true_slip_path(problem: mj.Problem, module_mm: float, torques_Nmm, *,
                              increments: int = 20) -> list[dict]:
    """strainwave's true-slip solve along a torque history (each leg ends at its torque), one record per leg."""
    from strainwave.fea.mesh_friction import twists_for_torques
    legs = twists_for_torques(band_system(problem, module_mm), torques_Nmm, increments)
    for r in legs:
        r["teeth_in_contact"] = int((r["forces_N"] > 0).sum())
    return legs


def _equations(out: list[str], rid: int, n: np.ndarray, t: np.ndarray, f: np.ndarray, g: np.ndarray) -> None:
    """u_R,x and u_R,y as the band's weighted sums of the flank nodes' displacements (R dependent, first)."""
    for d in (0, 1):
        a = -n[d] * f + t[d] * g                     # coefficient of every sector dof in u_R,d
        keep = np.flatnonzero(np.abs(a) > EQ_DROP * np.abs(a).max())
        terms = [(rid, d + 1, 1.0)] + [(j // 2 + 1, j % 2 + 1, -a[j]) for j in keep.tolist()]
        out += ["*EQUATION", str(len(terms))]
        for k in range(0, len(terms), 4):
            out.append(",".join(f"{nd},{dof},{c:.13e}" for nd, dof, c in terms[k:k + 4]))


def write_band_deck(path: Path, problem: mj.Problem, params, twist_rad, *, friction: bool = True,
                    penalty_N_per_mm: float = 1.0e10, stick_N_per_mm: float = 1.0e9,
                    increments: int = 20) -> dict:
    """The deck: the sector (CPE6, bore clamped), one reference node per pair tied to its flank's band by
    *EQUATION, a rigid punch per pair (CPE8, moved by -twist about the axis), node-to-surface contact of R on
    the punch face with *FRICTION. Returns what ``mj.read_punch_loads`` needs."""
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    x, conn = mj._fs_elements(problem.model)
    n_fs, n_pairs = x.shape[0], problem.teeth.size
    quads = mj._punches(problem, geo.fs.module_mm)
    punch_nodes = n_fs + 1 + np.arange(8 * n_pairs).reshape(n_pairs, 8)
    ref_nodes = punch_nodes.max() + 1 + np.arange(n_pairs)
    out = ["*HEADING", "strainwave band contact: FS rim sector, band reference nodes, rigid punches "
           "(benchmarks/mesh_ccx_band.py)", "*NODE, NSET=NALL"]
    mj._rows(out, np.column_stack([np.arange(1, n_fs + 1), x]), "%d," + ",".join([mj.REAL] * 2))
    mj._rows(out, np.column_stack([punch_nodes.ravel(), quads.reshape(-1, 2)]), "%d," + ",".join([mj.REAL] * 2))
    mj._rows(out, np.column_stack([ref_nodes, problem.point_mm]), "%d," + ",".join([mj.REAL] * 2))
    out.append("*ELEMENT, TYPE=CPE6, ELSET=EFS")
    mj._rows(out, np.column_stack([np.arange(1, conn.shape[0] + 1), conn + 1]), ",".join(["%d"] * 7))
    out.append("*ELEMENT, TYPE=CPE8, ELSET=EPUNCH")
    first = conn.shape[0] + 1
    mj._rows(out, np.column_stack([first + np.arange(n_pairs), punch_nodes]), ",".join(["%d"] * 9))
    _nset(out, "NBORE", np.flatnonzero(np.hypot(*x.T) < problem.r_bore_mm * (1 + 1e-6)) + 1)
    _nset(out, "NPUNCH", punch_nodes.ravel())
    _nset(out, "NREF", ref_nodes)
    F, G = band_vectors(problem, geo.fs.module_mm)
    t = _tangent(problem)
    for k in range(n_pairs):
        _equations(out, int(ref_nodes[k]), problem.normal[k], t[k], F[:, k], G[:, k])
    mu = problem.system.friction_coefficient if friction else 0.0
    out += ["*SURFACE INTERACTION, NAME=BAND", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{penalty_N_per_mm:.6e},0.0,1.0e-7"]
    if mu > 0.0:
        out += ["*FRICTION", f"{mu:.6e},{stick_N_per_mm:.6e}"]
    for k in range(n_pairs):
        out += [f"*SURFACE, NAME=S{k}, TYPE=NODE", str(int(ref_nodes[k])), f"*SURFACE, NAME=M{k}", f"{first + k},S1"]
    for k in range(n_pairs):
        out += ["*CONTACT PAIR, INTERACTION=BAND, TYPE=NODE TO SURFACE", f"S{k},M{k}"]
    m = params.material
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{m.youngs_modulus_MPa:.13e},{m.poisson_ratio:.13e}",
            "*SOLID SECTION, ELSET=EFS, MATERIAL=STEEL", f"{geo.face_width_mm:.13e}",
            "*SOLID SECTION, ELSET=EPUNCH, MATERIAL=STEEL", f"{geo.face_width_mm:.13e}",
            "*BOUNDARY", "NBORE,1,2,0.", "NREF,3,3,0."]
    mj.punch_steps(out, quads.reshape(-1, 2), punch_nodes, twist_rad, increments)
    path.write_text("\n".join(out + [""]))
    return {"punch_nodes": punch_nodes, "punch_xy": quads, "ref_nodes": ref_nodes}


def _nset(out: list[str], name: str, ids: np.ndarray) -> None:
    mj._nset(out, name, np.asarray(ids))


def run_band(problem: mj.Problem, params, twist_rad, job_dir: Path, *, friction: bool = True,
             penalty_N_per_mm: float = 1.0e10, stick_N_per_mm: float = 1.0e9, threads: int = 1,
             ccx: str = "ccx", increments: int = 20) -> dict:
    """Write the band deck, run ccx, read each step's flank loads (the punches' reactions)."""
    import calculix_job as cj
    job_dir.mkdir(parents=True, exist_ok=True)
    info = write_band_deck(job_dir / "mesh.inp", problem, params, twist_rad, friction=friction,
                           penalty_N_per_mm=penalty_N_per_mm, stick_N_per_mm=stick_N_per_mm, increments=increments)
    run, _ = cj.run_ccx(job_dir / "mesh.inp", threads=threads, ccx=ccx)
    n = np.atleast_1d(twist_rad).size
    steps = [mj.read_punch_loads(job_dir / "mesh.dat", problem, info["punch_nodes"], info["punch_xy"], k + 1)
             for k in range(n)]
    return steps[0] | {"steps": steps, "wall_s": run.wall_s, "peak_GB": run.peak_GB}
