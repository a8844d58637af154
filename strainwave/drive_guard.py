"""The one geometric consistency guard: the whole drive checked before any work, by every command.

Each section of the parameters checks its own keys (a crack against its own wall, a bore against its own
outer diameter). What no section can see is how the parts sit in each other; the CAD and the solvers find
that late (after seconds of CAD start-up) or never (a 100 mm w0 on a 52.8 mm bore solved to 1e5 MPa). Here,
from the parameters alone and with the parts' own construction rules (geometry/*.py):

- the cup: its length holds the tooth band and the diaphragm region;
- the bearing inner ring inside the cup's bore as built (race R = d1/2 - delta - t_o - D_w, bore R - t_i > 0), the
  cam inside the ring (semi-axes r_b +- w0: r_b - w0 > 0);
- w0 against each ring it bends: a ring r + w0 cos(U phi) keeps its curvature's sign only while
  w0 < r / (U^2 - 1) (linear ring theory: kappa = 1/r - (U^2 - 1) w0 cos(U phi) / r^2);
- the seed's contact patch on its ring: on the ring's face (sqrt(pi) a' < B), one patch per ball pitch 2 pi R / Z,
  and the ring (B = wave_generator.bearing_width_mm wide) inside the cup's length;
- the balls and the flexible outer ring between the inner ring's race and the cup's bore, the balls around
  their circle;
- the bearing's race crack (half length c from Q) inside the ring's width;
- the cup, bent to its major axis, inside the circular spline's rim, and the spline's teeth on the cup;
- the EWG drive: its generator's W0 = m dZ / 2 against the ring's radii.

A refusal names the user's own key (one line, exit 2) and, when the limit is derived, the keys it comes from.
"""
from __future__ import annotations

import math

from strainwave.errors import InputError

__all__ = ["check_drive"]


def check_drive(params) -> None:
    """Refuse (InputError naming the key) a parameter set whose parts cannot sit in each other."""
    _cup(params)
    _bearing_in_cup(params)
    _balls_and_outer_ring(params)
    _w0_against_rings(params)
    _contact_patch(params)
    _bearing_crack(params)
    _ewg(params)
    _cup_in_circular_spline(params)


def _cup(params) -> None:
    from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS, HUB_RATIO
    from strainwave.params import CupShape

    fc = params.flexspline_cup
    d1, t = fc.pitch_diameter_mm, fc.wall_thickness_mm
    band = BAND_RATIO * d1
    if fc.cup:   # geometry/flexspline_cup.build's own rule, checked before any CAD or meshing
        diaphragm = BOSS_HEIGHT_WALLS * t + (0.3 * (d1 / 2 - t - HUB_RATIO * d1) + t if fc.shape == CupShape.BELL else t)
        if fc.length_mm <= band + diaphragm:
            raise InputError("flexspline_cup.length_mm", fc.length_mm,
                             f"must exceed the tooth band 0.2 d1 plus the diaphragm region = {band + diaphragm:g} mm "
                             f"(from flexspline_cup.pitch_diameter_mm and wall_thickness_mm)")


def _radii(params) -> dict[str, float]:
    """The cup's and the bearing ring's radii as geometry/flexspline_cup.py and bearing_ring.py build them."""
    from strainwave.geometry.bearing_ring import race_radius_mm

    fc, t_i = params.flexspline_cup, params.wave_generator.bearing_inner_ring_thickness_mm
    bore = fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm
    race = race_radius_mm(params)
    return {"cup_mid": fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm / 2, "cup_bore": bore, "race": race,
            "ring_bore": race - t_i, "ring_mid": race - t_i / 2}


def _bearing_in_cup(params) -> None:
    t_i = params.wave_generator.bearing_inner_ring_thickness_mm
    r = _radii(params)
    if r["ring_bore"] <= 0:
        raise InputError("wave_generator.bearing_inner_ring_thickness_mm", t_i,
                         f"the bearing ring would close its bore inside the cup: need t_o + D_w + t_i < d1/2 - delta = "
                         f"{r['cup_bore']:g} mm (from flexspline_cup.pitch_diameter_mm, wall_thickness_mm and "
                         f"wave_generator.outer_ring_thickness_mm, ball_diameter_mm)")


def _balls_and_outer_ring(params) -> None:
    """The balls around the race's pitch circle (the ball and the outer ring set the race's radius as built:
    their room under the cup's bore is ``_bearing_in_cup``'s)."""
    wg = params.wave_generator
    r = _radii(params)
    circle = 2 * math.pi * (r["race"] + wg.ball_diameter_mm / 2)
    if wg.ball_count * wg.ball_diameter_mm >= circle:
        raise InputError("wave_generator.ball_count", wg.ball_count,
                         f"{wg.ball_count} balls of wave_generator.ball_diameter_mm = {wg.ball_diameter_mm:g} mm do not "
                         f"fit around the ball circle of {circle:g} mm")


def _w0_against_rings(params) -> None:
    w0, u = params.gear.radial_deformation_mm, params.gear.wave_number
    r = _radii(params)
    if w0 >= r["ring_bore"]:
        raise InputError("gear.radial_deformation_mm", w0,
                         f"must be < the bearing ring's bore radius {r['ring_bore']:g} mm: the cam's minor semi-axis "
                         f"r_b - w0 would vanish (r_b from flexspline_cup.pitch_diameter_mm, wall_thickness_mm, "
                         f"wave_generator.bearing_inner_ring_thickness_mm)")
    if u < 2:
        return
    for what, radius in (("the bearing ring's mid-radius", r["ring_mid"]), ("the cup's mid-radius", r["cup_mid"])):
        limit = radius / (u * u - 1)
        if w0 >= limit:
            raise InputError("gear.radial_deformation_mm", w0,
                             f"must be < {what} / (U^2 - 1) = {limit:g} mm (U = gear.wave_number = {u}): beyond it "
                             f"the ring bent into {u} waves turns its curvature inside out")


def _contact_patch(params) -> None:
    wg, fc = params.wave_generator, params.flexspline_cup
    a_c, b_c = wg.contact_semi_axes_mm
    key, width = "wave_generator.contact_semi_axes_mm", wg.bearing_width_mm
    # the seed's patch (seed 000's load on its ring); the contact as built is the ball's Hertz ellipse
    # (analytic/wg_contact.py, ~1 x 0.1 mm), judged by ISO 281/76, not this patch
    if math.sqrt(math.pi) * a_c >= width:
        raise InputError(key, [a_c, b_c], f"the patch's axial length sqrt(pi) a' = {math.sqrt(math.pi) * a_c:g} mm must "
                                          f"fit the ring's width wave_generator.bearing_width_mm = {width:g} mm")
    if width >= fc.length_mm:
        raise InputError("wave_generator.bearing_width_mm", width,
                         f"the bearing ring must fit inside the cup of flexspline_cup.length_mm = {fc.length_mm:g} mm")
    pitch = 2 * math.pi * _radii(params)["race"] / wg.ball_count
    if math.sqrt(math.pi) * b_c >= pitch:   # the patch's circumferential length (geometry/bearing_ring.py)
        raise InputError(key, [a_c, b_c], f"the patch's circumferential length sqrt(pi) b' = "
                                          f"{math.sqrt(math.pi) * b_c:g} mm overlaps the next ball's: the ball pitch "
                                          f"is {pitch:g} mm (wave_generator.ball_count = {wg.ball_count} on the race)")


def _bearing_crack(params) -> None:
    from strainwave.geometry.cracks import half_length_from_q

    wg = params.wave_generator
    c = half_length_from_q(wg.bearing_crack_depth_mm, params.cracks.surface_crack_shape_factor)
    width = wg.bearing_width_mm
    if 2 * c >= width:
        raise InputError("wave_generator.bearing_crack_depth_mm", wg.bearing_crack_depth_mm,
                         f"its surface length 2c = {2 * c:g} mm (c from cracks.surface_crack_shape_factor = "
                         f"{params.cracks.surface_crack_shape_factor:g}) must fit the ring's width {width:g} mm "
                         f"(wave_generator.bearing_width_mm)")


def _cup_in_circular_spline(params) -> None:
    """The cup, bent to its major axis (tooth tips at r_tip + w0), inside the circular spline's rim; its toothed rim
    (as wide as the spline's teeth) on the cup."""
    from strainwave.geometry.involute import cup_tooth_spec

    cs, fc = params.circular_spline, params.flexspline_cup
    reach = cup_tooth_spec(params).tip_radius_mm + params.gear.radial_deformation_mm
    if cs.outer_diameter_mm / 2 <= reach:
        raise InputError("circular_spline.outer_diameter_mm", cs.outer_diameter_mm,
                         f"must exceed the cup's tooth tips at the major axis, 2 (r_tip + w0) = {2 * reach:g} mm "
                         f"(from flexspline_cup.pitch_diameter_mm, module_mm, teeth and gear.radial_deformation_mm)")
    if cs.face_width_mm >= fc.length_mm:
        raise InputError("circular_spline.face_width_mm", cs.face_width_mm,
                         f"the teeth (and the cup's toothed rim, as wide) must be shorter than the cup, "
                         f"flexspline_cup.length_mm = {fc.length_mm:g} mm")


def _ewg(params) -> None:
    from strainwave.geometry.ewg_ring import radii_mm

    e = params.ewg_drive
    w0 = 0.5 * e.module_mm * e.tooth_difference   # seed 003, eq 7
    r = radii_mm(params)
    limit = r["r_m_mm"] / 3.0   # a two-wave ring (U = 2): r / (U^2 - 1)
    if w0 >= limit:
        raise InputError("ewg_drive.tooth_difference", e.tooth_difference,
                         f"the generator's W0 = m dZ / 2 = {w0:g} mm must be < the ring's mid-radius / 3 = {limit:g} mm "
                         f"(from ewg_drive.module_mm and flexspline_teeth): beyond it the ring turns inside out")
