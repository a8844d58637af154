"""A loop with backlash crosses its band at 0 N m: a reading grid point there keeps the twist the drive arrives
with (decision 076), whatever round-off the solve leaves on the band's knots."""
import numpy as np
import pytest

from strainwave.fea import mesh_loop


def _band_loop(eps: float) -> tuple[np.ndarray, np.ndarray]:
    """0 -> +1 -> -1 -> +1 on a unit stiffness past a +-0.1 band; the band's knots at +-eps N m of round-off."""
    b = 0.1
    T = np.array([0.0, eps, 1.0, -eps, eps, -1.0, eps, -eps, 1.0])
    th = np.array([0.0, b, 1.0 + b, b, -b, -1.0 - b, -b, b, 1.0 + b])
    return T, th


@pytest.mark.parametrize("eps", [0.0, 1e-13, -1e-13, 3e-11])
def test_the_grid_at_zero_torque_keeps_the_arrival_twist(eps):
    grid, th = mesh_loop.resample(*_band_loop(eps), 4)
    at_zero = th[grid == 0.0]
    # the start at rest, the unloading leg arriving from +T (+band), the reloading leg from -T (-band)
    assert at_zero == pytest.approx([0.0, 0.1, -0.1])
    # off the band the loop is linear between its knots: interpolation exact
    assert th[grid == 0.5] == pytest.approx([0.6, 0.6, 0.6])
    assert th[grid == -0.5] == pytest.approx([-0.6, -0.6])
