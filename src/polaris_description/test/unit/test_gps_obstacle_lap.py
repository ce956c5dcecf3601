"""GPS inverse, the obstacle detector on synthetic clouds, pure pursuit and one seeded cone run."""
import math

import numpy as np
import pytest

from polaris_description import gps, parking_lot
from polaris_description.errors import ConfigError
from polaris_description.lap import gap_to, run_lap, seeded_cone
from polaris_description.obstacle import FRONT_X, ObstacleDetector, StopGuard
from polaris_description.pure_pursuit import PurePursuit
from polaris_description.synthetic_scan import scan


@pytest.mark.parametrize("xyz", [(100.0, 0.0, 0.0), (0.0, 100.0, 1.0), (-35.5, 12.25, 0.3)])
def test_gps_round_trip(xyz):
    back = gps.from_fix(*gps.to_fix(*xyz))
    assert back == pytest.approx(xyz, abs=1e-6)


def test_gps_100m_north_is_about_900_microdegrees():
    lat, lon, _ = gps.to_fix(100.0, 0.0, 0.0)
    assert (lat - 49.9) == pytest.approx(100.0 / 111200.0, rel=0.01) and lon == pytest.approx(8.9)


def test_obstacle_ahead_is_found_at_its_distance():
    cone = (8.0, 0.0)
    d = ObstacleDetector().distance(scan((0.0, 0.0, 0.0), [cone]))
    # the nearest cone surface is 8 - 0.16 m from the rear axle, i.e. ~5.6 m past the bumper
    assert d == pytest.approx(cone[0] - 0.16 - FRONT_X, abs=0.15)


def test_ground_body_and_side_cones_are_ignored():
    det = ObstacleDetector()
    assert det.distance(scan((0.0, 0.0, 0.0), [])) == math.inf
    assert det.distance(scan((0.0, 0.0, 0.0), [(6.0, 3.0)])) == math.inf       # beside the way
    assert det.distance(scan((0.0, 0.0, 0.0), [(-6.0, 0.0)])) == math.inf      # behind


def test_curved_corridor_follows_the_arc():
    r = 5.0
    a = 1.2                                     # rad along a left arc of radius 5 from the rear axle
    cone = (r * math.sin(a), r - r * math.cos(a))
    d = ObstacleDetector().distance(scan((0.0, 0.0, 0.0), [cone]), kappa=1.0 / r)
    assert d == pytest.approx(r * a - FRONT_X, abs=0.4)
    assert ObstacleDetector().distance(scan((0.0, 0.0, 0.0), [cone]), kappa=0.0) == math.inf


def test_stop_guard_latches():
    g = StopGuard(4.0)
    assert not g.update(10.0) and g.update(3.0) and g.update(math.inf)


def test_non_finite_points_are_dropped():
    pts = np.array([[np.nan, 0, 0], [4.0, 0.0, -1.0], [4.1, 0.0, -1.0]])
    assert ObstacleDetector().distance(pts) < math.inf


def test_pure_pursuit_refuses_bad_waypoints():
    with pytest.raises(ConfigError, match="at least 2"):
        PurePursuit([(0, 0)])


def test_pure_pursuit_steers_towards_the_path():
    pp = PurePursuit([(0, 0), (10, 0), (20, 0)], closed=False)
    v, w = pp.update(0.0, 1.0, 0.0)             # left of the path: turn right
    assert v > 0 and w < 0


def test_gap_is_clearance_to_the_footprint():
    expected = 5.0 - 2.3 - parking_lot.CONE_BASE / 2 * math.sqrt(2)
    assert gap_to((5.0, 0.0), 0.0, 0.0, 0.0) == pytest.approx(expected)


def test_seeded_cone_run_stops_before_the_cone():
    cone = seeded_cone(1)
    r = run_lap(cone=cone, max_time=40.0)
    assert r["stopped"], "did not stop for the cone at %s" % (cone,)
    assert r["min_gap"] > 0.5
    assert r["max_cross_track"] < 1.0
