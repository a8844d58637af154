"""The flexspline tooth's root stress from the mesh load beside the design verdict (issue 48, item 2): the
tooth-mesh FE's filleted sector (fea/tooth_root_fe.py, per mesh: GCI) and ISO 6336-3 method B on the same tooth,
fillet, load and load radius (analytic/tooth_root_iso.py), with their difference."""
from __future__ import annotations

__all__ = ["tooth_root_record", "tooth_root_line"]


def tooth_root_record(params, book, label: str | None) -> dict | None:
    """FE peak (GCI) and ISO's closed form at the FE's load (the most loaded tooth at rated), or None."""
    if not label:
        return None
    q = {n: book.quantity(label, n)[0] for n in ("root_stress_peak_tooth_MPa", "peak_tooth_load_N",
                                                 "root_contact_radius_mm")}
    if any(v is None for v in q.values()):
        return None
    from strainwave.analytic.tooth_root_iso import iso_root_stress
    from strainwave.fea.tooth_root_fe import fillet_geometry
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    fil = fillet_geometry(geo.fs)
    F = q["peak_tooth_load_N"].value
    iso = iso_root_stress(geo.fs, fil["rho_mm"], fil["dphi_rad"], q["root_contact_radius_mm"].value, F,
                          geo.face_width_mm, geo.r_bore_mm)
    fe = q["root_stress_peak_tooth_MPa"]
    return {"fe_MPa": fe.value, "fe_gci_MPa": fe.uncertainty, "load_N": F,
            "contact_radius_mm": q["root_contact_radius_mm"].value, "iso_MPa": iso.stress_MPa,
            "iso_nominal_MPa": iso.nominal_MPa, "Y_S": iso.Y_S, "Y_B": iso.Y_B, "s_Fn_mm": iso.s_Fn_mm,
            "h_Fe_mm": iso.h_Fe_mm, "rho_F_mm": iso.rho_F_mm, "fe_over_iso": fe.value / iso.stress_MPa,
            # the FE's rim sits on a radially held bore (the rigid WG): ISO's thin-rim Y_B assumes a rim free to bend
            "fe_over_iso_without_Y_B": fe.value * iso.Y_B / iso.stress_MPa}


def tooth_root_line(r: dict) -> str:
    gci = "no GCI" if r.get("fe_gci_MPa") is None else f"GCI +- {r['fe_gci_MPa']:.3g} MPa"
    return (f"Tooth-root stress from the mesh load (the most loaded flexspline tooth at rated, {r['load_N']:.4g} N at "
            f"r = {r['contact_radius_mm']:.4g} mm): FE {r['fe_MPa']:.4g} MPa ({gci}; peak max-principal on the "
            f"root fillet, rho = {r['rho_F_mm']:.3g} mm); ISO 6336-3 method B on the same tooth and load "
            f"{r['iso_MPa']:.4g} MPa (nominal {r['iso_nominal_MPa']:.4g} x Y_S {r['Y_S']:.3g} x Y_B {r['Y_B']:.3g}; "
            f"s_Fn {r['s_Fn_mm']:.3g}, h_Fe {r['h_Fe_mm']:.3g} mm): FE/ISO = {r['fe_over_iso']:.3g}, "
            f"{r['fe_over_iso_without_Y_B']:.3g} without Y_B (the FE's rim is held radially by the wave generator, "
            "ISO's thin rim bends free; ISO's Y_S is fitted on generated trochoid roots of longer teeth)")
