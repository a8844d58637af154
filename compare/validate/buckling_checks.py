"""Check ``cup.buckling_torque``: the flexspline's torsional buckling torque, FE eigenvalue against the closed form.

FE (fea/cup_buckling.py): the cup's wall as a full tube (bore to root circle, diaphragm mid-plane to rim), ends
simply supported (u_r = u_theta = 0, free axially), linear buckling on the uniform-twist prestress, on three
meshes (28, 40, 56 elements around: ratio 1.4) for its GCI; an eigenvalue is a Rayleigh quotient, an energy
quantity of order 2k = 4 on P2. Closed form (analytic/cylinder_buckling.py) of the SAME tube: Batdorf's
Galerkin solution of Donnell's equation at the least integer wave number (asserted), its moderate-length
asymptote tau_cr = 0.747 E (t/R)^(5/4) (R/L)^(1/2) (k_s = 0.85 Z^(3/4): Timoshenko & Gere 1961 sec. 11.12,
NASA SP-8007) beside it as the published form.

Tolerance, fixed from the theory's own terms: GCI + 1/n^2 (Donnell's shallow-shell equations drop the terms of
relative order 1/n^2 against Flugge's at n circumferential waves; the solid FE keeps them) + the Galerkin
sum's truncation (TERMS axial half-waves against twice as many: measured at this Z, at least 1e-4).

Reported with it (the design verdict's rating, not asserted): the buckling torque over the rated torque, the
shear at buckling against the shear yield R_p0.2/sqrt(3) (above it the cup yields before it buckles: the
elastic value is then an upper bound), and the CSF catalogue's buckling torque of the nearest size
(/work/shared/tooth-mesh-references.md section 3; the CSF size is the pitch diameter in tenths of an inch).
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.analytic.cylinder_buckling import TERMS, batdorf_k, torsional_buckling
from strainwave.analytic.reference import Reference
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, not_evaluated
from strainwave.errors import StageError

__all__ = ["CHECK_ID", "MESHES", "reference", "allowances", "fe_quantity", "buckling_check", "buckling_record",
           "CSF_BUCKLING_NM"]

CHECK_ID = "cup.buckling_torque"
MESHES = (56, 40, 28)          # elements around the full circumference, finest first (ratio 1.4), for n <= 5 waves
# more waves get proportionally more elements (5.6 per wave on the coarsest), at most this many times MESHES: the
# cost grows with its square; beyond it the GCI carries the under-resolution
MAX_MESH_SCALE = 1.5
# Harmonic Drive LLC CSF/CSG catalogue, buckling torque (all ratios), N m, by size (tooth-mesh-references.md s. 3)
CSF_BUCKLING_NM = {8: 35, 11: 90, 14: 190, 17: 330, 20: 560, 25: 1000, 32: 2200, 40: 4300, 45: 5800, 50: 8000,
                   58: 12000}
INCH_MM = 25.4


def _tube(params):
    from strainwave.fea.wg_band import tube_geometry
    geo = tube_geometry(params)
    return geo, geo.r_m_mm, geo.wall_mm, geo.length_mm - geo.z_end_mm


def closed_form(params):
    _, R, t, L = _tube(params)
    m = params.material
    return torsional_buckling(R, t, L, m.youngs_modulus_MPa, m.poisson_ratio)


def reference(params) -> Reference:
    cb = closed_form(params)
    return Reference(cb.torque_asymptote_Nmm, cb.torque_Nmm, "N*mm",
                     f"Batdorf's Galerkin solution of Donnell's equation, simply supported, n = {cb.n_waves} waves, "
                     f"Z = {cb.Z:.4g} (published: 0.85 Z^(3/4), Timoshenko & Gere sec. 11.12 / NASA SP-8007) "
                     "(analytic/cylinder_buckling.py)")


def allowances(params) -> dict[str, float]:
    cb = closed_form(params)
    _, R, _, L = _tube(params)
    beta = cb.n_waves * L / (math.pi * R)
    truncation = abs(batdorf_k(cb.Z, beta, 2 * TERMS) / cb.k_s - 1.0)
    return {f"Donnell's shallow-shell terms, 1/n^2 at n = {cb.n_waves}": 1.0 / cb.n_waves ** 2,
            f"the Galerkin sum's truncation ({TERMS} vs {2 * TERMS} terms)": max(truncation, 1e-4)}


def fe_quantity(params):
    """The FE buckling torque on the three meshes with its GCI (order 4: an eigenvalue on P2), and the solves."""
    from strainwave.fea.assembly import Lame
    from strainwave.fea.cup_buckling import buckling_torque
    from strainwave.fea.refinement import converged_quantity

    geo, *_ = _tube(params)
    m = params.material
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)
    scale = min(MAX_MESH_SCALE, max(1.0, closed_form(params).n_waves / 5.0))
    solves = [buckling_torque(geo, lame, round(scale * n)) for n in MESHES[::-1]][::-1]
    q = converged_quantity("buckling_torque_Nmm", "N*mm", [s.h_mm for s in solves],
                           [s.torque_Nmm for s in solves], order=4.0)
    return q, solves


def buckling_check(params, solved=None) -> Check:
    """The check on ``solved`` = fe_quantity(params) (solved here when None)."""
    ref = reference(params)
    try:
        q, solves = solved or fe_quantity(params)
    except (StageError, ValueError, np.linalg.LinAlgError) as exc:   # a tube the FE cannot take is reported, not raised
        return not_evaluated(CHECK_ID, "flexspline torsional buckling torque (smooth wall tube)", "N*mm",
                             f"the buckling FE failed: {exc}", analytic=ref.variants())
    tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances(params),
                        basis=q.convergence.basis if q.convergence is not None else "")
    note = (f"FE: the cup's wall as a full tube of 27-node hexahedra (one through the wall), ends simply supported "
            f"and free axially, linear buckling on the uniform-twist prestress; meshes of {', '.join(map(str, MESHES))} "
            f"elements around ({', '.join(str(s.dofs) for s in solves)} dofs), the mode's waves "
            f"{'/'.join(str(s.n_waves) for s in solves)}; closed form: {ref.source}")
    return evaluate(Check(CHECK_ID, "flexspline torsional buckling torque (smooth wall tube)", "N*mm", q.value,
                          q.uncertainty, ref.variants(), "corrected", tol, note=note,
                          sources={"fea": "fea/cup_buckling.py (validate's own three meshes)",
                                   "analytic": "analytic/cylinder_buckling.py"}))


def nearest_csf(pitch_diameter_mm: float) -> tuple[int, float]:
    """(CSF size, its buckling torque in N m) nearest to the pitch diameter (size = pitch diameter in 0.1 in)."""
    size = pitch_diameter_mm / (0.1 * INCH_MM)
    near = min(CSF_BUCKLING_NM, key=lambda s: abs(s - size))
    return near, CSF_BUCKLING_NM[near]


def buckling_record(params, check: Check) -> dict:
    """The rating beside the design verdict: FE and closed form over rated torque, yield first or buckling first,
    the catalogue's nearest size (shown, not asserted)."""
    cb = closed_form(params)
    _, R, t, _ = _tube(params)
    rated = params.gear.rated_output_torque_Nmm
    tau_y = params.material.yield_strength_MPa / math.sqrt(3.0)
    fe = check.fea
    size, csf = nearest_csf(params.flexspline_cup.pitch_diameter_mm)
    yield_torque = tau_y * 2.0 * math.pi * R * R * t
    return {"fe_buckling_torque_Nmm": fe, "fe_gci_Nmm": check.fea_uncertainty,
            "closed_form_torque_Nmm": cb.torque_Nmm, "asymptote_torque_Nmm": cb.torque_asymptote_Nmm,
            "n_waves": cb.n_waves, "Z": cb.Z, "rated_torque_Nmm": rated,
            "fe_over_rated": None if fe is None else fe / rated,
            "closed_form_over_rated": cb.torque_Nmm / rated, "tau_cr_MPa": cb.tau_cr_MPa,
            "shear_yield_MPa": tau_y, "shear_yield_torque_Nmm": yield_torque,
            "yields_first": cb.tau_cr_MPa > tau_y, "csf_size": size, "csf_buckling_torque_Nm": csf,
            "csf_note": ("Harmonic Drive CSF catalogue buckling torque of the nearest size (shown, not asserted: a "
                         "catalogue cup is thinner, R/t ~ 100, and its rating includes the teeth and the diaphragm)")}
