"""Object detection from a scan (pure): run splitting, the seed's formula and its frame, centres
of synthetic cans within 1 cm."""
import math

import pytest

from katana_sim.detection import cast_circles, detect, laser_xy, seed_xy, split_runs
from katana_sim.errors import DetectionError

INF = float("inf")


@pytest.mark.parametrize("ranges, runs", [
    ([INF, 0.5, 0.5, INF, 0.4, INF], [(1, 2), (4, 4)]),
    ([0.5, 0.5, INF], [(0, 1)]),                          # a run at the start
    ([INF, 0.3, 0.3], [(1, 2)]),                          # a run at the end
    ([0.01, 0.5, 0.5, 2.0, 0.6], [(1, 2), (4, 4)]),       # below range_min / above range_max break runs
    ([float("nan"), 0.5, float("nan")], [(1, 1)]),        # NaN is out of range
    ([INF, INF], []),
    ([], []),
])
def test_runs_of_in_range_beams_are_objects(ranges, runs):
    assert split_runs(ranges, 0.03, 1.0) == runs


def test_a_depth_jump_splits_two_objects_that_touch_in_angle():
    ranges = [INF, 0.30, 0.30, 0.50, 0.50, INF]
    assert split_runs(ranges, 0.03, 1.0) == [(1, 4)]                   # the seed's rule alone
    assert split_runs(ranges, 0.03, 1.0, max_jump=0.05) == [(1, 2), (3, 4)]


def test_seed_formula_as_written_and_its_frame():
    # the seed's angle is measured from its y axis towards its x axis
    assert seed_xy(0.0, 2.0) == pytest.approx((0.0, 2.0))
    assert seed_xy(math.pi / 2, 2.0) == pytest.approx((2.0, 0.0))
    # in the laser frame (x ahead, y left, angles counter-clockwise from x) that is a swap
    for a in (-1.2, -0.3, 0.0, 0.4, 1.5):
        x, y = laser_xy(a, 0.7)
        assert (x, y) == pytest.approx((0.7 * math.cos(a), 0.7 * math.sin(a)))


CANS = [(0.315, 0.15, 0.033), (0.265, -0.10, 0.033)]


@pytest.mark.parametrize("samples", [181, 361, 720])
def test_synthetic_cans_are_found_within_1cm(samples):
    amin, amax = -math.pi / 2, math.pi / 2
    inc = (amax - amin) / (samples - 1)
    ranges = cast_circles(CANS, amin, inc, samples, 1.0)
    found = detect(ranges, amin, inc, 0.03, 1.0, radius=0.033)
    assert len(found) == 2
    for d in found:
        err = min(math.hypot(d.x - cx, d.y - cy) for cx, cy, _ in CANS)
        assert err < 0.01, (d, err)


def test_radius_estimate_without_knowing_the_can():
    amin, inc, n = -math.pi / 2, math.pi / 720, 721
    ranges = cast_circles(CANS, amin, inc, n, 1.0)
    for d in detect(ranges, amin, inc, 0.03, 1.0):
        assert d.radius == pytest.approx(0.033, abs=0.006)
        assert min(math.hypot(d.x - cx, d.y - cy) for cx, cy, _ in CANS) < 0.01


def test_the_seeds_edge_average_lands_short_of_the_centre():
    amin, inc, n = -math.pi / 2, math.pi / 360, 361
    ranges = cast_circles([(0.4, 0.0, 0.033)], amin, inc, n, 1.0)
    (seed,) = detect(ranges, amin, inc, 0.03, 1.0, method="seed")
    (ours,) = detect(ranges, amin, inc, 0.03, 1.0, radius=0.033)
    assert ours.x == pytest.approx(0.4, abs=0.003)
    assert seed.x < 0.4 - 0.008     # the rim (here 11 mm short), not the centre


def test_single_beam_noise_is_ignored_and_bad_scans_refused():
    ranges = [INF, 0.5, INF, INF]
    assert detect(ranges, -1.0, 0.1, 0.03, 1.0, min_beams=2) == []
    with pytest.raises(DetectionError, match="finite"):
        detect(ranges, float("nan"), 0.1, 0.03, 1.0)
    with pytest.raises(DetectionError, match="angle_increment"):
        detect(ranges, -1.0, 0.0, 0.03, 1.0)
    with pytest.raises(DetectionError, match="method"):
        detect(ranges, -1.0, 0.1, 0.03, 1.0, method="hough")
