"""Parametric CAD of the strain wave gear parts (build123d): solids, named faces, STEP, previews.

Entry points: ``strainwave.geometry.parts.build_part``, ``strainwave.geometry.export.export_part``,
``write_step`` / ``write_brep`` (export), ``render_preview`` (preview). Nothing is imported here, so
importing the package does no work.

Coordinate conventions (FEA relies on them). Every part's axis is z; lengths in mm.

- ``output-shaft``: z = 0 (end face ``fixed``) to L_s (end face ``loaded``); ``outer``, ``bore``.
  Crack: slot at z = shaft_axial_position_ratio L_s, centred on +x, over shaft_arc_deg.
- ``flexspline-cup``: hub/boss at z = 0 (its bottom face ``fixed``), diaphragm just above, open rim at
  z = L (``rim``). The band z in [L - 0.2 d1, L] is ``loaded`` (torque zone: teeth or smooth outer
  surface); ``tooth_flank`` the involute flanks; ``bore`` the inner cylinder r = d1/2 - delta; ``outer``
  the smooth outer wall r = d1/2 below the band. Crack: inclined root slot at the tooth space after
  tooth ``flexspline_tooth_index`` (angle (index + 1/2) 2 pi / Z from +x), z = ratio L.
- ``ewg-flexspline-ring``: z = 0 (``side_bottom``) to B (``side_top``); ``outer`` the smooth outer
  cylinder the EWG squeezes, ``contact`` the two outer strips at +/- y (+/- 2 deg, separate faces),
  ``bore`` everything inside, ``tooth_flank`` the involute flanks. ``Part.section``: the 2D xy Face,
  with the contact arcs as separate edges.
- ``wg-bearing-ring``: z = 0 to width (``side_bottom``, ``side_top``); ``bore``, ``race`` (outer),
  ``contact`` the imprinted patch at +x (area of the contact ellipse pi a' b'). Crack at +x, plane y = 0.
- ``ewg``: rollers at +/- y (two solids) or an elliptical cam ring, in the ring's frame, touching the
  ring's outer radius minus W0 = 0.5 m dZ on the minor axis (``meta['W0_mm']``); ``contact``.
- ``circular-spline``: z = 0 (``side_bottom``) to b (``side_top``), a tooth space on +x; ``rim`` (outer cylinder),
  ``tooth_flank``, ``tooth_tip``, ``tooth_root``, ``root_fillet``.
- ``wg-bearing-balls``, ``wg-bearing-outer-ring``: the wave generator's bearing as made (round), z = 0..width;
  ``assembly`` draws them, the cam and an inner ring from the same layout on the cam (``drive_assembly``).
- Crack faces: ``crack_face`` (slot walls), ``crack_front`` (slot floor and ends);
  ``Part.crack_front_mm`` samples points along the front for mesh size fields.
- ``Part.meta``: key dimensions (radii, r_m, rim thickness, W0_mm, teeth, closed-form volumes, ...).
"""
