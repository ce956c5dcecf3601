"""The scanner (seed 002 section 3.3): 0 <-> pi in 0.05 rad steps, overshooting pi by less than
a step, turning at both ends."""
import math

import pytest

from ptrz_camera import scanner


def test_positions_stay_in_range_and_reverse_at_both_ends():
    axis = scanner.ScanAxis()
    values = [axis.advance() for _ in range(500)]
    assert min(values) >= 0.0
    assert max(values) <= math.pi + scanner.STEP
    assert max(values) >= math.pi                      # the seed's overshoot past pi
    ups = [i for i in range(1, len(values) - 1) if values[i] > values[i - 1] and values[i] > values[i + 1]]
    downs = [i for i in range(1, len(values) - 1) if values[i] < values[i - 1] and values[i] < values[i + 1]]
    assert len(ups) >= 3 and len(downs) >= 3
    assert all(values[i] >= math.pi for i in ups)
    assert all(values[i] == pytest.approx(0.0, abs=1e-12) for i in downs)
    steps = [abs(b - a) for a, b in zip(values, values[1:])]
    assert max(steps) == pytest.approx(scanner.STEP) and min(steps) == pytest.approx(scanner.STEP)


def test_no_drift_after_many_cycles():
    axis = scanner.ScanAxis()
    for _ in range(100000):
        value = axis.advance()
        assert -1e-9 <= value <= math.pi + scanner.STEP


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError, match="positive"):
        scanner.ScanAxis(step=0)
    with pytest.raises(ValueError, match="above"):
        scanner.ScanAxis(lower=1, upper=0)
