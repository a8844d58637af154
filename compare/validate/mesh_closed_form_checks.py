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
- ``mesh.engagement_zone``: the edge of the engagement zone. FE side: the outermost flank pair the study's contact
  solve loads at rated (headline WG angle, first loading; its angle from the major axis folded into the lobe).
  Closed form: the kinematic theory's zone edge, where the rigid tooth's tip, riding the inextensible neutral line
  (w = w0 cos 2 phi, v = -(w0/2) sin 2 phi), reaches the circular spline's flank (analytic/engagement_zone.py,
  written out by hand, not the study's engagement). Beyond it rigid teeth would cut into each other, and the gap
  narrows towards it, so the pair nearest the edge loads first (the first load step's edge is in the note).
  Tolerance = GCI + one FS pitch over the edge angle (the loaded teeth stand on the pitch: the outermost is up to a
  pitch inside the edge) + the contact point (the study takes it at the middle of the radial overlap, the closed
  form at the tip: the closed form's own edge at the mid-overlap radius, over the edge angle).
"""
from __future__ import annotations

import math

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
    return evaluate(Check(cid, quantity, unit, q.value, q.uncertainty, {"corrected": ref.peak_share}, "corrected",
                          tol, note=note, sources={"fea": f"FEA {label} (contact solve, rim coupling removed)",
                                                   "analytic": "analytic/rigid_rim_sharing.py"}))


ZONE = "engagement_edge_rated_rad"


def zone_reference(params) -> tuple[float, float]:
    """(the zone's edge at the tooth tip, at the middle of the radial overlap there), rad."""
    from strainwave.analytic.engagement_zone import zone_edge_rad
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    tip = zone_edge_rad(geo)
    depth = geo.fs.tip_radius_mm + geo.w0_mm * math.cos(2 * tip) - geo.cs_tip_mm
    return tip, zone_edge_rad(geo, geo.fs.tip_radius_mm - 0.5 * depth)


def zone_allowances(params, edge_rad: float, mid_rad: float) -> dict[str, float]:
    pitch = 2 * math.pi / params.flexspline_cup.teeth
    return {f"one FS pitch ({math.degrees(pitch):.3g} deg) over the edge angle (the loaded teeth stand on the pitch)":
            pitch / edge_rad,
            "contact at the middle of the radial overlap (the study) vs the tip (the closed form)":
            abs(edge_rad - mid_rad) / edge_rad}


def zone_check(book, label: str | None, params) -> Check:
    cid, quantity, unit = ("mesh.engagement_zone", "edge of the engagement zone: outermost loaded pair at rated, "
                           "from the major axis", "rad")
    edge, mid = zone_reference(params)
    q, why = (None, f"no {STUDY} case") if label is None else book.quantity(label, ZONE)
    if q is None:
        return not_evaluated(cid, quantity, unit, why, analytic={"corrected": edge})
    tol = fea_tolerance(q.value, q.uncertainty, allowances=zone_allowances(params, edge, mid), basis=gci_basis(q))
    first, _ = book.quantity(label, "engagement_edge_first_step_rad")
    note = (f"closed form: the tooth tip's path on the neutral line reaches the CS flank at {math.degrees(edge):.4g} "
            "deg "
            f"({math.degrees(mid):.4g} deg at the middle of the overlap); the contact solve's outermost loaded pair at "
            f"rated {math.degrees(q.value):.4g} deg, at its first load step (a small torque) "
            f"{'n/a' if first is None else format(math.degrees(first.value), '.4g')} deg")
    return evaluate(Check(cid, quantity, unit, q.value, q.uncertainty, {"corrected": edge}, "corrected", tol,
                          note=note, sources={"fea": f"FEA {label} (contact solve)",
                                              "analytic": "analytic/engagement_zone.py (kinematic theory)"}))
