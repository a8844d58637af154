"""The simulated baseline a recording is compared with: one linear compliance per specimen.

Analytic (default), from strainwave.analytic's corrected closed forms:
- torsion / output_shaft: hollow shaft 32 L/(pi G (d^4 - d_i^4)), G = E/(2(1+nu)) (seed 000, lambda_so0 corrected);
- torsion / flexspline_cup: the corrected cup flexibility validate checks, strainwave's series shell model
  (tube + diaphragm + hub, analytic.seed000.cup_series_model), G = E/(2(1+nu)): seed 000's lambda_f0 is a
  bare tube and omits the diaphragm, which the FEA and a real cup have (FEA vs series model +4.7 %);
- torsion / gear: K_HD-type series sum lambda_H + lambda_f (series shell, as above) + lambda_so0 (seed 000);
- ring_compression / ewg_ring: thin ring delta_CD = 0.148778 F r_m^3/(E I) (seed 003, eqs 1 and 3).
G is taken from E and nu (not shear_modulus_MPa) so the analytic and FEA baselines see the same material.
A header key ``baseline_stiffness_Nmm_per_rad`` / ``baseline_stiffness_N_per_mm`` replaces the
simulation by a given linear stiffness (e.g. a catalogue K1), with the same relative uncertainty.

``fea`` runs the matching study of strainwave.fea with quick meshes and reads its compliance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.errors import InputError
from strainwave.registry import STUDIES
from strainwave.compare.diagnose.recording import Recording, RecordingKind

# recording specimen -> the study that models it (registry)
FEA_STUDY = {s.specimen: s.name for s in STUDIES.values() if s.specimen}


@dataclass(frozen=True)
class Baseline:
    """Linear model response = compliance * load, with a relative uncertainty of the compliance."""

    compliance: float           # rad/(N*mm) for torsion, mm/N for ring compression
    unit: str
    uncertainty: float          # relative (1 sigma)
    source: str                 # what produced it, quoted in the report
    geometry: dict              # specimen facts an effect model may need (r_m_mm, thick-ring factor, ...)
    # a drive's curve (a catalogue unit's, drive_curve.py): the baseline is that curve, its first slope the line
    # above and its bend (DriveCurve.departure_rad) taken out of the twist before the fit (pipeline.diagnose)
    curve: object | None = None

    @property
    def stiffness(self) -> float:
        return 1.0 / self.compliance


def analytic_baseline(rec: Recording, params) -> Baseline:
    """Closed-form baseline for the recording's specimen (see module docstring for the formulas)."""
    geometry = ring_geometry(params) if rec.kind is RecordingKind.RING_COMPRESSION else {}
    if rec.unit is not None:
        return unit_baseline(rec)
    if rec.baseline_stiffness is not None:
        unit = "rad/(N*mm)" if rec.kind is RecordingKind.TORSION else "mm/N"
        source = f"given linear stiffness {rec.baseline_stiffness:.6g} ({'N*mm/rad' if unit[0] == 'r' else 'N/mm'})"
        first = rec.baseline_stiffness
        reading = given_slope(rec)
        if reading is not None:
            first = reading.first_slope
            source = f"{source}; {reading.sentence()}"
        return Baseline(1.0 / first, unit, rec.baseline_uncertainty, source,
                        geometry or (_gear_facts(rec, params) if unit[0] == "r" else {}))
    if rec.kind is RecordingKind.RING_COMPRESSION:
        return Baseline(geometry["thin_compliance_mm_per_N"], "mm/N", rec.baseline_uncertainty,
                        "thin ring, seed 003 eq 3 (delta_CD = 0.148778 F r_m^3/EI)", geometry)
    compliance, source = torsion_compliance(rec.specimen, params)
    return Baseline(compliance, "rad/(N*mm)", rec.baseline_uncertainty, source, _gear_facts(rec, params))


def _gear_facts(rec: Recording, params) -> dict:
    """A gear's ratio (its tooth pitch of output twist is pi/i: events.py); the unit's where one is named."""
    if rec.specimen != "gear":
        return {}
    if rec.unit is not None:
        return {"gear_ratio": float(rec.unit.rsplit("-", 1)[1])}
    return {"gear_ratio": float(params.gear.gear_ratio)}


def unit_baseline(rec: Recording) -> Baseline:
    """A catalogue unit's piecewise curve (K1 to T1, K2 to T2, K3 above) as the baseline."""
    from strainwave.compare.diagnose.drive_curve import unit_curve
    curve = unit_curve(rec.unit)
    source = (f"catalogue curve of {rec.unit} (K1 {curve.K1_Nm_per_rad:.4g}, K2 {curve.K2_Nm_per_rad:.4g}, "
              f"K3 {curve.K3_Nm_per_rad:.4g} N*m/rad; T1 {curve.T1_Nm:.4g}, T2 {curve.T2_Nm:.4g} N*m; {curve.source})")
    return Baseline(1.0 / (curve.K1_Nm_per_rad * 1e3), "rad/(N*mm)", rec.baseline_uncertainty, source,
                    _gear_facts(rec, None), curve)


def given_slope(rec: Recording):
    """For a gear, which of its slopes the given stiffness is (drive_slope.py); None for another specimen or a
    curve that does not stiffen."""
    if rec.kind is not RecordingKind.TORSION or rec.specimen != "gear" or rec.baseline_stiffness is None:
        return None
    from strainwave.compare.diagnose.context import find_segments, reversal_threshold
    from strainwave.compare.diagnose.drive_slope import read_slope
    u = rec.load / float(np.max(np.abs(rec.load)))
    direction = np.ones(rec.n)
    for start, stop, d in find_segments(u, reversal_threshold(u)):
        direction[start:stop] = d
    return read_slope(rec.load, rec.response, direction, rec.baseline_stiffness)


def torsion_compliance(specimen: str, params) -> tuple[float, str]:
    """Corrected seed-000 flexibility of the torsion specimen, rad/(N*mm)."""
    from strainwave.analytic import torsion as tor
    from strainwave.analytic.seed000 import cup_series_model
    from strainwave.analytic.variant import Variant
    G = params.material.implied_shear_modulus_MPa
    sh, cup, gear, wg = params.output_shaft, params.flexspline_cup, params.gear, params.wave_generator
    shaft = tor.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm, sh.inner_diameter_mm, G, Variant.CORRECTED)
    flex = cup_series_model(params, G).total
    if specimen == "output_shaft":
        return shaft, "hollow shaft 32L/(pi G (d^4 - d_i^4)) (seed 000 lambda_so0, corrected)"
    if specimen == "flexspline_cup":
        return flex, "flexspline cup series shell model, tube + diaphragm + hub (corrected, as validate)"
    lam_h = tor.wave_generator_flexibility(gear.force_coefficient, wg.uncracked_radial_stiffness_N_per_mm,
                                           cup.pitch_diameter_mm, gear.wave_number, gear.radial_deformation_mm,
                                           gear.gear_ratio)
    return tor.total_flexibility(lam_h, flex, shaft), "gear K_HD = 1/(lambda_H + lambda_f + lambda_so0) (seed 000; lambda_f the series shell model)"


def ring_geometry(params) -> dict:
    """Thin-ring compliance (seed 003 eqs 1, 3) and Roark's thick-ring factor for the EWG rim."""
    from strainwave.analytic import ring, thick_ring
    d = params.ewg_drive
    E, nu = params.material.youngs_modulus_MPa, params.material.poisson_ratio
    delta = d.rim_thickness_mm
    r_m = ring.mid_layer_radius_mm(d.module_mm, d.flexspline_teeth, delta, d.dedendum_coefficient)
    I = ring.second_moment_mm4(d.face_width_mm, delta)
    thin = ring.delta_cd_mm(1.0, r_m, E, I)
    section = thick_ring.RingSection(r_m, delta, d.face_width_mm)
    thick_dv, _ = thick_ring.deflections_mm(1.0, section, E, nu, thick=True)
    return {"r_m_mm": r_m, "rim_thickness_mm": delta, "face_width_mm": d.face_width_mm, "E_MPa": E,
            "poisson_ratio": nu, "I_mm4": I, "thin_compliance_mm_per_N": thin,
            "thick_ring_factor": thick_dv / thin}


def fea_baseline(rec: Recording, params) -> Baseline:
    """Compliance from the FEA study with quick meshes; InputError when no study models the specimen."""
    if rec.baseline_stiffness is not None or rec.unit is not None:
        return analytic_baseline(rec, params)
    study = FEA_STUDY.get(rec.specimen)
    if study is None:
        raise InputError("--baseline", "fea", f"no FEA study models specimen {rec.specimen!r}; "
                         f"use --baseline analytic or give baseline_stiffness in the header")
    try:
        from strainwave.fea.studies import run_study
        result = run_study(study, params, quick=True)
    except ModuleNotFoundError as exc:
        raise InputError("--baseline", "fea", f"the FEA study {study!r} is not available in this build ({exc})") from None
    compliance, name = _compliance_from(result)
    q = result[STUDIES[study].flexibility.name]
    unc = (q.uncertainty or 0.0) / abs(q.value)     # relative GCI discretization uncertainty, in quadrature
    geometry = ring_geometry(params) if rec.kind is RecordingKind.RING_COMPRESSION else {}
    return Baseline(compliance, "rad/(N*mm)" if rec.kind is RecordingKind.TORSION else "mm/N",
                    math.hypot(rec.baseline_uncertainty, unc), f"FEA {study} (quick mesh), {name}", geometry)


def _compliance_from(result) -> tuple[float, str]:
    """The study's linear compliance, its registry ``flexibility`` quantity: a torsion study's flexibility
    in rad/(N*mm); the ring's delta_cd_mm divided by the force the study applied (its typed ``Load``)."""
    spec = STUDIES[result.study]
    q = spec.flexibility
    if q is not None and q.name in result.quantities:
        value = result.quantities[q.name].value
        force = result.load.force_N
        if force is None:          # a torque-loaded study's flexibility is already per unit load
            return value, q.name
        return value / force, f"{q.name} / {result.load.name}"
    raise InputError("--baseline", "fea", f"study {result.study!r} reports no linear compliance "
                     f"(quantities: {', '.join(result.quantities)})")
