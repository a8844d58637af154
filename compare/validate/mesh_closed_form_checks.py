"""Closed forms beside the tooth-mesh study (issue 48, item 3), each a check that can fail.

- ``mesh.rigid_rim_sharing``: the study's frictional contact solve (fea/mesh_contact.py) of the headline
  wave-generator angle, with the FE's own flank-pair compliances but the rim's coupling removed (teeth on a rigid
  rim: the diagonal of the flexibility), first loading to rated torque, against the rigid rim's closed-form
  distribution F_i = max(0, a_i t - g_i) / c_i with t from the torque balance sum (|lever_i| + mu |slide_i|) F_i = T,
  solved by sorting the clearances (analytic/rigid_rim_sharing.py; no contact solver). Like against like: the same
  clearances, levers, slides, mu and pair compliances (the finest mesh's, read from the study's record), so it
  catches an error in the contact solver or in how the study sums the loads into the torque. Asserted: the peak
  pair's share of the flank loads at rated; the pairs in contact and the twist are in the note, and the FE's
  coupled result (the rim's give shares the load differently) beside it, not asserted.
  Tolerance = the GCI of the FE reading (Fs once). No other allowance: for the same inputs the closed form is the
  exact solution of the same contact problem (the solver's own round-off is ~1e-12).
"""
from __future__ import annotations

from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, gci_basis, not_evaluated

STUDY = "tooth-mesh"
SHARE = "rigid_rim_peak_tooth_share"


def rigid_rim_reference(inputs: dict):
    """The closed form on the inputs the study's rigid-rim solve took (its record ``meta['rigid_rim']``)."""
    from strainwave.analytic.rigid_rim_sharing import rigid_rim_sharing
    return rigid_rim_sharing(inputs["clearance_mm"], inputs["compliance_mm_per_N"], inputs["lever_mm"],
                             inputs["slide_mm_per_rad"], inputs["friction_coefficient"], inputs["torque_Nmm"])


def _beside(book, label: str) -> str:
    got = {k: book.quantity(label, k)[0] for k in ("peak_tooth_share", "teeth_in_contact_rated")}
    if any(v is None for v in got.values()):
        return "the coupled FE result: n/a"
    return (f"the FE's coupled rim (beside, not asserted): peak share {got['peak_tooth_share'].value:.4g}, "
            f"{got['teeth_in_contact_rated'].value:.0f} pairs in contact")


def rigid_rim_check(book, label: str | None, params) -> Check:
    cid, quantity, unit = "mesh.rigid_rim_sharing", "peak flank pair's share of the load at rated, rigid rim", "1"
    q, why = (None, f"no {STUDY} case") if label is None else book.quantity(label, SHARE)
    result = None if q is None else book.result(label)
    inputs = None if result is None else result.meta.get("rigid_rim")
    if q is None or not inputs:
        return not_evaluated(cid, quantity, unit, why or f"case {label} recorded no rigid-rim solve")
    ref = rigid_rim_reference(inputs)
    tol = fea_tolerance(q.value, q.uncertainty, allowances={}, basis=gci_basis(q))
    n_fe = sum(1 for f in inputs["forces_N"] if f > 0.0)
    note = (f"headline WG angle, first loading to {inputs['torque_Nmm'] / 1e3:.4g} N m, mu = "
            f"{inputs['friction_coefficient']:g}, {len(inputs['clearance_mm'])} flank pairs; pairs in contact: "
            f"contact solve {n_fe}, closed form {ref.teeth_in_contact}; twist: contact solve "
            f"{inputs['twist_rad']:.6g} rad, closed form {ref.twist_rad:.6g} rad; {_beside(book, label)}")
    check = evaluate(Check(cid, quantity, unit, q.value, q.uncertainty, {"corrected": ref.peak_share}, "corrected",
                           tol, note=note, sources={"fea": f"FEA {label} (contact solve, rim coupling removed)",
                                                    "analytic": "analytic/rigid_rim_sharing.py"}))
    return check
