"""Torque as a tangential traction, twist as a mean face rotation, and the load and supports hooks: shared by
the torsion studies."""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from strainwave.fea.result import Load, Support
from strainwave.fea.study_facts import TORQUE_RATED
from strainwave.fea.skeleton import StudyVariant
from strainwave.fea.static import StaticSolution


def saint_venant_traction(torque_Nmm: float, J_mm4: float):
    """tau = T r / J e_theta, i.e. t = (T/J)(-y, x, 0): the exact end shear of a circular (hollow) section."""
    def traction(x):
        return np.stack([-torque_Nmm * x[1] / J_mm4, torque_Nmm * x[0] / J_mm4, np.zeros_like(x[0])])
    return traction


def uniform_tangential_traction(torque_Nmm: float, moment_arm_mm3: float):
    """t = c e_theta with c = T / int r dA: constant tangential shear whose moment about z is exactly T."""
    c = torque_Nmm / moment_arm_mm3

    def traction(x):
        r = np.sqrt(x[0] ** 2 + x[1] ** 2)
        return np.stack([-c * x[1] / r, c * x[0] / r, np.zeros_like(x[0])])
    return traction


def moment_arm_mm3(sol: StaticSolution, group: str) -> float:
    """int r dA over a named group (curved P2 facets, so r follows the true surface)."""
    q = sol.surface(group)
    return q.integrate(np.hypot(q.x[..., 0], q.x[..., 1]))


def mean_rotation_rad(sol: StaticSolution, group: str) -> float:
    """Area-weighted mean rotation about z of a face set: int (x u_y - y u_x)/r^2 dA / A."""
    q = sol.surface(group)
    u = q.interpolate(sol.nodal_u())
    x, y = q.x[..., 0], q.x[..., 1]
    return q.integrate((x * u[..., 1] - y * u[..., 0]) / (x ** 2 + y ** 2)) / q.area


@dataclass(frozen=True)
class TorsionVariant(StudyVariant):
    """The hooks both torsion studies share: seed 000's output torque T on the 'loaded' faces, spread as the
    study's ``load_distribution`` says, and the 'fixed' faces (``clamped_face``) clamped; and the fields
    both are made of (a study adds its own after them)."""

    load_distribution: ClassVar[str]
    clamped_face: ClassVar[str]
    image_marks: ClassVar[tuple] = (("fixed",), "loaded", "T")
    rated_load: ClassVar[str] = TORQUE_RATED
    params: object
    order: int
    h_fine_mm: float
    ratio: float
    crack_depth_mm: float | None

    def load(self, parts) -> Load:
        return Load("output torque T", self.params.gear.output_torque_Nmm, "N*mm", ("loaded",),
                    self.load_distribution)

    def supports(self) -> tuple[Support, ...]:
        return (Support(("fixed",), f"{self.clamped_face} clamped (all displacement components zero)"),)


def torsion_meta(params, order: int, ratio: float, sizes_mm) -> dict:
    """What a reader of a torsion study's result needs to reproduce it: twist definition, moduli, sizes."""
    mat = params.material
    return {"twist": "area-weighted mean rotation of 'loaded'", "G_fea_MPa": mat.implied_shear_modulus_MPa,
            "mu_seed_MPa": mat.shear_modulus_MPa, "order": order, "refinement_ratio": ratio,
            "mesh_sizes_mm": list(sizes_mm)}
