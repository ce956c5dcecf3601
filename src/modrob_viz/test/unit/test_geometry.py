"""Polyline distance, Douglas-Peucker, divergence and path generators against hand-worked cases."""
import math

import numpy as np
import pytest

from modrob_viz import geometry, paths
from modrob_viz.errors import TrajectoryError

L_PATH = [(0, 0, 0), (1, 0, 0), (1, 1, 0)]


@pytest.mark.parametrize("p, expect", [
    ((0.5, 0.3, 0), 0.3),        # above the first segment
    ((-3, 4, 0), 5.0),           # beyond the start: distance to (0, 0, 0)
    ((1.5, 0.5, 0), 0.5),        # beside the second segment
    ((2, 2, 0), math.sqrt(2)),   # beyond the end: distance to (1, 1, 0)
    ((0.5, 0.5, 2), math.sqrt(0.25 + 4)),  # above the corner region, nearest on segment 1 or 2
    ((1, 0.5, 0), 0.0),          # on the polyline
])
def test_polyline_distance_hand_cases(p, expect):
    assert geometry.polyline_distance(p, L_PATH) == pytest.approx(expect, abs=1e-12)


def test_query_reports_segment_and_closest_point():
    d, seg, closest = geometry.PolylineDistance(L_PATH).query((1.5, 0.25, 0))
    assert d == pytest.approx(0.5) and seg == 1
    np.testing.assert_allclose(closest, (1, 0.25, 0))


def test_single_point_polyline_and_degenerate_segment():
    assert geometry.polyline_distance((3, 4, 0), [(0, 0, 0)]) == pytest.approx(5.0)
    assert geometry.polyline_distance((0, 1, 0), [(0, 0, 0), (0, 0, 0), (2, 0, 0)]) == pytest.approx(1.0)
    d, t = geometry.point_segment_distance((1, 1, 0), (0, 0, 0), (2, 0, 0))
    assert d == pytest.approx(1.0) and t == pytest.approx(0.5)


def test_douglas_peucker_hand_cases():
    # a zig-zag: the middle bump of 0.3 survives a 0.2 tolerance, the 0.05 wiggles do not
    pts = [(0, 0, 0), (1, 0.05, 0), (2, 0.3, 0), (3, 0.05, 0), (4, 0, 0)]
    assert geometry.douglas_peucker(pts, 0.2) == [0, 2, 4]
    assert geometry.douglas_peucker(pts, 0.01) == [0, 1, 2, 3, 4]
    assert geometry.douglas_peucker(pts, 0.5) == [0, 4]
    # collinear points collapse to the end points
    assert geometry.douglas_peucker([(i, 2 * i, 0) for i in range(10)], 1e-9) == [0, 9]
    # a closed loop (first == last) keeps the far points
    square = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 0)]
    assert geometry.douglas_peucker(square, 0.1) == [0, 1, 2, 3, 4]
    assert geometry.douglas_peucker([], 0.1) == []
    assert geometry.douglas_peucker([(1, 2, 3)], 0.1) == [0]


def test_douglas_peucker_keeps_every_dropped_point_within_tolerance():
    pts = paths.helix(n=2000)
    for tol in (0.001, 0.005, 0.02):
        kept = geometry.douglas_peucker(pts, tol)
        assert kept[0] == 0 and kept[-1] == len(pts) - 1
        reduced = [pts[i] for i in kept]
        worst = max(geometry.polyline_distance(p, reduced) for p in pts)
        assert worst <= tol + 1e-12
    assert len(geometry.douglas_peucker(pts, 0.02)) < len(geometry.douglas_peucker(pts, 0.001)) < len(pts)


def test_bad_inputs():
    with pytest.raises(TrajectoryError, match="not finite"):
        geometry.polyline_distance((0, 0, 0), [(0, 0, 0), (1, float("nan"), 0)])
    with pytest.raises(TrajectoryError, match="shape"):
        geometry.douglas_peucker([(0, 0), (1, 1)], 0.1)
    with pytest.raises(TrajectoryError, match="tolerance"):
        geometry.douglas_peucker(L_PATH, -1)
    with pytest.raises(TrajectoryError, match="no points"):
        geometry.PolylineDistance([])


def test_divergence_max_rms_final():
    desired = [(0, 0, 0), (1, 0, 0)]
    travelled = [(0, 0.1, 0), (0.5, -0.2, 0), (1, 0.2, 0)]
    div = geometry.divergence(desired, travelled)
    assert div.max == pytest.approx(0.2)
    assert div.rms == pytest.approx(math.sqrt((0.01 + 0.04 + 0.04) / 3))
    assert div.final == pytest.approx(0.2)
    assert div.n == 3 and "RMS" in str(div)
    with pytest.raises(TrajectoryError, match="no samples"):
        geometry.divergence(desired, [])


def test_path_generators():
    c = paths.circle(center=(1, 2, 3), radius=0.5, n=101)
    assert len(c) == 101
    np.testing.assert_allclose(c[0], c[-1], atol=1e-12)
    assert all(abs(math.hypot(x - 1, y - 2) - 0.5) < 1e-12 and z == 3 for x, y, z in c)
    assert geometry.path_length(c) == pytest.approx(2 * math.pi * 0.5, rel=1e-3)
    ln = paths.line((0, 0, 0), (0, 3, 4), n=11)
    assert geometry.path_length(ln) == pytest.approx(5.0)
    h = paths.helix(center=(0, 0, 0), radius=0.1, pitch=0.05, turns=2, n=201)
    assert h[-1][2] == pytest.approx(0.1)
    f8 = paths.figure_eight(center=(0.3, 0, 0.4), size=0.1, n=101)
    np.testing.assert_allclose(f8[50], (0.3, 0, 0.4), atol=1e-12)  # crosses itself at the centre
    assert paths.generate("line", n=5) == paths.line(n=5)
    with pytest.raises(TrajectoryError, match="choose one of"):
        paths.generate("spiral")
    with pytest.raises(TrajectoryError, match="bad parameters"):
        paths.generate("circle", radius=1, width=2)
    with pytest.raises(TrajectoryError, match="n >= 2"):
        paths.circle(n=1)
