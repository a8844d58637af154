"""Checks of the tooth-root surface crack (study ``cup-surface-crack``) and its record.

- ``cup.surface_crack_major`` / ``cup.surface_crack_between``: the FEA's delta lambda_f of the crack at the
  major axis / at 45 deg (wave generator + rated torque, face contact) against Newman-Raju integrated as seed 000
  eq 4 (analytic/surface_crack.py), with the same crack-face loads, the same crack (a = 0.2 t, a/c = 0.5) and
  the block's own width (Newman-Raju's f_w): corrected. Published = the seed's 45 deg through-wall crack of
  the same depth (another problem, the published idealisation: shown, not asserted).
- ``cup.surface_crack_minor``: the share of the open crack's compliance that the faces' contact removes at the
  minor axis, 1 - delta(minor)/delta(major), FEA against the Newman-Raju rule (combined K < 0 -> shut);
  published = the seed's crack, which never shuts (0).
- Tolerance = GCI (Fs inside) + allowances fixed here, before any result, from the equations' own statement and the
  block's geometry alone:
  * Newman and Raju state their equations within +-5 % of their 3D finite elements for a/t <= 0.8, so K^2
    (the compliance) within 10 %;
  * the block's far face at L from the crack: the opened crack acts on the far field as a dipole, whose
    stress decays as (c/L)^3, so the far face's uniform traction misplaces that much of the crack's energy.
- The closing state (52 deg) and the other depths are reported beside the rule, not asserted: where the
  crack shuts part of its front, the rule "K < 0 -> no compliance" integrated over the growth is approximate.
"""
from __future__ import annotations

import math

from strainwave.analytic import surface_crack as sc
from strainwave.analytic.reference import Reference
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated
from strainwave.compare.validate.fea_book import FeaBook
from strainwave.fea.surface_crack import ASPECT, STUDY, Block, block_for, delta_name, sweep_depths_mm

__all__ = ["STUDY", "CHECKS", "headline_depth_mm", "allowances", "references", "reference_at", "surface_crack_checks",
           "surface_crack_record"]

CHECKS = (("cup.surface_crack_major", "major"), ("cup.surface_crack_between", "between"),
          ("cup.surface_crack_minor", "minor"))
NEWMAN_RAJU_K2 = 0.10     # +-5 % on K (Newman-Raju's statement against their FE), squared


def headline_depth_mm(params) -> float:
    """The checked depth: a = 0.2 t, the one depth --quick also runs."""
    return sweep_depths_mm(params, quick=True)[0]


def _block(params, depth_mm: float) -> Block:
    m = params.material
    loads = sc.study_loads(params)
    return block_for(params.flexspline_cup.wall_thickness_mm, depth_mm, ASPECT, m.youngs_modulus_MPa,
                     m.poisson_ratio, loads["per_torque_MPa_per_Nmm"], loads["states"])


def allowances(block: Block) -> dict[str, float]:
    return {"Newman-Raju: K within +-5 % of their 3D FE (a/t <= 0.8), so K^2 within 10 %": NEWMAN_RAJU_K2,
            f"far face at L = {block.length_mm:.3g} mm: the crack's dipole field decays as (c/L)^3, "
            f"c = {block.c_mm:.3g} mm": (block.c_mm / block.length_mm) ** 3}


def references(params, depth_mm: float, state: str | None, deg: float | None = None) -> dict[str, float]:
    """Newman-Raju integrated (corrected) and the seed's through-wall crack (published) at one state (or at the
    wave-generator angle ``deg`` when ``state`` is None)."""
    block = _block(params, depth_mm)
    deg = dict(sc.STATES_DEG)[state] if state is not None else deg
    loads = sc.tooth_root_loads(params, math.radians(deg))
    E_prime = block.E_MPa / (1.0 - block.nu ** 2)
    nr = sc.delta_flexibility(depth_mm, ASPECT, block.t_mm, loads, E_prime, half_width_mm=block.half_width_mm)
    return {"corrected": nr, "published": sc.through_wall_flexibility(params, depth_mm)}


def _shut_share(book, label, params, depth, ref_major):
    """(FEA share, its uncertainty, references) of 1 - delta(minor)/delta(major)."""
    q_min, _ = book.quantity(label, delta_name("minor", depth))
    q_maj, _ = book.quantity(label, delta_name("major", depth))
    if q_min is None or q_maj is None or q_maj.value <= 0.0:
        return None, None, {}
    share = 1.0 - q_min.value / q_maj.value
    u_min = q_min.uncertainty if math.isfinite(q_min.uncertainty) else abs(q_min.value)
    u = abs(u_min / q_maj.value) + abs(q_min.value / q_maj.value) * abs(q_maj.uncertainty / q_maj.value)
    ref_minor = references(params, depth, "minor")["corrected"]
    return share, u, {"corrected": 1.0 - ref_minor / ref_major, "published": 0.0}


def reference_at(state: str):
    """The closed form the check at ``state`` asserts, as ``check_list.CheckSpec.reference``: (params, At) ->
    Reference at the checked depth (or At's); at the minor axis the share of the open crack's compliance shut."""
    def reference(params, at) -> Reference:
        depth = at.crack_depth_mm or headline_depth_mm(params)
        r = references(params, depth, state)
        if state == "minor":
            share = 1.0 - float(r["corrected"]) / float(references(params, depth, "major")["corrected"])
            return Reference(0.0, share, "1", "Newman-Raju's contact rule (K < 0 -> shut); published: the seed's "
                             "crack never shuts")
        return Reference(float(r["published"]), float(r["corrected"]), "rad/(N*mm)", "Newman-Raju integrated as seed 000 eq 4 "
                         "(analytic/surface_crack.py); published: the seed's through-wall crack")
    return reference


def surface_crack_checks(book: FeaBook, label: str | None, params, *, reference=None) -> list[Check]:
    """The three checks at the headline depth; ``reference(params, depth, state)`` replaces the closed forms
    (a test perturbs it)."""
    reference = reference or references
    depth = headline_depth_mm(params)
    block = _block(params, depth)
    tol_allow = allowances(block)
    out = []
    for check_id, state in CHECKS:
        analytic = reference(params, depth, state)
        if state == "minor":
            quantity = f"share of the open crack's compliance shut by face contact at the minor axis, a = {depth:g} mm"
            value, u, analytic = _shut_share(book, label or "", params, depth, reference(params, depth, "major")["corrected"])
            unit, basis = "1", "GCIs of both states, propagated"
        else:
            quantity = f"delta lambda_f of the tooth-root surface crack at the {state} state, a = {depth:g} mm"
            q, why = book.quantity(label or "", delta_name(state, depth)) if label else (None, "study not run")
            value, u, unit = (None, None, "rad/(N*mm)") if q is None else (q.value, q.uncertainty, "rad/(N*mm)")
            basis = gci_basis(q)
        if value is None:
            out.append(not_evaluated(check_id, quantity, unit, f"{STUDY}: no FEA value (case missing or failed)",
                                     analytic=analytic))
            continue
        tol = fea_tolerance(value, u, allowances=tol_allow, basis=basis)
        note = (f"a/c = {ASPECT:g}, a = {depth:g} mm in t = {block.t_mm:g} mm; wave generator + rated torque, "
                "crack-face normal stresses by analytic/surface_crack.py's map; corrected = Newman-Raju integrated "
                "as seed 000 eq 4 (K < 0 -> shut); published = the seed's through-wall crack")
        out.append(evaluate(Check(check_id, quantity, unit, value, u, analytic, "corrected", tol, note=note,
                                  sources={"fea": f"FEA {label}", "analytic": "analytic/surface_crack.py"})))
    return out


def surface_crack_record(book: FeaBook, label: str | None, params) -> dict:
    """Every depth and state beside Newman-Raju and the seed, and the breathing ripple at twice the input
    frequency in % of K_HD (the seed's corrected K_HD) per mm of depth."""
    from strainwave.analytic.seed000 import seed000_summary
    result = book.result(label or "")
    if result is None:
        return {}
    lam_total = 1.0 / seed000_summary(params)["K_HD"]["corrected"]
    rows = []
    for depth in result.meta.get("cracks", {}):
        a = float(depth)
        fea = {s: book.quantity(label, delta_name(s, a))[0] for s, _ in sc.STATES_DEG}
        row = {"depth_mm": a, "states": {}}
        for state, deg in sc.STATES_DEG:
            q = fea[state]
            row["states"][state] = {"phi_deg": deg, "fea": None if q is None else q.value,
                                    "gci": None if q is None else q.convergence.gci_fine,
                                    **references(params, a, state)}
        # Newman-Raju's breathing over a quarter revolution of the wave generator (0: major axis)
        row["newman_raju_by_phi"] = [[deg, references(params, a, None, deg)["corrected"]] for deg in range(0, 91, 5)]
        if fea["major"] is not None and fea["minor"] is not None:
            ripple = sc.ripple_percent(fea["major"].value, fea["minor"].value, lam_total)
            row["ripple_percent_of_K_HD"] = ripple
            row["ripple_percent_of_K_HD_per_mm"] = ripple / a
        rows.append(row)
    return {"study": STUDY, "case": label, "K_HD_Nmm_per_rad": 1.0 / lam_total, "depths": rows}
