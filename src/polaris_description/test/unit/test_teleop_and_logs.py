"""Teleop key table, odometry transform, IMU CSV, the parking lot file."""
import math
import os

import pytest

from polaris_description import parking_lot
from polaris_description.errors import CommandError, ConfigError
from polaris_description.imu_log import COLUMNS, ImuCsvWriter, read_rows
from polaris_description.odometry import find_model, odom_from_model_state
from polaris_description.teleop import KEYS, TeleopState, help_text
from polaris_description.transforms import quat_from_yaw

PKG = os.path.join(os.path.dirname(__file__), "..", "..")


def test_help_lists_every_key_of_the_table():
    text = help_text()
    for key, (_, line) in KEYS.items():
        assert line in text


def test_keys_change_rate_and_steering_within_limits():
    s = TeleopState()
    for _ in range(100):
        s.press("w")
        s.press("a")
    assert s.rate == s.max_rate and s.steer == pytest.approx(s.steer_limit)
    s.press(" ")
    assert s.rate == 0.0
    s.press("x")
    assert s.steer == 0.0
    assert s.press("q") == "quit" and s.rate == 0.0


def test_unbound_key_is_named():
    with pytest.raises(CommandError, match="'z' is not bound"):
        TeleopState().press("z")


def test_odometry_twist_is_in_the_body_frame():
    s = odom_from_model_state((1, 2, 0.3), quat_from_yaw(math.pi / 2), (0.0, 2.0, 0.0), (0, 0, 0.5))
    assert s.linear[0] == pytest.approx(2.0) and abs(s.linear[1]) < 1e-12
    assert s.angular[2] == pytest.approx(0.5)
    assert find_model(["ground_plane", "polaris"], "polaris") == 1
    assert find_model(["ground_plane"], "polaris") is None
    with pytest.raises(ConfigError, match="position"):
        odom_from_model_state((float("nan"), 0, 0), (0, 0, 0, 1), (0, 0, 0), (0, 0, 0))


def test_imu_csv_round_trip(tmp_path):
    path = tmp_path / "imu.csv"
    with open(path, "w", newline="") as f:
        w = ImuCsvWriter(f)
        w.row(1.5, "imu_link", (0, 0, 0, 1), (0.1, 0.2, 0.3), (0.0, 0.0, 9.81))
    rows = read_rows(str(path))
    assert list(rows[0]) == list(COLUMNS)
    assert rows[0]["linear_acceleration_z"] == pytest.approx(9.81) and rows[0]["frame_id"] == "imu_link"


def test_world_file_is_generated_from_the_module():
    with open(os.path.join(PKG, "worlds", "parking_lot.world")) as f:
        assert f.read() == parking_lot.world_sdf(), "run: python3 -m polaris_description.parking_lot"


def test_lap_is_closed_and_evenly_spaced():
    pts = parking_lot.lap_waypoints(1.0)
    gaps = [math.dist(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
    assert max(gaps) < 1.05 and min(gaps) > 0.5


def test_ramps_have_different_inclines():
    a, b = parking_lot.RAMPS
    assert a.incline_deg != b.incline_deg
    x0, x1 = parking_lot.ramp_extent(a)
    assert parking_lot.ramp_surface_height(a, (x0 + x1) / 2.0, a.y) == pytest.approx(a.height)
