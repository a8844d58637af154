"""The GCI machinery on sequences whose exact limit and order are known."""
import math

import pytest

from strainwave.fea.convergence import grid_convergence


@pytest.mark.parametrize("p_true,ratios", [(2.0, (2.0, 2.0)), (3.0, (1.5, 1.5)), (2.0, (1.3, 1.7)), (1.0, (2.0, 1.4))])
def test_recovers_order_and_limit_of_a_power_law(p_true, ratios):
    f_exact, c = 1.2345, 0.37
    h1 = 0.1
    hs = [h1, h1 * ratios[0], h1 * ratios[0] * ratios[1]]
    values = [f_exact + c * h ** p_true for h in hs]
    conv = grid_convergence(hs, values)
    # An exact power law: the implicit order equation is solved to its iteration tolerance (1e-10).
    assert conv.observed_order == pytest.approx(p_true, rel=1e-8)
    assert conv.extrapolated == pytest.approx(f_exact, rel=1e-9)
    assert conv.monotone
    # GCI = 1.25 |e21| / (r^p - 1): here that is 1.25 times the true error of the finest value.
    true_rel_error = abs(values[0] - f_exact) / abs(values[0])
    assert conv.gci_fine == pytest.approx(1.25 * true_rel_error, rel=1e-6)


def test_order_independent_of_input_order():
    hs, values = [0.4, 0.1, 0.2], [1.16, 1.01, 1.04]
    a = grid_convergence(hs, values)
    b = grid_convergence(sorted(hs), [1.01, 1.04, 1.16])
    assert a == b and a.h_mm == (0.1, 0.2, 0.4)


def test_oscillatory_sequence_reports_the_spread():
    conv = grid_convergence([0.1, 0.2, 0.4], [1.00, 1.02, 0.99])
    assert not conv.monotone
    # Richardson cannot be trusted when the sign of the change flips: the band covers the spread of all three.
    assert conv.gci_fine == pytest.approx(1.25 * 0.03, rel=1e-12)
    assert conv.extrapolated == 1.00


def test_identical_fine_values_mean_no_resolvable_error():
    conv = grid_convergence([0.1, 0.2, 0.4], [2.0, 2.0, 2.1])
    assert conv.gci_fine == 0.0 and math.isinf(conv.observed_order)


def test_needs_three_distinct_sizes():
    with pytest.raises(ValueError):
        grid_convergence([0.1, 0.1, 0.2], [1.0, 1.1, 1.2])


def test_crack_order_is_fixed_at_its_formal_value():
    # irregular steps of a crack compliance: e32/e21 = 10 would mean p = 6.8 at r = 1.4 (GCI tiny);
    # fixed at the formal first order (CRACK_ORDER_BOUNDS = (1, 1)), the GCI is that of a first-order quantity
    from strainwave.fea.convergence import grid_convergence
    from strainwave.fea.refinement import CRACK_ORDER_BOUNDS
    h, v = (1.0, 1.4, 1.96), (1.0, 0.99, 0.89)
    free = grid_convergence(h, v)
    fixed = grid_convergence(h, v, min_order=CRACK_ORDER_BOUNDS[0], max_order=CRACK_ORDER_BOUNDS[1])
    assert free.observed_order > 6
    assert fixed.observed_order == 1.0
    assert fixed.gci_fine == pytest.approx(1.25 * 0.01 / (1.4 - 1), rel=1e-12)
    assert fixed.gci_fine > 10 * free.gci_fine


def test_crack_front_grading_refines_the_tip_with_the_mesh_and_keeps_its_zones():
    """The shaft's and the cup's gradings (the values their studies measured): the tip is tip_over_a a on the
    finest mesh and scales with h / h_fine on the coarser ones (so the GCI sees the tip converge), the floor
    holds shallow cracks at floor_over_h h_fine, and the graded zone ends at zone a + grow h."""
    from strainwave.fea import cup_torsion, shaft_torsion
    from strainwave.fea.refinement import refinement_sizes

    front = ((10.0, 0.0, 5.0), (10.0, 1.0, 5.0))
    h_fine = 6.72
    cup = [cup_torsion.CRACK_FRONT.refine(front, h, h_fine, 1.12) for h in refinement_sizes(h_fine)]
    assert [r.size_mm for r in cup] == pytest.approx([0.28, 0.28 * 1.4, 0.28 * 1.96])
    assert [r.dist_min_mm for r in cup] == pytest.approx([1.12, 1.12, 1.12])       # uniform within a
    assert cup[0].dist_max_mm == pytest.approx(2 * 1.12 + 3 * h_fine)
    assert cup[0].points_mm == front
    shaft = shaft_torsion.CRACK_FRONT
    deep, shallow = shaft.refine(front, 8.33, 8.33, 3.13), shaft.refine(front, 8.33, 8.33, 0.1)
    assert deep.size_mm == pytest.approx(3.13 / 6) and deep.dist_min_mm == pytest.approx(3.13 / 2)
    assert shallow.size_mm == pytest.approx(8.33 / 32)                             # the floor, not a/6
    assert shallow.dist_min_mm == pytest.approx(8.33 / 32)                         # never below the tip
    assert shallow.dist_max_mm == pytest.approx(3 * 0.1 + 8.33)
