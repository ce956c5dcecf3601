"""Marker builders, colour parsing, direction arrows, progress dimming and the distance log."""
import csv
import math

import numpy as np
import pytest
from visualization_msgs.msg import Marker

from modrob_viz import markers, paths
from modrob_viz.distance_log import DistanceLog
from modrob_viz.errors import VizError


def test_parse_color():
    assert markers.parse_color("red") == (1.0, 0.0, 0.0, 1.0)
    assert markers.parse_color("0 0.5 1") == (0.0, 0.5, 1.0, 1.0)
    assert markers.parse_color("0.1,0.2,0.3,0.4") == (0.1, 0.2, 0.3, 0.4)
    assert markers.parse_color([0, 1, 0, 0.5]) == (0.0, 1.0, 0.0, 0.5)
    for bad in ("purple-ish", "1 2 3", [1, 0], "nan 0 0"):
        with pytest.raises(VizError, match="colour"):
            markers.parse_color(bad)


def test_line_strip_carries_points_frame_and_width():
    pts = paths.circle(n=50)
    m = markers.line_strip(pts, "world", color="blue", width=0.01)
    assert m.type == Marker.LINE_STRIP and m.header.frame_id == "world"
    assert len(m.points) == 50 and m.scale.x == 0.01
    assert (m.points[7].x, m.points[7].y, m.points[7].z) == pts[7]
    assert m.pose.orientation.w == 1.0


def test_direction_arrows_follow_the_path():
    pts = paths.line((0, 0, 0), (1, 0, 0), n=20)
    arr = markers.direction_arrows(pts, "world", spacing=0.25)
    assert arr.markers[0].action == Marker.DELETEALL
    arrows = arr.markers[1:]
    assert len(arrows) == 4
    for m in arrows:
        assert m.type == Marker.ARROW
        assert m.points[1].x > m.points[0].x  # pointing forward along the line
        assert abs(m.points[0].y) < 1e-12
    assert [round(m.points[0].x, 6) for m in arrows] == [0.125, 0.375, 0.625, 0.875]
    assert markers.arrow_positions([(0, 0, 0)], 0.1) == []


def test_progress_strip_dims_or_clips_passed_points():
    pts = paths.line(n=10)
    dim = markers.progress_strip(pts, 4, "world", color="red", style="dim")
    assert len(dim.points) == 10 and len(dim.colors) == 10
    assert all(c.a < 0.5 for c in dim.colors[:4]) and all(c.a == 1.0 for c in dim.colors[4:])
    clip = markers.progress_strip(pts, 4, "world", style="clip")
    assert len(clip.points) == 7  # from the last passed point on
    with pytest.raises(VizError, match="passed_style"):
        markers.progress_strip(pts, 4, "world", style="fade")


def test_sphere_marker():
    m = markers.sphere((0.1, 0.2, 0.3), "base_link", diameter=0.04, color="green")
    assert m.type == Marker.SPHERE and m.pose.position.z == 0.3 and m.scale.y == 0.04
    assert m.color.g == pytest.approx(0.8)


def test_distance_log_csv_and_plot(tmp_path):
    log = DistanceLog()
    for i in range(50):
        log.add(i * 0.1, 0.5 - 0.01 * i, 0.02 * math.sin(i / 5.0) ** 2)
    log.add(5.0, 0.0)
    csv_path = log.write_csv(str(tmp_path / "out" / "usertest.csv"))
    back = DistanceLog.read_csv(csv_path)
    assert len(back) == 51
    np.testing.assert_allclose(back.rows[10][:2], log.rows[10][:2], atol=1e-6)
    assert math.isnan(back.rows[-1][2])
    with open(csv_path) as f:
        assert next(csv.reader(f)) == ["time_s", "distance_to_endpoint_m", "distance_to_trajectory_m"]
    png = log.plot(str(tmp_path / "usertest.png"))
    with open(png, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
