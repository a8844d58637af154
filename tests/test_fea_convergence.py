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
    conv = grid_convergence(hs, values, formal_order=p_true)
    # An exact power law: the implicit order equation is solved to its iteration tolerance.
    assert conv.observed_order == pytest.approx(p_true, rel=1e-8)
    assert conv.extrapolated == pytest.approx(f_exact, rel=1e-9)
    assert conv.monotone and conv.asymptotic and conv.safety_factor == 1.25
    # GCI = 1.25 |e21| / (r^p - 1): here that is 1.25 times the true error of the finest value.
    true_rel_error = abs(values[0] - f_exact) / abs(values[0])
    assert conv.gci_fine == pytest.approx(1.25 * true_rel_error, rel=1e-6)


def test_order_independent_of_input_order():
    hs, values = [0.4, 0.1, 0.2], [1.16, 1.01, 1.04]
    a = grid_convergence(hs, values)
    b = grid_convergence(sorted(hs), [1.01, 1.04, 1.16])
    assert a == b and a.h_mm == (0.1, 0.2, 0.4)


def test_outside_the_asymptotic_range_the_formal_order_with_fs_3_is_used_and_the_observed_one_kept():
    # an exact power law of order 6 read as a P2 stress (formal 2): error cancellation, not asymptotic
    hs = [1.0, 1.4, 1.96]
    values = [1.0 + 0.01 * h ** 6 for h in hs]
    conv = grid_convergence(hs, values, formal_order=2.0)
    assert conv.observed_order == pytest.approx(6.0, rel=1e-8)        # never clipped (the old rule: 8)
    assert not conv.asymptotic and conv.order_used == 2.0 and conv.safety_factor == 3.0
    e_a21 = abs(values[1] - values[0]) / values[0]
    assert conv.gci_fine == pytest.approx(3.0 * e_a21 / (1.4 ** 2 - 1), rel=1e-12)
    assert conv.basis == "formal p = 2, Fs = 3"


@pytest.mark.parametrize("p_obs,asymptotic", [(1.79, False), (1.81, True), (2.19, True), (2.21, False)])
def test_the_asymptotic_band_is_ten_percent_of_the_formal_order(p_obs, asymptotic):
    hs = [1.0, 1.4, 1.96]
    conv = grid_convergence(hs, [3.0 + 0.02 * h ** p_obs for h in hs], formal_order=2.0)
    assert conv.asymptotic is asymptotic
    # outside the band: Fs = 3 with min(max(0.5, p_observed), p_formal) (Oberkampf & Roy)
    assert conv.order_used == pytest.approx(p_obs if asymptotic else min(p_obs, 2.0), rel=1e-8)
    assert conv.safety_factor == (1.25 if asymptotic else 3.0)


@pytest.mark.parametrize("p_obs,used", [(0.3, 0.5), (1.2, 1.2), (-1.0, 0.5)])
def test_a_slow_series_outside_the_range_keeps_its_own_lower_order_never_below_a_half(p_obs, used):
    hs = [1.0, 1.4, 1.96]
    values = [3.0 + 0.02 * h ** p_obs for h in hs]
    conv = grid_convergence(hs, values, formal_order=2.0)
    assert conv.order_used == pytest.approx(used, rel=1e-8) and conv.safety_factor == 3.0
    e_a21 = abs(values[1] - values[0]) / values[0]
    assert conv.gci_fine == pytest.approx(3.0 * e_a21 / (1.4 ** used - 1), rel=1e-8)
    # never smaller than the formal order's band would be: the slower order widens it
    assert conv.gci_fine >= 3.0 * e_a21 / (1.4 ** 2 - 1)


def test_oscillatory_sequence_reports_the_spread_or_the_formal_band():
    conv = grid_convergence([0.1, 0.2, 0.4], [1.00, 1.02, 0.99])
    assert not conv.monotone and math.isnan(conv.observed_order)
    # Richardson cannot be trusted when the sign of the change flips: the band covers the spread of all three
    # and is never below the formal-order band of the fine step
    assert conv.gci_fine == pytest.approx(max(1.25 * 0.03, 3 * 0.02 / (2.0 ** 2 - 1)), rel=1e-12)
    assert conv.extrapolated == 1.00


def test_identical_fine_values_carry_the_coarse_step_at_the_formal_order_never_zero():
    conv = grid_convergence([0.1, 0.2, 0.4], [2.0, 2.0, 2.1], formal_order=2.0)
    assert math.isinf(conv.observed_order) and not conv.asymptotic
    assert conv.gci_fine == pytest.approx(3.0 * 0.05 / (2 ** 2 - 1) / 2 ** 2, rel=1e-12)
    assert conv.gci_fine > 0


def test_three_identical_values_are_refused():
    from strainwave.fea.convergence import GciUndefined
    with pytest.raises(GciUndefined, match="three identical values"):
        grid_convergence([0.1, 0.2, 0.4], [2.5, 2.5, 2.5])


def test_needs_three_distinct_sizes():
    with pytest.raises(ValueError):
        grid_convergence([0.1, 0.1, 0.2], [1.0, 1.1, 1.2])


def test_crack_delta_uses_its_formal_order_with_fs_3_unless_the_observed_one_confirms_it():
    # irregular steps of a crack compliance: e32/e21 = 10 would mean p = 6.8 at r = 1.4 (GCI tiny);
    # at the formal first order with Fs = 3 the GCI is that of a first-order quantity, 2.4 x the Fs = 1.25 band
    from strainwave.fea.refinement import CRACK_FORMAL_ORDER
    h, v = (1.0, 1.4, 1.96), (1.0, 0.99, 0.89)
    conv = grid_convergence(h, v, formal_order=CRACK_FORMAL_ORDER)
    assert conv.observed_order > 6 and conv.order_used == 1.0
    assert conv.gci_fine == pytest.approx(3.0 * 0.01 / (1.4 - 1), rel=1e-12)
    # a first-order series in the band keeps its observed order and Fs = 1.25
    clean = grid_convergence(h, [2.0 + 0.1 * x ** 0.95 for x in h], formal_order=CRACK_FORMAL_ORDER)
    assert clean.asymptotic and clean.order_used == pytest.approx(0.95, rel=1e-8)


def test_stored_records_round_trip_and_legacy_ones_are_recomputed_by_the_rule():
    from strainwave.fea.result import Quantity
    conv = grid_convergence([1.0, 1.4, 1.96], [1.0, 1.01, 1.03], formal_order=1.0)
    q = Quantity("delta_flexibility_rad_per_Nmm", 1.0, "rad/(N*mm)", conv)
    assert Quantity.from_dict(q.to_dict()) == q
    legacy = {"name": q.name, "value": 1.0, "unit": q.unit, "convergence": {
        "h_mm": [1.0, 1.4, 1.96], "values": [1.0, 1.01, 1.03], "observed_order": 1.0, "extrapolated": 0.975,
        "gci_fine": 0.03, "monotone": True, "order_bounds": [1.0, 1.0]}}
    assert Quantity.from_dict(legacy).convergence == conv


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


def test_a_quantity_the_elements_hold_exactly_carries_a_refused_gci_not_zero():
    from strainwave.fea.refinement import converged_quantity
    q = converged_quantity("flexibility_rad_per_Nmm", "rad/(N*mm)", (1.0, 1.4, 1.96), (1.25e-9,) * 3)
    assert q.value == 1.25e-9 and q.uncertainty is None
    assert "three identical values" in q.convergence.refused and math.isnan(q.convergence.gci_fine)
    assert q.convergence.basis.startswith("GCI refused")
