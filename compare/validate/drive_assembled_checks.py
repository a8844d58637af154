"""Check ``gear.drive_assembled`` (issue 48, item 4; decision 073-assembled48): the drive as it carries torque,
assembled, against the chain of the same members in series.

- FEA: ``fea/drive_assembled.assemble``: the tooth-mesh study's teeth (its pair compliance on the rated contact set,
  from its record), the cup's wall on the wave generator's cam (3D, three meshes) and the wave generator's lobes as
  radial springs K_G (the wg-bearing FE's) solved together; K = the circular spline's twist against the wall's held
  end per unit torque.
- Reference: the same members in series, each loaded alone by the teeth's own share of the load: the teeth
  (L^T C^-1 L), the wall under a uniform shear, the wall's extra under the teeth's zones net of the plane rim the
  teeth's C already holds, the lobes. The series sum assumes the load share does not change when the members
  meet; the assembly lets it change (it can only stiffen: complementary energy).
- Tolerance: the GCI of assembled / chain on the same three wall meshes (the wall is in both sides, so its mesh
  error is common; the assembled K's own GCI is quoted in the note) + the Fourier truncation (K/2 against K
  harmonics of the teeth's load on the wall, finest mesh) + the members' own mesh error on their shares (a series
  error smaller than that cannot be told from the members'), each derived in the run.
- Beside it, not asserted: the chain validate's gear line used before (seed 000's lambda_H from K_G, the wall
  under a uniform shear only), so the note says what the old chain misses by.
"""
from __future__ import annotations

from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated

CHECK = "gear.drive_assembled"
STUDY = "tooth-mesh"


_LAST: list = []      # (the tooth-mesh result it was built from, K_G, the assembly): the gear line reads it too


def assembled(book, mesh_label: str | None, wg_label: str, params, memo: dict | None = None) -> tuple[dict | None, str]:
    """The assembly of this gear from the book (once per run: the check and the gear line share it), or None and
    why."""
    from strainwave.fea import drive_assembled as da
    if memo is not None and "drive_assembled" in memo:
        return memo["drive_assembled"]
    out: tuple[dict | None, str]
    kg, why = book.quantity(wg_label, "radial_stiffness_N_per_mm") if wg_label else (None, "no wg-bearing case")
    result = None if mesh_label is None or not hasattr(book, "result") else book.result(mesh_label)
    meta = None if result is None else result.meta
    if _LAST and _LAST[0][0] is result and result is not None and kg is not None and _LAST[0][1] == kg.value:
        return _LAST[0][2]
    if mesh_label is None:
        out = None, f"no {STUDY} case"
    elif kg is None:
        out = None, why
    elif not meta or not meta.get("rated_compliance"):
        out = None, f"case {mesh_label} recorded no rated contact set"
    else:
        try:
            out = da.assemble(meta, params, kg.value) | {"K_G": kg}, ""
        except ValueError as exc:
            out = None, str(exc)
    if memo is not None:
        memo["drive_assembled"] = out
    if result is not None and kg is not None:
        _LAST[:] = [(result, kg.value, out)]
    return out


def seed_lambda_H(params, K_G: float) -> float:
    from strainwave.analytic import torsion
    g, cup = params.gear, params.flexspline_cup
    return torsion.wave_generator_flexibility(g.force_coefficient, K_G, cup.pitch_diameter_mm, g.wave_number,
                                              g.radial_deformation_mm, g.gear_ratio)


def drive_check(book, mesh_label: str | None, wg_label: str, params, memo: dict | None = None) -> Check:
    cid, quantity, unit = CHECK, "drive stiffness at rated: teeth + cup wall + wave generator, assembled", "N*mm/rad"
    a, why = assembled(book, mesh_label, wg_label, params, memo)
    if a is None:
        return not_evaluated(cid, quantity, unit, why)
    K, f, ratio = a["K"], a["finest"], a["ratio"]
    ref = f.K_chain_Nmm_per_rad
    half = f.K_assembled_half_harmonics / f.K_chain_half_harmonics
    trunc = abs(half - f.K_assembled_Nmm_per_rad / ref)
    lam = 1.0 / ref
    rel = lambda q: abs((q.uncertainty or 0.0) / q.value) if q is not None else 0.0  # noqa: E731
    k3 = book.quantity(mesh_label, "K3_Nmm_per_rad")[0]
    members = f.lambda_teeth / lam * rel(k3) + f.lambda_wg_lobes / lam * rel(a["K_G"])
    # the wall's mesh error is in both sides: the comparison's GCI is the ratio's (K's own, below, is the number's)
    tol = fea_tolerance(1.0, ratio.uncertainty, basis=f"of assembled / chain on the same three walls; "
                                                      f"{gci_basis(ratio)}", allowances={
        "the Fourier truncation of the teeth's load on the wall (K/2 against K harmonics, finest wall)": trunc,
        "the members' own mesh error (the teeth's K3 GCI on their share, K_G's on the lobes')": members})
    old = 1.0 / (f.lambda_teeth + f.lambda_wall_uniform + seed_lambda_H(params, a["K_G"].value))
    note = (f"members in series (rad/(N mm)), each loaded by the teeth's own share: teeth (tooth-mesh C on "
            f"{len(a['rated_set'].phi_rad)} pairs at rated) {f.lambda_teeth:.4g}, wall uniform "
            f"{f.lambda_wall_uniform:.4g}, wall's zone extra net of the plane rim {f.lambda_zone_net:.4g} (gross "
            f"{f.lambda_zone_gross:.4g}, decision 067's cup-zone form), WG lobes (K_G {a['K_G'].value:.4g} N/mm) "
            f"{f.lambda_wg_lobes:.4g}; cam holds {100 * f.held_fraction:.3g} % of the band's bore; the previous chain "
            f"(seed 000's lambda_H {seed_lambda_H(params, a['K_G'].value):.4g}, no zone term) {old:.4g} N mm/rad, "
            f"assembled / previous {K.value / old:.4f} (not asserted); the assembled K's own GCI "
            f"{100 * rel(K):.3g} % (the cam's contact edge moves by an element between walls); {a['cpu_s']:.3g} CPU-s")
    return evaluate(Check(cid, quantity, unit, K.value, K.uncertainty, {"corrected": ref}, "corrected", tol,
                          note=note, sources={"fea": f"FEA drive-assembled ({mesh_label} teeth, wg_band wall, "
                                                     f"{wg_label} K_G)",
                                              "analytic": "the same members in series (fea/drive_assembled.py)"}))
