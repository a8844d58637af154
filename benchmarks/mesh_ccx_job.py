"""CalculiX (``ccx``) and strainwave on ONE frictional tooth-contact problem, on the same P2 mesh.

The problem (docs/decisions/069-ccx48-mesh-contact-calculix.md): a sector of the flexspline's toothed rim
(``fea/tooth_mesh_fe.sector_model``, the study's P2 triangles, plane strain, thickness = engaged face width),
its bore clamped, and one rigid flat punch per flank pair of a lobe: the circular spline's tooth reduced to its
flank, tangent to the cup's +theta flank at the study's contact radius and set off along the flank normal by the
study's unloaded clearance (analytic/mesh_engagement.py's numbers, handed in). The punches turn together about
the axis by the twist theta; Coulomb friction mu on every flank.

strainwave solves it with its own machinery: the flank compliance matrix of this mesh from its unit parabolic
band loads (``fe.flank_loads``, ``fe.compliance``) and the study's contact solve (``mesh_contact``) to the torque.
CalculiX solves the same mesh (CPE6, the same nodes) with *CONTACT PAIR (node-to-surface, penalty, *FRICTION)
at the twist strainwave found, the punches moved rigidly by *BOUNDARY; each punch's reaction is its flank load.
"""
from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REAL = "%.13e"                 # CalculiX reads 20 characters a number (benchmarks/calculix_job.py)
PUNCH_HALF_MM_OVER_M = 0.3     # half-length of a punch's face along the flank, over the module
PUNCH_DEPTH_OVER_M = 0.3       # its depth into the tooth space
SLAVE_BAND_OVER_M = 0.5        # the flank facets each punch may touch: this far in radius from the contact point
PENALTY_N_PER_MM3 = 1.0e8      # normal penalty slope: ~500 E / mm; x10 moves the shares < 0.1 % (decision 069-ccx48)
STICK_SLOPE_N_PER_MM3 = 1.0e7   # friction's stick slope (CalculiX's lambda); x10: shares < 0.1 % (decision 069-ccx48)
CLEARANCE_MAX_MM = 0.05        # pairs further open than this never close at rated torque on this gear


@dataclass
class Problem:
    """The sector, the punches and strainwave's contact system of that mesh (lengths mm, forces N)."""

    model: object              # fe.RimSolve of the sector (scalar P2 basis, clamped bore)
    teeth: np.ndarray          # (n,) sector tooth of each pair (0 = the sector's centre tooth)
    radius_mm: np.ndarray      # (n,) contact radius: the midpoint of the flank facet at the study's radius
    clearance_mm: np.ndarray   # (n,) unloaded gap along the flank normal
    point_mm: np.ndarray       # (n, 2) contact point on the flank
    normal: np.ndarray         # (n, 2) the flank's outward normal there (the punch presses along -normal)
    system: object             # mesh_contact.MeshSystem
    r_bore_mm: float
    setup_s: float
    side: np.ndarray | None = None   # (n,) +1: the tooth's +theta flank (carries +T), -1: its -theta flank


def lobe_pairs(mesh: dict, clearance_max_mm: float = CLEARANCE_MAX_MM, sides: tuple = (1,)) -> dict:
    """The pairs of the headline angle's lobe about tooth 0 on the flanks ``sides`` (+1: +theta, carrying +T;
    -1: -theta, carrying -T) that are open by less than ``clearance_max_mm``: sector tooth (signed offset from
    tooth 0), contact radius, clearance, side; +theta pairs first, each side by tooth."""
    pr = mesh["angles"][0]
    z = int(mesh["z_f"])
    tooth = (np.asarray(pr["tooth"]) + z // 4) % z - z // 4        # signed, the lobe about tooth 0
    side = np.asarray(pr["side"])
    keep = (np.isin(side, sides) & (np.abs(tooth) < z // 4)
            & (np.asarray(pr["clearance_mm"]) < clearance_max_mm))
    order = np.lexsort((tooth[keep], -side[keep]))
    return {"tooth": tooth[keep][order], "fs_radius_mm": np.asarray(pr["fs_radius_mm"])[keep][order],
            "clearance_mm": np.asarray(pr["clearance_mm"])[keep][order], "side": side[keep][order],
            "friction_coefficient": float(mesh["friction_coefficient"]), "rim_radius_mm": float(mesh["rim_radius_mm"])}


def _flank_point(model, tooth: int, radius_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """The midpoint of the straight facet of tooth ``tooth``'s +theta flank (the mesh's boundary) that crosses
    ``radius_mm``, and its outward normal. A punch set flush with that facet touches it over the whole facet,
    centred where strainwave centres its band (off-centre, the tip tooth's steep compliance gradient moved
    CalculiX's share by 9 % between meshes: decision 069-ccx48)."""
    from strainwave.fea.tooth_mesh_fe import _boundary_facet_teeth
    bf, r_mid, which, off = _boundary_facet_teeth(model)
    sel = bf[(which == tooth % model.teeth) & (off > 0)]
    for f in sel:
        a, b = model.mesh.p[:, model.mesh.facets[:, f]].T
        ra, rb = math.hypot(*a), math.hypot(*b)
        if min(ra, rb) <= radius_mm <= max(ra, rb) and ra != rb:
            n = np.array([b[1] - a[1], a[0] - b[0]]) / math.hypot(*(b - a))
            mid = 0.5 * (a + b)
            centroid = model.mesh.p[:, model.mesh.t[:, model.mesh.f2t[0, f]]].mean(axis=1)
            return mid, (n if n @ (mid - centroid) > 0 else -n)
    raise ValueError(f"tooth {tooth}: no +theta flank facet crosses r = {radius_mm:.5g} mm")


def _involute_point(spec, tooth: int, radius_mm: float, side: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The point of tooth ``tooth``'s flank ``side`` (+1: +theta) at ``radius_mm`` on the exact involute and its
    outward normal (tangent to the base circle): a contact point that does not move with the mesh."""
    from strainwave.geometry.involute import half_angle_rad
    pitch = 2 * math.pi / spec.teeth

    def at(r: float) -> np.ndarray:
        a = tooth * pitch + side * float(half_angle_rad(spec, r))
        return np.array([r * math.cos(a), r * math.sin(a)])

    p, dr = at(radius_mm), 1e-4 * spec.module_mm
    tan = at(radius_mm + dr) - at(radius_mm - dr)
    n = np.array([tan[1], -tan[0]]) / math.hypot(*tan)
    e_theta = np.array([-p[1], p[0]]) / radius_mm
    return p, (n if side * (n @ e_theta) > 0 else -n)


def band_loads(model, teeth: np.ndarray, radius_mm: np.ndarray, band_mm: float, side: np.ndarray) -> np.ndarray:
    """strainwave's unit band loads (columns, in pair order) on each pair's flank ``side``."""
    from strainwave.fea import tooth_mesh_fe as fe
    F = np.zeros((2 * model.basis.N, teeth.size))
    for sd in np.unique(side).tolist():
        k = np.flatnonzero(side == sd)
        F[:, k] = fe.flank_loads(model, teeth[k], radius_mm[k], band_mm, int(sd))[0]
    return F


def build(params, pairs: dict, h_mm: float, *, margin_teeth: int = 3, on_involute: bool = False) -> Problem:
    """The sector holding the pairs' teeth (+ ``margin_teeth`` each side), its P2 mesh, and strainwave's
    contact system: compliance F^T K^-1 F of the band loads, lever and slide of each punch. The contact point:
    the midpoint of the flank facet at the study's radius (a flat punch's seat), or with ``on_involute`` the
    exact involute point at that radius (the band problem: the same problem on every mesh)."""
    from strainwave.fea import tooth_mesh_fe as fe
    from strainwave.fea.assembly import Lame
    from strainwave.fea.mesh_contact import MeshSystem
    from strainwave.geometry.mesh_geometry import mesh_geometry
    t0 = time.perf_counter()
    geo = mesh_geometry(params)
    m = params.material
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio, plane_stress=False)
    centre = int(round(0.5 * (pairs["tooth"].min() + pairs["tooth"].max())))
    teeth = pairs["tooth"] - centre                  # the sector is centred on tooth 0 at +x
    half = int(np.max(np.abs(teeth))) + margin_teeth
    model = fe.sector_model(geo.fs, geo.r_bore_mm, half, h_mm, lame, geo.face_width_mm)
    side = np.asarray(pairs.get("side", np.ones(teeth.size, int)))
    if not on_involute and np.any(side != 1):
        raise ValueError("a facet seat is built for +theta flanks only; pass on_involute=True")
    seat = (lambda j, r, sd: _involute_point(geo.fs, j, r, sd)) if on_involute else \
        (lambda j, r, sd: _flank_point(model, j, r))
    flank = [seat(int(j), float(r), int(sd)) for j, r, sd in zip(teeth, pairs["fs_radius_mm"], side)]
    point, normal = np.array([p for p, _ in flank]), np.array([n for _, n in flank])
    radius = np.hypot(point[:, 0], point[:, 1])      # a facet's midpoint: within half a facet of the study's
    band = 0.2 * geo.fs.module_mm                    # the study's band half-width (tooth_mesh.BAND_OVER_M)
    C = fe.compliance(model, band_loads(model, teeth, radius, band, side))
    # the punches turn by -theta: each gap closes at lever * theta, lever = (P x n)_z (the base radius)
    lever = point[:, 0] * normal[:, 1] - point[:, 1] * normal[:, 0]
    tangent = np.column_stack([-normal[:, 1], normal[:, 0]])
    slide = point[:, 0] * tangent[:, 1] - point[:, 1] * tangent[:, 0]
    system = MeshSystem(np.asarray(pairs["clearance_mm"], float), C, lever, slide,
                        pairs["friction_coefficient"], pairs["rim_radius_mm"])
    return Problem(model, teeth, radius, system.clearance_mm, point, normal, system,
                   geo.r_bore_mm, time.perf_counter() - t0, side)


def strainwave_solve(problem: Problem, torque_Nmm: float, *, friction: bool = True,
                     unload_to: float | None = None) -> dict:
    """strainwave's contact solve from unloaded to ``torque_Nmm`` (twist, normal forces, shares); with
    ``unload_to`` (a fraction of it) also back down to that torque after the reversal (``unloaded``)."""
    from dataclasses import replace
    from strainwave.fea.mesh_contact import solve_torque_path
    s = problem.system if friction else replace(problem.system, friction_coefficient=0.0)
    t0 = time.perf_counter()
    history = [0.0, torque_Nmm] + ([] if unload_to is None else [unload_to * torque_Nmm])
    path = solve_torque_path(s, np.array(history))
    dt = time.perf_counter() - t0

    def at(k: int) -> dict:
        F = path.forces_N[k]
        return {"twist_rad": float(path.twist_rad[k]), "forces_N": F, "share": F / F.sum(),
                "teeth_in_contact": int((F > 0).sum()), "torque_Nmm": float(history[k])}
    out = at(1) | {"solve_s": dt}
    return out if unload_to is None else out | {"unloaded": at(2)}


def _rows(lines: list[str], rows, fmt: str) -> None:
    lines.extend(fmt % tuple(r) for r in np.asarray(rows).tolist())


def _nset(lines: list[str], name: str, ids: np.ndarray) -> None:
    lines.append(f"*NSET, NSET={name}")
    lines.extend(",".join(str(int(v)) for v in ids[k:k + 8]) for k in range(0, ids.size, 8))


def _fs_elements(model) -> tuple[np.ndarray, np.ndarray]:
    """(nodes (N, 2), CPE6 connectivity (nel, 6), 0-based): the basis' P2 dofs as nodes, corners counter-clockwise
    then the mid nodes of edges 1-2, 2-3, 3-1 (skfem's facets of a triangle: 01, 12, 02)."""
    x = model.basis.doflocs.T
    conn = model.basis.element_dofs.T.copy()
    a, b, c = x[conn[:, 0]], x[conn[:, 1]], x[conn[:, 2]]
    if not np.allclose(x[conn[:, 3]], 0.5 * (a + b)) or not np.allclose(x[conn[:, 5]], 0.5 * (a + c)):
        raise RuntimeError("skfem P2 dofs are not in the expected edge order (01, 12, 02)")
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0.0
    conn[cw] = conn[cw][:, [0, 2, 1, 5, 4, 3]]        # mirror: corners 1 3 2, mids 13 32 21
    return x, conn


def _slave_faces(problem: Problem, conn: np.ndarray, k: int, band_mm: float) -> list[tuple[int, int]]:
    """(element id, face 1/2/3: edges 1-2, 2-3, 3-1, as Abaqus numbers a plane element's faces) of the
    +theta-flank facets of pair k's tooth within ``band_mm`` of its contact radius."""
    from strainwave.fea.tooth_mesh_fe import _boundary_facet_teeth
    model = problem.model
    bf, r_mid, which, off = _boundary_facet_teeth(model)
    near = np.abs(r_mid - problem.radius_mm[k]) < band_mm
    sel = bf[(which == problem.teeth[k] % model.teeth) & (off > 0) & near]
    faces = []
    for f in sel:
        e = int(model.mesh.f2t[0, f])
        ends = set(model.mesh.facets[:, f].tolist())
        for face, (i, j) in zip((1, 2, 3), ((0, 1), (1, 2), (2, 0))):
            if {int(conn[e, i]), int(conn[e, j])} == ends:
                faces.append((e + 1, face))
    if len(faces) != sel.size:
        raise RuntimeError(f"pair {k}: {sel.size} flank facets, {len(faces)} element faces found")
    return faces


def _punches(problem: Problem, module_mm: float) -> np.ndarray:
    """(n, 8, 2) the punch quads (CPE8: CalculiX expands only quadratic plane elements), counter-clockwise,
    their edge 1-2 the contact face (offset by the clearance)."""
    n, t = problem.normal, np.column_stack([-problem.normal[:, 1], problem.normal[:, 0]])
    face = problem.point_mm + problem.clearance_mm[:, None] * n
    L, D = PUNCH_HALF_MM_OVER_M * module_mm, PUNCH_DEPTH_OVER_M * module_mm
    q = np.stack([face + L * t, face - L * t, face - L * t + D * n, face + L * t + D * n], axis=1)
    v1, v2 = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
    if np.any(v1[:, 0] * v2[:, 1] - v1[:, 1] * v2[:, 0] <= 0.0):
        q = q[:, [1, 0, 3, 2]]
    return np.concatenate([q, 0.5 * (q + np.roll(q, -1, axis=1))], axis=1)


def write_deck(path: Path, problem: Problem, params, twist_rad, *, friction: bool = True,
               penalty_N_per_mm3: float = PENALTY_N_PER_MM3, stick_N_per_mm3: float = STICK_SLOPE_N_PER_MM3,
               increments: int = 20) -> dict:
    """The CalculiX job: the sector's P2 triangles as CPE6 (node id = basis dof + 1), its bore clamped, the punches
    as CPE8 moved rigidly by -twist about the axis, a node-to-surface *CONTACT PAIR per flank (penalty, *FRICTION),
    the punches' reactions printed. ``twist_rad``: one twist, or a history of them, one step each (the flanks'
    friction carries over). Returns the punch node ids per pair (for ``read_punch_loads``)."""
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    x, conn = _fs_elements(problem.model)
    n_fs, n_pairs = x.shape[0], problem.teeth.size
    quads = _punches(problem, geo.fs.module_mm)
    punch_nodes = n_fs + 1 + np.arange(8 * n_pairs).reshape(n_pairs, 8)
    out = ["*HEADING", "strainwave tooth-mesh contact: FS rim sector, rigid flank punches (benchmarks/mesh_ccx_job.py)",
           "*NODE, NSET=NALL"]
    _rows(out, np.column_stack([np.arange(1, n_fs + 1), x]), "%d," + ",".join([REAL] * 2))
    _rows(out, np.column_stack([punch_nodes.ravel(), quads.reshape(-1, 2)]), "%d," + ",".join([REAL] * 2))
    out.append("*ELEMENT, TYPE=CPE6, ELSET=EFS")
    _rows(out, np.column_stack([np.arange(1, conn.shape[0] + 1), conn + 1]), ",".join(["%d"] * 7))
    out.append("*ELEMENT, TYPE=CPE8, ELSET=EPUNCH")
    first = conn.shape[0] + 1
    _rows(out, np.column_stack([first + np.arange(n_pairs), punch_nodes]), ",".join(["%d"] * 9))
    r = np.hypot(*x.T)
    _nset(out, "NBORE", np.flatnonzero(r < problem.r_bore_mm * (1 + 1e-6)) + 1)
    _nset(out, "NPUNCH", punch_nodes.ravel())
    band = SLAVE_BAND_OVER_M * geo.fs.module_mm
    mu = problem.system.friction_coefficient if friction else 0.0
    out += ["*SURFACE INTERACTION, NAME=FLANK", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{penalty_N_per_mm3:.6e},0.0,1.0e-7"]   # no tension across an open gap (sigma_inf = 0)
    if mu > 0.0:
        out += ["*FRICTION", f"{mu:.6e},{stick_N_per_mm3:.6e}"]
    for k in range(n_pairs):
        out.append(f"*SURFACE, NAME=S{k}")
        out += [f"{e},S{f}" for e, f in _slave_faces(problem, conn, k, band)]
        out += [f"*SURFACE, NAME=M{k}", f"{first + k},S1"]
    for k in range(n_pairs):
        out += ["*CONTACT PAIR, INTERACTION=FLANK, TYPE=NODE TO SURFACE", f"S{k},M{k}"]
    m = params.material
    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{m.youngs_modulus_MPa:.13e},{m.poisson_ratio:.13e}",
            "*SOLID SECTION, ELSET=EFS, MATERIAL=STEEL", f"{geo.face_width_mm:.13e}",
            "*SOLID SECTION, ELSET=EPUNCH, MATERIAL=STEEL", f"{geo.face_width_mm:.13e}",
            "*BOUNDARY", "NBORE,1,2,0."]
    punch_steps(out, quads.reshape(-1, 2), punch_nodes, twist_rad, increments)
    out.append("")
    path.write_text("\n".join(out))
    return {"punch_nodes": punch_nodes, "punch_xy": quads}


def punch_steps(out: list[str], p: np.ndarray, punch_nodes: np.ndarray, twist_rad, increments: int) -> None:
    """One *STEP per twist: the punches turned rigidly by -twist (linear kinematics, as strainwave's gap
    = c - lever * theta)."""
    for theta in np.atleast_1d(np.asarray(twist_rad, float)).tolist():
        out += [f"*STEP, INC={50 * increments}", "*STATIC",
                f"{1.0 / increments},1.0,{1e-4 / increments},{1.0 / increments}", "*BOUNDARY"]
        u = theta * np.column_stack([p[:, 1], -p[:, 0]])
        for nid, (ux, uy) in zip(punch_nodes.ravel().tolist(), u.tolist()):
            out += [f"{nid},1,1,{ux:.13e}", f"{nid},2,2,{uy:.13e}"]
        out += ["*NODE PRINT, NSET=NPUNCH", "RF", "*END STEP"]


def read_punch_loads(dat: Path, problem: Problem, punch_nodes: np.ndarray, punch_xy: np.ndarray,
                     step: int | None = None) -> dict:
    """Each flank's normal load (the force it puts on its punch, along +normal) and the torque the punches
    carry, from the RF block at the end of ``step`` (1-based; None: the last) in the .dat file."""
    rf = {}
    inside = False
    for line in dat.read_text().splitlines():
        if line.strip().startswith("forces (fx,fy,fz)"):
            t = float(line.split()[-1])        # total time: step k ends at k
            if step is not None and t > step + 1e-9:
                break
            inside, rf = True, {}              # a new increment's block: keep the last
            continue
        parts = line.split()
        if inside and len(parts) == 4 and re.fullmatch(r"\d+", parts[0]):
            rf[int(parts[0])] = np.array([float(v) for v in parts[1:3]])
        elif inside and parts:
            inside = False
    R = np.array([[rf[int(i)] for i in row] for row in punch_nodes])         # (n, 4, 2) the supports' reactions
    force_on_punch = -R.sum(axis=1)                                          # what the flank pushes the punch with
    normal_N = np.einsum("ij,ij->i", force_on_punch, problem.normal)
    tangent = np.column_stack([-problem.normal[:, 1], problem.normal[:, 0]])
    tangential_N = np.einsum("ij,ij->i", force_on_punch, tangent)           # friction on the punch
    # torque on the punches (the CS) about the axis, positive as strainwave's T = sum (lever + mu slide) F
    torque = float(np.sum((punch_xy[..., 0] * -R[..., 1] - punch_xy[..., 1] * -R[..., 0])))
    return {"forces_N": normal_N, "tangential_N": tangential_N, "share": normal_N / normal_N.sum(),
            "torque_Nmm": torque,
            "teeth_in_contact": int((normal_N > 1e-3 * normal_N.max()).sum())}


PEAK_SHARE_REL_TOL = 0.02      # issue 48 item 8: the peak tooth share of the two codes within 2 %


def lobe_torque_Nmm(mesh: dict) -> float:
    """Rated torque on one lobe: the dual wave's two lobes carry it half each."""
    return 0.5 * float(mesh["rated_torque_Nmm"])


def pairs_for(params, sides: tuple = (1,)) -> dict:
    """The lobe's pairs and torque from the study's kinematics (analytic/mesh_engagement.py's numbers)."""
    from strainwave.analytic.mesh_engagement import study_loads
    mesh = study_loads(params)["mesh"]
    return lobe_pairs(mesh, sides=sides) | {"torque_Nmm": lobe_torque_Nmm(mesh)}


def problem_for(params, h_mm: float, *, on_involute: bool = False, sides: tuple = (1,)) -> tuple[Problem, dict]:
    """The problem on the study's kinematics: (problem, the lobe's pairs)."""
    pairs = pairs_for(params, sides)
    return build(params, pairs, h_mm, on_involute=on_involute), pairs


def run_calculix(problem: Problem, params, twist_rad, job_dir: Path, *, friction: bool = True,
                 penalty_N_per_mm3: float = PENALTY_N_PER_MM3, stick_N_per_mm3: float = STICK_SLOPE_N_PER_MM3,
                 threads: int = 1, ccx: str = "ccx") -> dict:
    """Write the deck, run ccx on it, read the flank loads (of each step when ``twist_rad`` is a history:
    ``steps``); ``wall_s`` is ccx's own run (under GNU time)."""
    import calculix_job as cj
    job_dir.mkdir(parents=True, exist_ok=True)
    info = write_deck(job_dir / "mesh.inp", problem, params, twist_rad, friction=friction,
                      penalty_N_per_mm3=penalty_N_per_mm3, stick_N_per_mm3=stick_N_per_mm3)
    run, _ = cj.run_ccx(job_dir / "mesh.inp", threads=threads, ccx=ccx)
    n = np.atleast_1d(twist_rad).size
    steps = [read_punch_loads(job_dir / "mesh.dat", problem, info["punch_nodes"], info["punch_xy"], k + 1)
             for k in range(n)]
    return steps[0] | {"steps": steps, "wall_s": run.wall_s, "peak_GB": run.peak_GB}


def agreement(sw: dict, ccx: dict, tol: float = PEAK_SHARE_REL_TOL) -> dict:
    """The numbers the check compares: peak shares (relative), the largest per-tooth share difference,
    the teeth in contact and CalculiX's torque at strainwave's twist over strainwave's torque."""
    peak_sw, peak_ccx = float(np.max(sw["share"])), float(np.max(ccx["share"]))
    return {"peak_share_strainwave": peak_sw, "peak_share_calculix": peak_ccx,
            "peak_share_rel": peak_ccx / peak_sw - 1.0,
            "share_max_abs_diff": float(np.max(np.abs(ccx["share"] - sw["share"]))),
            "teeth_in_contact": (sw["teeth_in_contact"], ccx["teeth_in_contact"]),
            "torque_ratio": ccx["torque_Nmm"] / sw["torque_Nmm"],
            "normal_sum_ratio": float(ccx["forces_N"].sum() / sw["forces_N"].sum()),
            "passes": abs(peak_ccx / peak_sw - 1.0) <= tol
            and sw["teeth_in_contact"] == ccx["teeth_in_contact"]}
