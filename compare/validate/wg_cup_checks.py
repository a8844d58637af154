"""Checks and the design record of the cup on its wave generator (study ``cup-wave-generator``, issue 34).

- ``cup.wg_bending_major`` / ``cup.wg_bending_minor``: the FEA's hoop bending stress (outer - inner fibre)/2
  at the band's mid-width, prescribed shape, linear, against the ring forced into w0 cos 2 phi
  (analytic/ring_prescribed.py): corrected = the band of a long shell (E/(1 - nu^2), no anticlastic
  curvature where w is prescribed along the band), published = seed 003's two-point-load ring (eqs 8, 9) at
  the same W0 (what the seed would give; not the same problem, so not asserted).
- Tolerance = GCI (Fs inside) + two allowances fixed here, from the geometry alone: the thin ring's neglected
  t/(2 r_m) (curved beam), and the edge zones: plane strain holds away from the band's rim and its junction
  with the coned wall; within them the shell relaxes toward plane stress (the nu^2 of E') with the shell's
  edge decay exp(-beta s), beta = [3(1 - nu^2)]^(1/4)/sqrt(r_m t) (Timoshenko), s = b/2 from either edge.
- The membrane part (outer + inner)/2 and the stations along the cup are the end effect: reported.
"""
from __future__ import annotations

import math

from strainwave.analytic import ring, ring_prescribed
from strainwave.analytic.reference import Reference
from strainwave.catalogue_units import beside
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated
from strainwave.compare.validate.fea_book import FeaBook

STUDY = "cup-wave-generator"
CHECKS = (("cup.wg_bending_major", "major", "prescribed_linear_bending_major_MPa"),
          ("cup.wg_bending_minor", "minor", "prescribed_linear_bending_minor_MPa"))


def _geometry(params) -> tuple[float, float, float]:
    """(t, r_m, band width) of the cup's wall (geometry/flexspline_cup.py: bore d1/2 - t, outer d1/2)."""
    from strainwave.geometry.flexspline_cup import BAND_RATIO
    fc = params.flexspline_cup
    return fc.wall_thickness_mm, 0.5 * (fc.pitch_diameter_mm - fc.wall_thickness_mm), BAND_RATIO * fc.pitch_diameter_mm


def allowances(params) -> dict[str, float]:
    t, r_m, band = _geometry(params)
    nu = params.material.poisson_ratio
    beta = (3.0 * (1.0 - nu ** 2)) ** 0.25 / math.sqrt(r_m * t)
    edge = nu ** 2 * math.exp(-beta * 0.5 * band)
    return {f"curved beam: thin ring leaves out t/(2 r_m) = {t:g}/(2 x {r_m:g})":
            ring_prescribed.curved_beam_allowance(t, r_m),
            f"edge zones: nu^2 x exp(-beta b/2), beta = [3(1 - nu^2)]^1/4/sqrt(r_m t) = {beta:.4g}/mm, b/2 = "
            f"{0.5 * band:g} mm": edge}


def references(params, axis: str) -> Reference:
    t, r_m, _ = _geometry(params)
    m, w0 = params.material, params.gear.radial_deformation_mm
    phi = 0.0 if axis == "major" else 0.5 * math.pi / (params.gear.wave_number / 2.0)
    corrected = float(ring_prescribed.hoop_bending_stress_MPa(phi, w0, t, r_m, m.youngs_modulus_MPa, m.poisson_ratio,
                                                               wave_number=params.gear.wave_number))
    # seed 003: outer fibre at the free point B (major axis, eq 9) and under the load D (minor axis, eq 8)
    seed = ring.sigma_min_MPa if axis == "major" else ring.sigma_max_MPa
    return Reference(seed(w0, m.youngs_modulus_MPa, t, 2.0 * r_m), corrected, "MPa",
                     "published: seed 003 eqs 8/9; corrected: ring forced into w0 cos 2 phi (analytic/ring_prescribed.py)")


def wg_checks(book: FeaBook, label: str, params) -> list[Check]:
    out = []
    for check_id, axis, name in CHECKS:
        quantity = f"hoop bending stress (outer - inner)/2 at the {axis} axis, band mid-width, on the wave generator"
        analytic = references(params, axis).variants()
        q, why = book.quantity(label, name)
        if q is None:
            out.append(not_evaluated(check_id, quantity, "MPa", why, analytic=analytic))
            continue
        tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances(params),
                            basis=gci_basis(q))
        note = (f"w0 = {params.gear.radial_deformation_mm:g} mm prescribed as u_r = w0 cos 2 phi on the band's bore "
                "(linear); corrected = ring forced into that shape, E/(1 - nu^2) (analytic/ring_prescribed.py); "
                "published = seed 003 eqs 8/9 (two point loads) at the same W0, shown, not asserted")
        out.append(evaluate(Check(check_id, quantity, "MPa", q.value, q.uncertainty, analytic, "corrected", tol,
                                  note=note, sources={"fea": f"FEA {label}", "analytic": "analytic/ring_prescribed.py"})))
    return out


def _value(book: FeaBook, label: str, name: str) -> dict | None:
    q, _ = book.quantity(label, name)
    return None if q is None else {"value": q.value, "uncertainty": q.uncertainty}


def wg_record(book: FeaBook, label: str, params) -> dict:
    """The numbers issue 34 asks for, and the revolution cycle the design factor ``cup_tooth_root`` takes
    (compare/validate/design_fea.py: its n is in design.csv, not here)."""
    result = book.result(label)
    if result is None:
        return {}
    names = sorted(result.quantities)
    record = {"study": STUDY, "case": label, "quantities": {n: _value(book, label, n) for n in names}}
    a, m = result.quantities.get("cycle_amplitude_MPa"), result.quantities.get("cycle_mean_MPa")
    if a is not None and m is not None:
        record["fatigue"] = {
            "amplitude_MPa": a.value, "mean_MPa": m.value, "amplitude_gci_MPa": a.uncertainty,
            "mean_gci_MPa": m.uncertainty,
            "where": "band outer fibre (tooth root circle, smooth band) at mid-width, rigid cam, nonlinear, rated T",
            "design_factor": "cup_tooth_root (design.csv): the fitted tooth factors, the mesh load and the shear added"}
    record["closed_form_axis_stresses_MPa"] = {axis: references(params, axis).variants() for axis in ("major", "minor")}
    return record


def wg_lines(record: dict) -> list[tuple[str, str]]:
    """(item, value) rows of the report's table."""
    if not record:
        return []
    q = record["quantities"]

    def v(name, unit="MPa"):
        x = q.get(name)
        if x is None:
            return "n/a"
        gci = x["uncertainty"]
        return (f"{x['value']:.4g} {unit}" + ("" if gci is None else f" (GCI +- {abs(gci):.2g})")
                + beside(x["value"], unit))   # the torsional stiffness also in the catalogue's N m/rad
    rows = []
    for model in ("prescribed", "contact"):
        for kin in ("linear", "nonlinear"):
            k = f"{model}_{kin}"
            rows.append((f"{model}, {kin}: hoop outer fibre major / minor, bending major / minor",
                         f"{v(k + '_hoop_major_outer_MPa')} / {v(k + '_hoop_minor_outer_MPa')}; "
                         f"{v(k + '_bending_major_MPa')} / {v(k + '_bending_minor_MPa')}"))
            rows.append((f"{model}, {kin}: peak von Mises; torsional stiffness",
                         f"{v(k + '_peak_von_mises_MPa')}; {v(k + '_torsional_stiffness_Nmm_per_rad', 'N*mm/rad')}"))
    f = record.get("fatigue")
    if f:
        rows.append(("revolution cycle at rated T: amplitude / mean", f"{f['amplitude_MPa']:.4g} / {f['mean_MPa']:.4g} MPa"))
        rows.append(("design factor", "Flexspline cup, tooth root on the wave generator: see the design table"))
    return rows
