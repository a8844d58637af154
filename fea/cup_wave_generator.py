"""Study ``cup-wave-generator``: the flexspline cup's band forced onto the wave generator, then twisted.

The wall of the cup (fea/wg_band.py: the cylinder from the diaphragm, held round, to the open rim; smooth
band, so the tooth root is the band's outer fibre at d1/2) is forced onto the wave generator of radial
amplitude w0 = ``gear.radial_deformation_mm`` in two ways: the prescribed-shape limit (u_r = w0 cos 2 phi
on the band's bore) and a rigid elliptical cam (semi-axes r_bore +- w0) in frictionless unilateral contact
(an active set on the bore's radial dofs: the band lifts off near the minor axis). Each is solved linear
and geometrically nonlinear (total Lagrangian, St Venant-Kirchhoff, Newton). On each inserted state the
tangent problem under a uniform tangential shear on the band gives the torsional stiffness, and the state
at the rated torque (inserted +- the torque increment: a point of the band sees both signs as it passes
the axes) gives the stress cycle a point of the band's outer fibre runs through per input revolution.

Quantities (each on three meshes, GCI): hoop bending stress (outer - inner)/2 at the major and minor axes
at the band's mid-width, the full outer-fibre hoop stress there, the peak von Mises stress over the sampled
wall, the torsional stiffness, the bending at the major axis along the cup (end effect), and the outer
fibre's hoop stress amplitude and mean at the band's mid-width over one revolution.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np

from strainwave.errors import InputError
from strainwave.fea.assembly import Lame
from strainwave.fea.refinement import converged_quantity
from strainwave.fea.result import Load, MeshQuality, StudyResult, Support
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, StudyVariant, check_variant, run_variant
from strainwave.fea.study_facts import TORQUE_RATED
from strainwave.fea import wg_band as wb

STUDY = wb.STUDY
MODELS = ("prescribed", "contact")
KINEMATICS = ("linear", "nonlinear")
# Axial stations, as distances from the open rim in band widths: the band's mid-width (0.5) is where the
# ring's closed form is checked; the others measure the cup's end effect (rim, band edge, coned wall).
STATIONS = (0.02, 0.25, 0.5, 0.75, 1.0, 2.0)
MID = STATIONS.index(0.5)
# Elements around the quarter circumference, finest first (ratio ~1.4, the project's default).
REFINEMENTS = {True: (14.0, 10.0, 7.0), False: (20.0, 14.0, 10.0)}


def default_size_mm(params, quick: bool) -> float:
    """Finest element length around the band: the quarter circumference over the finest count."""
    return 0.5 * math.pi * wb.tube_geometry(params).r_m_mm / REFINEMENTS[bool(quick)][0]


def case_name(model: str, kinematics: str) -> str:
    return f"{model}_{kinematics}"


def _stations_z_mm(geo: wb.TubeGeometry) -> np.ndarray:
    return geo.length_mm - geo.band_mm * np.asarray(STATIONS)


def _sample(tube, u, lame, nonlinear) -> dict[str, np.ndarray]:
    """Hoop stress at the outer / inner fibre and von Mises, on (station, phi node) grids."""
    geo = tube.geo
    phi = np.linspace(0.0, 0.5 * math.pi, int(round(tube.geo.r_m_mm * 0.5 * math.pi / tube.h_mm)) + 1)
    zz, pp = np.meshgrid(_stations_z_mm(geo), phi, indexing="ij")
    out = {}
    for fibre, r in (("outer", geo.r_o_mm), ("inner", geo.r_i_mm)):
        sig = wb.stresses_at(tube, u, lame, nonlinear, np.full(zz.size, r), pp.ravel(), zz.ravel())
        out[f"hoop_{fibre}"] = sig[:, 1, 1].reshape(zz.shape)
        out[f"shear_{fibre}"] = sig[:, 1, 2].reshape(zz.shape)
        out[f"mises_{fibre}"] = wb.von_mises_MPa(sig).reshape(zz.shape)
    return out


def _state_values(name: str, s: dict[str, np.ndarray], stiffness: float) -> dict[str, float]:
    bend = 0.5 * (s["hoop_outer"] - s["hoop_inner"])
    return {f"{name}_bending_major_MPa": float(bend[MID, 0]), f"{name}_bending_minor_MPa": float(bend[MID, -1]),
            f"{name}_hoop_major_outer_MPa": float(s["hoop_outer"][MID, 0]),
            f"{name}_hoop_minor_outer_MPa": float(s["hoop_outer"][MID, -1]),
            f"{name}_peak_von_mises_MPa": float(max(s["mises_outer"].max(), s["mises_inner"].max())),
            f"{name}_torsional_stiffness_Nmm_per_rad": stiffness}


def _cycle_values(tube, state, du_unit, arm_mm3, lame, rated_torque_Nmm) -> dict[str, float]:
    """Outer-fibre hoop stress over one input revolution at the band's mid-width, at the rated torque: the
    quarter's points with the torque increment added and (their mirror images) subtracted."""
    scale = rated_torque_Nmm / (4.0 * arm_mm3)
    plus = _sample(tube, state.u + scale * du_unit, lame, state.nonlinear)
    minus = _sample(tube, state.u - scale * du_unit, lame, state.nonlinear)
    hoop = np.concatenate([plus["hoop_outer"][MID], minus["hoop_outer"][MID]])
    hi, lo = float(hoop.max()), float(hoop.min())
    return {"cycle_hoop_max_MPa": hi, "cycle_hoop_min_MPa": lo, "cycle_amplitude_MPa": 0.5 * (hi - lo),
            "cycle_mean_MPa": 0.5 * (hi + lo), "cycle_torque_shear_MPa": float(abs(plus["shear_outer"][MID, 0]))}


def _case_values(params, tube, lame, name, state, du, twist, arm, facts) -> dict[str, float]:
    """One case's values (and its solver facts into ``facts``): the state's, the end effect (prescribed linear),
    the revolution's cycle (contact nonlinear, whose rated-torque field is kept)."""
    s = _sample(tube, state.u, lame, state.nonlinear)
    values = _state_values(name, s, 4.0 * arm / float(twist @ du))
    facts[name] = {"newton_steps": state.newton_iterations, "active_set_changes": state.active_set_iterations,
                   "bore_points_in_contact": int(state.active.sum()), "bore_points": int(state.active.size)}
    if name == "prescribed_linear":
        bend = 0.5 * (s["hoop_outer"] - s["hoop_inner"])
        values |= {f"end_bending_major_s{k}_MPa": float(bend[k, 0]) for k in range(len(STATIONS))}
    if name == "contact_nonlinear":
        values |= _cycle_values(tube, state, du, arm, lame, params.gear.rated_output_torque_Nmm)
        facts["fields_u"] = state.u + params.gear.rated_output_torque_Nmm / (4.0 * arm) * du
    return values


def solve_mesh(params, n_theta: int) -> tuple[dict[str, float], object, dict]:
    """Every case on one mesh: the values by name, the tube and the solver facts."""
    geo = wb.tube_geometry(params)
    mat = params.material
    lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)
    w0 = params.gear.radial_deformation_mm
    tube = wb.tube_mesh(geo, n_theta)
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    shear, twist, arm, _ = wb.band_outer_loads(tube)
    values, facts = {}, {}
    # K0 factorised twice for every linear state: symmetric (insertion) and antisymmetric (torque) conditions
    systems = {sym: wb.bore_system(tube, K0, symmetric=sym) for sym in (True, False)}
    try:
        for model in MODELS:
            linear = wb.insert(tube, lame, w0, contact=model == "contact", nonlinear=False, K0=K0,
                               system=systems[True])
            # K0's factors also precondition the Krylov solves of every nonlinear tangent (Newton, torque)
            for kin, state in (("linear", linear), ("nonlinear", wb.insert(
                    tube, lame, w0, contact=model == "contact", nonlinear=True, K0=K0, start=linear,
                    system=systems[True]))):
                name = case_name(model, kin)
                du = wb.torque_increment(tube, state, shear, systems[False])
                values |= _case_values(params, tube, lame, name, state, du, twist, arm, facts)
    finally:
        for system in systems.values():
            system.close()
    return values, tube, facts


@dataclass(frozen=True)
class CupWaveGenerator(StudyVariant):
    study: ClassVar[str] = STUDY
    # quarter wall of 27-node hexahedra, one through the wall, h/2 along the band: quick n = 14: 294 vs 239 cells
    elements_per_cell: ClassVar[float] = 1.23
    cpu_s_per_element: ClassVar[tuple[float, float]] = (1.0e-2, 1.4e-2)   # full, --quick: validate's schedule (decision 049)
    default_size_mm = staticmethod(default_size_mm)
    rated_load: ClassVar[str] = TORQUE_RATED   # solved at the rated T already (scale 1: not linear in T)
    report_component: ClassVar[str] = "cup"
    title: ClassVar[str] = "flexspline cup on the wave generator"
    image_marks: ClassVar[tuple] = ((), None, "T")     # its quarter-wall field carries no named faces
    signed_stress: ClassVar[tuple] = ("hoop_stress_MPa", "hoop stress")   # the wave generator's bending
    outside_design: ClassVar[str] = (
        "the cup's design factor on the wave generator is its fatigue factor over the revolution's stress cycle "
        "(amplitude and mean at the tooth root); a peak von Mises taken as fully reversed would count the wave "
        "generator's pre-stress as an amplitude")

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        g = wb.tube_geometry(params)     # the quarter wall the study meshes
        return 0.5 * math.pi * g.r_m_mm * g.wall_mm * (g.length_mm - g.z_end_mm), g.wall_mm
    params: object
    refinements: tuple[float, float, float]

    def __post_init__(self):
        check_variant(STUDY, order=2, sizes_mm=self.refinements)

    def build(self):
        return wb.tube_geometry(self.params)

    def series(self) -> tuple[SeriesPlan, ...]:
        return (SeriesPlan("wall", self.refinements),)

    def solve(self, parts, series, refinement, k, keep_fields, progress) -> MeshSolve:
        import time
        t0 = time.process_time()
        values, tube, facts = solve_mesh(self.params, int(refinement))
        u = facts.pop("fields_u")
        quality = MeshQuality(tube.elements, tube.basis.N, tube.dofs, 2, 1.0, 1.0)
        return MeshSolve(tube.h_mm, values, quality, {"solve": time.process_time() - t0},
                         {"method": "direct", "cases": facts}, {"tube": tube, "u": u} if keep_fields else {})

    def write_fields(self, series: Mapping[str, Series], vtu, load: Load) -> tuple:
        from strainwave.fea.fields import field_info
        f = series["wall"].finest.fields
        mat = self.params.material
        lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)
        info = field_info(STUDY, "rigid elliptical cam (contact, nonlinear) + " + load.describe(), mat)
        return (wb.write_fields(vtu, f["tube"], f["u"], lame, True, info),)

    def quantities(self, series: Mapping[str, Series]) -> dict:
        s = series["wall"]
        return {name: converged_quantity(name, _unit(name), s.h_mm, s.values(name)) for name in s.finest.values}

    def load(self, parts) -> Load:
        w0 = self.params.gear.radial_deformation_mm
        return Load("output torque T on the inserted band", self.params.gear.rated_output_torque_Nmm, "N*mm",
                    ("band outer surface",), f"uniform tangential shear on the band, on top of the wave generator's "
                    f"insertion w0 = {w0:g} mm (prescribed u_r = w0 cos 2 phi, or a rigid elliptical cam with "
                    "frictionless contact)", (("w0_mm", w0),))

    def supports(self) -> tuple[Support, ...]:
        return (Support(("held end",), "closed end held round: u_r = u_theta = 0 on the diaphragm's mid-plane, "
                        "u_z = 0 on its mid-wall circle"),
                Support(("symmetry planes",), "quarter model: symmetric (insertion) / antisymmetric (torque)"))

    def meta(self, parts, series: Mapping[str, Series]) -> dict:
        geo = parts
        return {"geometry_mm": {"r_bore": geo.r_i_mm, "r_outer": geo.r_o_mm, "r_m": geo.r_m_mm,
                                "held_end_z": geo.z_end_mm, "rim_z": geo.length_mm, "band_width": geo.band_mm},
                "stations_band_widths_from_rim": list(STATIONS), "elements_around_quarter": list(self.refinements),
                "element": "27-node hexahedron (P2), one through the wall",
                "tooth_root": "smooth band: the outer fibre at d1/2 is the tooth root circle (teeth stand on it)"}


def _unit(name: str) -> str:
    return "N*mm/rad" if name.endswith("_Nmm_per_rad") else "MPa"


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False) -> StudyResult:
    """Every case on three meshes; ``mesh_size_mm`` sets the finest element length around the band."""
    if order != 2:
        raise InputError("--order", order, "cup-wave-generator uses 27-node (P2) hexahedra only: 2")
    refinements = REFINEMENTS[bool(quick)]
    if mesh_size_mm is not None:
        quarter = 0.5 * math.pi * wb.tube_geometry(params).r_m_mm
        n = max(4, round(quarter / mesh_size_mm))
        refinements = (float(n), float(max(3, round(n / 1.4))), float(max(2, round(n / 1.96))))
    return run_variant(CupWaveGenerator(params, refinements), vtu=vtu, progress=progress)
