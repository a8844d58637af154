"""The typed study result and the one skeleton's loop: JSON round trip (the result cache rebuilds cases from
it), refusals of impossible records, the three-mesh order, and fea/'s independence from analytic/."""
from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

from strainwave.fea.convergence import grid_convergence
from strainwave.fea.refinement import on_three_meshes, refinement_sizes
from strainwave.fea.result import CrackRecord, Load, MeshQuality, Quantity, StudyResult, Support

FEA = Path(__file__).resolve().parents[1] / "fea"


def _result() -> StudyResult:
    conv = grid_convergence([1.0, 1.4, 1.96], [2.0, 2.01, 2.03])
    q = {"delta_cd_mm": Quantity("delta_cd_mm", 2.0, "mm", conv), "plain": Quantity("plain", 1.0, "1")}
    return StudyResult("ring-compression", q, MeshQuality(10, 20, 40, 2, 0.5, 0.8),
                       Load("diametral force F", 33.76, "N", ("contact",), "arcs", (("half_angle_rad", 0.02),)),
                       (Support(("A", "B"), "u_y = 0"), Support(("D",), "u_x = 0")),
                       CrackRecord(0.5, "seam", 12.0), {"total": 1.0}, (Path("f.vtu"),), {"method": "direct"},
                       {"note": "x"}, (MeshQuality(10, 20, 40, 2, 0.5, 0.8),) * 3)


def test_json_round_trip_keeps_every_typed_field():
    r = _result()
    assert StudyResult.from_dict(r.to_dict()) == r
    assert r.load.force_N == 33.76 and r.load.parameter("half_angle_rad") == 0.02 and r.crack_depth_mm == 0.5


def test_an_entry_of_the_layout_before_typed_loads_is_refused_not_misread():
    # the result cache recomputes a case whose stored layout it cannot read (runner catches KeyError)
    old = _result().to_dict()
    del old["load"]
    with pytest.raises(KeyError):
        StudyResult.from_dict(old)


@pytest.mark.parametrize("magnitude, unit, on", [(0.0, "N", ("a",)), (math.nan, "N", ("a",)),
                                                 (1.0, "kN", ("a",)), (1.0, "N", ())])
def test_impossible_loads_are_refused(magnitude, unit, on):
    with pytest.raises(ValueError):
        Load("F", magnitude, unit, on, "somewhere")


def test_a_torque_is_not_a_force_and_a_result_states_its_supports():
    torque = Load("output torque T", 1000.0, "N*mm", ("loaded",), "shear")
    assert torque.force_N is None
    with pytest.raises(ValueError):
        StudyResult("shaft-torsion", {}, MeshQuality(1, 1, 1, 2, 1.0, 1.0), torque, ())
    with pytest.raises(ValueError):
        CrackRecord(0.0, "seam")


def test_three_meshes_run_coarse_to_fine_and_come_back_finest_first():
    sizes = refinement_sizes(2.0)
    seen = []
    out = on_three_meshes(lambda h, k: seen.append((h, k)) or h * 10, sizes)
    assert seen == [(sizes[2], 2), (sizes[1], 1), (sizes[0], 0)]     # the coarse mesh first: cheap failures first
    assert out == tuple(h * 10 for h in sizes)
    with pytest.raises(ValueError):
        on_three_meshes(lambda h, k: h, sizes[:2])


def test_fea_imports_no_closed_form():
    # issue 11: closed forms live only in analytic/; a study receives a seed-formula load as numbers
    offenders = []
    for path in FEA.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and "analytic" in (node.module or ""):
                offenders.append(f"{path.name}: from {node.module}")
            elif isinstance(node, ast.Import):
                offenders += [f"{path.name}: import {a.name}" for a in node.names if "analytic" in a.name]
    assert not offenders


@pytest.mark.parametrize("kwargs", [dict(order=3), dict(h_fine_mm=0.0), dict(force_N=-1.0),
                                    dict(crack_depth_mm=0.0), dict(force_N=math.inf)])
def test_a_variant_refuses_what_no_solve_could_use(kwargs):
    from strainwave.fea.bearing_ring import BearingRing
    good = dict(params=None, order=2, h_fine_mm=5.0, force_N=2.5, crack_depth_mm=None)
    BearingRing(**good)                     # the good record is accepted: the refusals below are the inputs'
    with pytest.raises(ValueError):
        BearingRing(**(good | kwargs))
