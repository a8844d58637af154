"""A toy study, declared in this one file plus one registry line (the ``toy_study`` fixture), runs through
every stage that reads a study: ``run_study`` (the element budget, the solve), validate's plan, the report's
inputs-and-model record and a sweep point. Nothing outside this file names it.

The toy is a cantilever strip in plane stress (length L and depth t from the output shaft's parameters, 1 mm
thick), clamped at x = 0 and loaded by a tip shear force P on x = L, on P2 triangles: its tip deflection
converges on three meshes and is compared with Timoshenko's beam, P L^3/(3 E I) + P L/(kappa G A).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from strainwave.analytic.rated_load import RatedLoad
from strainwave.fea.refinement import DEFAULT_RATIO, refinement_sizes
from strainwave.fea.result import Load, MeshQuality, Support
from strainwave.fea.skeleton import MeshSolve, SeriesPlan, StudyVariant, run_variant
from strainwave.params import load_params
from strainwave.registry import STUDIES, QuantitySpec, Study

TOY = "toy-strip"
TIP = "tip_deflection_mm"
FORCE_N = 100.0


def strip(params) -> tuple[float, float]:
    """(L, t) in mm: the strip's length and depth."""
    return params.output_shaft.length_mm, params.output_shaft.wall_mm


def timoshenko_tip_mm(params, force_N: float) -> dict[str, float]:
    """published: Euler-Bernoulli P L^3/(3 E I); corrected: plus the shear term P L/(kappa G A), kappa = 5/6."""
    L, t = strip(params)
    E, nu = params.material.youngs_modulus_MPa, params.material.poisson_ratio
    bending = force_N * L ** 3 / (3.0 * E * t ** 3 / 12.0)
    return {"published": bending, "corrected": bending + force_N * L / (5.0 / 6.0 * E / (2 * (1 + nu)) * t)}


def toy_rated(study, params, solved, quantities=None) -> RatedLoad:
    return RatedLoad(study, "tip force P", "N", solved, 2.0 * solved, "toy: twice the solved force")


def _solve(params, h_mm: float) -> tuple[float, MeshQuality, float]:
    from skfem import (Basis, ElementTriP2, ElementVector, FacetBasis, Functional, LinearForm, MeshTri, asm,
                       condense, solve)
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    L, t = strip(params)
    nx, ny = max(2, round(L / h_mm)), max(2, round(t / h_mm))
    mesh = MeshTri.init_tensor(np.linspace(0, L, nx + 1), np.linspace(0, t, ny + 1)).with_boundaries(
        {"fixed": lambda x: x[0] < 1e-9 * L, "loaded": lambda x: x[0] > L * (1 - 1e-9)})
    basis = Basis(mesh, ElementVector(ElementTriP2()))
    E, nu = params.material.youngs_modulus_MPa, params.material.poisson_ratio
    lam, mu = lame_parameters(E, nu)
    K = asm(linear_elasticity(2 * lam * mu / (lam + 2 * mu), mu), basis)     # plane stress lambda*
    end = FacetBasis(mesh, basis.elem, facets=mesh.boundaries["loaded"])

    @LinearForm
    def shear(v, w):
        return -FORCE_N / t * v[1]

    u = solve(*condense(K, asm(shear, end), D=basis.get_dofs("fixed")))
    tip = -Functional(lambda w: w["u"][1]).assemble(end, u=end.interpolate(u)) / t     # mean u_y of the end
    return tip, MeshQuality(mesh.t.shape[1], mesh.p.shape[1], basis.N, 2, 1.0, 1.0), L / nx


@dataclass(frozen=True)
class ToyStrip(StudyVariant):
    study: ClassVar[str] = TOY
    elements_per_cell: ClassVar[float] = 2.0          # init_tensor: two triangles per cell
    plane: ClassVar[bool] = True
    rated_load: ClassVar[str] = f"{__name__}:toy_rated"
    report_component: ClassVar[str] = "toy"
    title: ClassVar[str] = "toy cantilever strip"
    element_text: ClassVar[str] = "P{order} triangles, plane stress, toy strip"
    params: object
    h_fine_mm: float

    @classmethod
    def default_size_mm(cls, params, quick: bool) -> float:
        return strip(params)[1] / (2.0 if quick else 3.0)

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        L, t = strip(params)
        return L * t, t

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        L, t = strip(params)
        return (("length L", f"{L:g} mm"), ("depth t", f"{t:g} mm"))

    def build(self):
        return None

    def series(self):
        return (SeriesPlan("strip", refinement_sizes(self.h_fine_mm, DEFAULT_RATIO)),)

    def solve(self, parts, series, refinement, k, keep_fields, progress) -> MeshSolve:
        tip, mesh, h = _solve(self.params, refinement)
        return MeshSolve(h, {TIP: tip}, mesh)

    def quantities(self, series):
        return {TIP: series["strip"].converged(TIP, "mm")}

    def load(self, parts) -> Load:
        return Load("tip force P", FORCE_N, "N", ("loaded",), "uniform shear traction P / t on x = L")

    def supports(self):
        return (Support(("fixed",), "end x = 0 clamped"),)


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None, quick=False):
    return run_variant(ToyStrip(params, mesh_size_mm or ToyStrip.default_size_mm(params, quick)), progress=progress)


@pytest.fixture
def toy_study(monkeypatch):
    """The one registry line."""
    monkeypatch.setitem(STUDIES, TOY, Study(TOY, f"{__name__}:ToyStrip", "output-shaft", None, None,
                                            (QuantitySpec(TIP, "mm", "tip deflection under P", "flexibility"),)))
    return STUDIES[TOY]


@pytest.fixture(scope="module")
def params():
    return load_params()


def test_the_toy_study_solves_through_run_study(toy_study, params):
    from strainwave.fea.budget import estimate
    from strainwave.fea.studies import run_study

    result = run_study(TOY, params, quick=True)
    tip = result.quantities[TIP]
    ref = timoshenko_tip_mm(params, FORCE_N)["corrected"]
    assert abs(tip.value / ref - 1.0) < 0.02                       # the beam it models
    assert tip.uncertainty is not None and tip.uncertainty > 0     # three different meshes
    est = estimate(TOY, params, None, quick=True)
    assert 0.5 < est.elements / result.mesh.elements < 2.0         # its own element estimate


def test_the_toy_study_is_in_the_plan_the_report_and_a_sweep(toy_study, params, tmp_path):
    from strainwave.compare.sweep.task import PointSpec, point_key, run_point
    from strainwave.compare.validate.inputs import component_inputs
    from strainwave.compare.validate.plan import make_plan
    from strainwave.fea.studies import run_study
    from strainwave.rated_stress import rated_load_of

    plan = make_plan(params, quick=True)
    case = plan.case_of(TOY)
    assert case is not None and case in plan.all_cases() and ("toy", case) in plan.reported()

    result = run_study(TOY, params, quick=True)
    rated = rated_load_of(TOY, params, result)
    assert rated.rated == 2.0 * FORCE_N
    inputs = component_inputs("toy", case, result, params, rated).to_dict()
    assert inputs["element"] == "P2 triangles, plane stress, toy strip"
    assert ["length L", f"{params.output_shaft.length_mm:g} mm"] in inputs["dimensions"]
    assert inputs["meshes"][0]["dofs"] == result.mesh.dofs

    spec = PointSpec(TOY, (("output_shaft.length_mm", 150.0),), params.to_dict(), quick=True)
    record = run_point(spec, point_key(spec, None), str(tmp_path))
    assert record["status"] == "ok", record.get("error")
    shorter = params.with_value("output_shaft.length_mm", 150.0)
    tip = record["fea"][TIP]["value"]
    assert tip == pytest.approx(run_study(TOY, shorter, quick=True).quantities[TIP].value, rel=1e-12)
    assert abs(tip / timoshenko_tip_mm(shorter, FORCE_N)["corrected"] - 1.0) < 0.02
