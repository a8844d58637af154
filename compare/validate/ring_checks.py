"""Checks of seed 003's ring model against the ring-compression study.

- ``ring.delta_cd`` / ``ring.delta_ab``: the FEA diameter changes against eq 3 / eq 4 (published, thin
  ring) and Roark's thick ring (corrected), both at the force the FEA applied.
- ``ring.sigma_max`` / ``ring.sigma_min``: the FEA hoop stress at the outer fibre of sections D and B
  against eqs 8 / 9 (thin) and Winkler-Bach (corrected), all at the prescribed deformation W0.
- The FEA spreads each force over a small arc; the thin-ring effect of that (``analytic/ring_arc_load.py``
  for the arc the study states in its typed ``Load``) is one modelling allowance, the second-order thick-ring terms (delta/r_m)^2 the other; the rest of the
  tolerance is the GCI (Fs inside, counted once).
- ``ring.tooth_influence`` / ``ring.stress_concentration``: the FEA's K_delta and K_sigma (in the seed's
  terms: K_sigma = root-fillet peak / (K_delta x smooth inner fibre), the factor eq 13 applies to sigma_a,
  which already holds K_delta) against the seed's assumed constants (published) and the tooth-factor model
  of analytic/tooth_factors.py (corrected), fitted on other rims; tolerance = GCI + the model's largest
  residual on its own fitting set (fixed before this geometry is solved).
"""
from __future__ import annotations

import math

from strainwave.analytic import ring
from strainwave.analytic.ring_arc_load import thin_ring_deflections_mm, thin_ring_moment_Nmm
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated
from strainwave.compare.validate.fea_book import FeaBook

def _scaled(ref: dict, factor: float) -> dict[str, float]:
    return {k: float(ref[k]) * factor for k in ("published", "corrected") if isinstance(ref.get(k), (int, float))}


def _mid_layer_radius_mm(params) -> float:
    e = params.ewg_drive
    return ring.mid_layer_radius_mm(e.module_mm, e.flexspline_teeth, e.rim_thickness_mm, e.dedendum_coefficient)


def _arc_allowances(load, params, refs: dict, F_ref: float | None) -> dict[str, float]:
    """How far the thin-ring answer for the FEA's arc load lies from the seed's point-load formula.

    The FEA spreads each force over a small arc (a point force has infinite local displacement); its typed
    ``Load`` states the force and the arc's half angle, and ``analytic/ring_arc_load.py`` gives the thin-ring
    deflections and moments of exactly that load. The gap to the point-load formula is a stated property of
    the load, granted as an allowance.
    """
    if load is None or load.force_N is None:
        return {}
    e, E = params.ewg_drive, params.material.youngs_modulus_MPa
    F, theta0, r_m = load.force_N, load.parameter("half_angle_rad"), _mid_layer_radius_mm(params)
    cd, ab = thin_ring_deflections_mm(F, theta0, r_m, E * ring.second_moment_mm4(e.face_width_mm, e.rim_thickness_mm))
    m_B, m_D = thin_ring_moment_Nmm([0.0, 0.5 * math.pi], F, theta0, r_m)
    out = {}
    why = "arc load instead of a point force (thin-ring theory of the FEA's load, analytic/ring_arc_load.py)"
    pub_cd = refs.get("ring.delta_cd", {}).get("published")
    pub_ab = refs.get("ring.delta_ab", {}).get("published")
    if pub_cd:
        out["ring.delta_cd"] = {why: abs(cd / pub_cd - 1.0)}
    if pub_ab:
        out["ring.delta_ab"] = {why: abs(ab / pub_ab - 1.0)}
    out["ring.sigma_max"] = {why: abs(m_D / ring.bending_moment_Nmm(0.5 * math.pi, F, r_m) - 1.0)}
    if F_ref:
        out["ring.sigma_min"] = {why: abs(m_B / ring.bending_moment_Nmm(0.0, F_ref, r_m) - 1.0)}
    return out


def _second_order_allowance(params) -> dict[str, float]:
    """Roark's thick-ring terms (shear, normal force, curvature) are first order in delta/r_m: what the
    corrected closed form leaves out is of order (delta/r_m)^2, which a converged 2D FEA does contain."""
    ratio = params.ewg_drive.rim_thickness_mm / _mid_layer_radius_mm(params)
    return {f"terms of order (delta/r_m)^2 = ({ratio:.4f})^2 beyond Roark's first-order thick ring": ratio ** 2}


def ring_checks(book: FeaBook, label: str, refs: dict, params) -> list[Check]:
    """All six ring checks from the ring case ``label`` and the analytic reference values ``refs``."""
    solved = book.result(label)
    F_ref = refs.get("ring.delta_cd", {}).get("force_N")
    F_fea = book.applied_force_N(label)
    # Deflections are at the force the FEA applied; stresses at the prescribed W0 (both sides of the
    # comparison state them that way), so only the deflections are rescaled.
    load_factor = 1.0 if F_fea is None or not F_ref else F_fea / F_ref
    load_note = (f"deflections at the FEA's force F = {F_fea:.6g} N (analytic rescaled by {load_factor:.6f}), "
                 "stresses at the prescribed W0" if F_fea else
                 f"analytic at the thin-ring force for W0, F = {F_ref:.6g} N (the ring case states no force)")
    arc = _arc_allowances(None if solved is None else solved.load, params, refs, F_ref)
    out = []
    specs = (
        ("ring.delta_cd", "shortening of the loaded diameter delta_CD", "mm", "delta_cd_mm", load_factor),
        ("ring.delta_ab", "lengthening of the free diameter delta_AB", "mm", "delta_ab_mm", load_factor),
        ("ring.sigma_max", "hoop stress, outer fibre at D (under the load), at W0", "MPa", "sigma_D_outer_MPa", 1.0),
        ("ring.sigma_min", "hoop stress, outer fibre at B (free point), at W0", "MPa", "sigma_B_outer_MPa", 1.0),
    )
    for check_id, quantity, unit, name, factor in specs:
        ref = refs.get(check_id, {})
        analytic = _scaled(ref, factor)
        q, why = book.quantity(label, name)
        if q is None:
            out.append(not_evaluated(check_id, quantity, unit, why, analytic=analytic))
            continue
        allowances = {**arc.get(check_id, {}), **_second_order_allowance(params)}
        tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances,
                            basis=gci_basis(q))
        note = f"{load_note}; {ref.get('note', '')}"
        out.append(evaluate(Check(check_id, quantity, unit, q.value, q.uncertainty, analytic, "corrected", tol,
                                  note=note, sources={"fea": f"FEA {label}", "analytic": "seed 003 / Roark"})))
    out.insert(2, solid_ring_check(book, label, refs, params, load_factor, arc.get("ring.delta_cd", {})))
    out += tooth_factor_checks(book, label, refs)
    return out


def width_allowance(poisson_ratio: float) -> tuple[float, float]:
    """(factor, half spread) of the 3D ring's compliance relative to the plane-stress closed form.

    A ring of width B bends between two bounds: free anticlastic curvature (plane stress, E I; a narrow
    ring) and none (plane strain, E I/(1 - nu^2); B^2/(r delta) large, the edges' free zones ~sqrt(r delta)
    small). Its compliance lies in [(1 - nu^2), 1] x the plane-stress value. Without a closed form for the
    transition, the midpoint 1 - nu^2/2 is asserted and half the interval, (nu^2/2)/(1 - nu^2/2), is the
    allowance: both follow from nu alone, fixed before the 3D solve.
    """
    factor = 1.0 - 0.5 * poisson_ratio ** 2
    return factor, 0.5 * poisson_ratio ** 2 / factor


def solid_ring_check(book: FeaBook, label: str, refs: dict, params, load_factor: float,
                     arc_allowance: dict[str, float]) -> Check:
    """``ring.delta_cd_solid``: the real 12 mm wide ring (3D solid FEA) against eq 3 and Roark's thick ring,
    the latter with the plane-stress / plane-strain spread as a named allowance (``width_allowance``)."""
    check_id, quantity, unit = "ring.delta_cd_solid", "shortening of the loaded diameter delta_CD, 3D solid ring", "mm"
    ref = refs.get("ring.delta_cd", {})
    nu = params.material.poisson_ratio
    factor, half_spread = width_allowance(nu)
    analytic = _scaled(ref, load_factor)
    if "corrected" in analytic:
        analytic["corrected"] *= factor
    q, why = book.quantity(label, "delta_cd_3d_mm")
    if q is None:
        return not_evaluated(check_id, quantity, unit, why, analytic=analytic)
    e = params.ewg_drive
    r_m = _mid_layer_radius_mm(params)
    searle = e.face_width_mm ** 2 / (r_m * e.rim_thickness_mm)
    allowances = {f"width: plane stress (E I) .. plane strain (E I/(1 - nu^2)) bounds, B^2/(r_m delta) = "
                  f"{searle:.3g}; midpoint asserted, half spread": half_spread, **arc_allowance}
    tol = fea_tolerance(q.value, q.uncertainty, allowances=allowances,
                        basis=gci_basis(q))
    q2d, _ = book.quantity(label, "delta_cd_mm")
    ratio = math.nan if q2d is None else q.value / q2d.value
    note = (f"3D solid (one eighth, P2, 2/3/4 elements through the rim, load uniform over B = {e.face_width_mm:g} mm) "
            f"at the FEA's force; 3D / 2D plane stress = {ratio:.4f} (bounds {1 - nu ** 2:.3f}..1); published = "
            f"eq 3 (E I), corrected = Roark thick ring x (1 - nu^2/2) = {factor:.4f}")
    return evaluate(Check(check_id, quantity, unit, q.value, q.uncertainty, analytic, "corrected", tol, note=note,
                          sources={"fea": f"FEA {label} (3D solid)", "analytic": "seed 003 eq 3 / Roark, width bounds"}))


def _relative_uncertainty(q) -> float:
    return 0.0 if q.uncertainty is None or q.value == 0 else abs(q.uncertainty / q.value)


def tooth_factor_checks(book: FeaBook, label: str, refs: dict) -> list[Check]:
    """K_delta and K_sigma of the toothed ring against the seed's constants and the fitted tooth-factor model."""
    out = []
    kd, why_kd = book.quantity(label, "tooth_influence")
    ks, why_ks = book.quantity(label, "stress_concentration")      # K_sigma = root factor / K_delta, per mesh
    prod, _ = book.quantity(label, "root_stress_factor")           # K_delta K_sigma
    for check_id, quantity, fit_key in (
            ("ring.tooth_influence", "tooth influence K_delta (toothed / smooth outer fibre, at W0)", "tooth_influence"),
            ("ring.stress_concentration", "root stress concentration K_sigma = root peak / (K_delta x smooth inner "
                                          "fibre)", "stress_concentration")):
        ref = refs.get(check_id, {})
        analytic = _scaled(ref, 1.0)
        q, why = (kd, why_kd) if check_id == "ring.tooth_influence" else (ks, why_ks)
        if q is None:
            out.append(not_evaluated(check_id, quantity, "1", why, analytic=analytic))
            continue
        value, rel_u = q.value, _relative_uncertainty(q)
        residual = float((ref.get("fit_residuals") or {}).get(fit_key, math.nan))
        fitted_on = ref.get("fitted_on_teeth_and_delta_over_m") or []
        rims = ", ".join(f"Z_R {z:g} delta/m {d:g}" for z, d in fitted_on)
        if not ref.get("held_out"):
            out.append(not_evaluated(check_id, quantity, "1", f"this rim is in the model's fitting set ({rims}): "
                                     "a fitted model is confirmed only on rims it was not fitted on",
                                     analytic=analytic))
            continue
        if ref.get("root_fillet_coefficient") != ref.get("model_root_fillet_coefficient"):
            out.append(not_evaluated(check_id, quantity, "1", f"the tooth-factor model holds for a root fillet of "
                                     f"{ref.get('model_root_fillet_coefficient')} m, this ring has "
                                     f"{ref.get('root_fillet_coefficient')} m", analytic=analytic))
            continue
        held = "held out (not in the fit)"
        allowances = {f"tooth-factor model's largest residual on its fitting set ({rims})": residual}
        tol = fea_tolerance(value, rel_u * abs(value), allowances=allowances,
                            basis=gci_basis(q))
        lo, hi = ref.get("seed_range", [math.nan, math.nan])
        note = (f"this rim: h/delta = {ref.get('h_over_delta', math.nan):.4g}, delta/m = "
                f"{1.0 / ref.get('m_over_delta', math.nan):.4g}, fillet {ref.get('root_fillet_coefficient')} m, {held}; "
                f"published = seed 003's assumption ({lo:g}..{hi:g}); FEA K_delta x K_sigma = "
                f"{prod.value if prod is not None else math.nan:.4g} (seed: 1.07 x 1.9 = 2.033)")
        out.append(evaluate(Check(check_id, quantity, "1", value, rel_u * abs(value), analytic, "corrected", tol,
                                  note=note, sources={"fea": f"FEA {label} (toothed vs smooth)",
                                                      "analytic": "seed 003 assumption | analytic/tooth_factors.py"})))
    return out
