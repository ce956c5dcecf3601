"""The filter core and the measurement preparation without ROS: the model's kinematics, the 20 m
drive with noisy wheel odometry and IMU (within 5 cm of the truth all along, better than the
odometry alone), differential and relative inputs, rejection, two_d_mode, and the parameters'
errors."""
import math

import numpy as np
import pytest

from robot_localization import config, drive_sim, ekf
from robot_localization.measurements import (Frame, PoseInput, imu_measurements, matrix_of_quaternion,
                                             quaternion_of_rpy, twist_measurement)

# Husky's localization.yaml with the IMU's yaw taken as it is (Husky differentiates it): the yaw
# rate's bias would otherwise turn into heading drift, 0.2 m sideways over 20 m
ODOM_AND_IMU_YAW = {
    "frequency": 50, "two_d_mode": True, "odom_frame": "odom", "base_link_frame": "base_link",
    "world_frame": "odom",
    "odom0": "odom", "odom0_config": [False, False, False, False, False, False, True, True, True,
                                      False, False, True, False, False, False],
    "imu0": "imu/data", "imu0_config": [False, False, False, True, True, True, False, False, False,
                                        True, True, True, False, False, False],
    "imu0_remove_gravitational_acceleration": True,
}


def getter(values):
    return lambda name, default: values.get(name, default)


def diag3(v):
    return [v, 0, 0, 0, v, 0, 0, 0, v]


def cov6_diag(*d):
    return np.diag(d)


def run_drive(cfg_values, seed=0, length=20.0):
    """Feed the drive's noisy odometry and IMU through the measurement preparation into the EKF at
    the sensors' rate; returns (position errors, dead-reckoning errors of the odometry alone)."""
    cfg = config.read(getter(cfg_values))
    f = ekf.Ekf(cfg.process_noise, cfg.initial_covariance, cfg.two_d_mode)
    odom_in = next(i for i in cfg.inputs if i.kind == "odom")
    imu_in = next(i for i in cfg.inputs if i.kind == "imu")
    imu_pose = PoseInput(imu_in.config, imu_in.differential, imu_in.relative)
    noise = drive_sim.Noise(seed)
    errors, dr_errors = [], []
    dr = [0.0, 0.0, 0.0]
    path = drive_sim.drive(length)
    for k, s in enumerate(path):
        v, w = noise.odometry(s)
        got = twist_measurement(odom_in.config, (v, 0.0, 0.0), (0.0, 0.0, w), cov6_diag(*[0.0025] * 6))
        f.process(ekf.Measurement(*got, time=s.t))
        yaw, rate, acc = noise.imu(s)
        for values, cov, mask in imu_measurements(
                imu_in.config, imu_pose, quaternion_of_rpy(0.0, 0.0, yaw), diag3(1e-4), (0.0, 0.0, rate),
                diag3(2.5e-5), acc, diag3(0.0025), s.t, remove_gravity=True):
            f.process(ekf.Measurement(values, cov, mask, s.t))
        if k:
            dt = s.t - path[k - 1].t
            dr[2] += w * dt
            dr[0] += v * dt * math.cos(dr[2])
            dr[1] += v * dt * math.sin(dr[2])
        errors.append(math.hypot(f.state[ekf.X] - s.x, f.state[ekf.Y] - s.y))
        dr_errors.append(math.hypot(dr[0] - s.x, dr[1] - s.y))
    return errors, dr_errors, path, f


def test_the_drive_is_twenty_metres_with_turns():
    path = drive_sim.drive(20.0)
    length = sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(path, path[1:]))
    assert length == pytest.approx(20.0, abs=0.05)
    assert max(abs(s.yaw) for s in path) > 1.0


@pytest.mark.parametrize("seed", [0, 1])
def test_twenty_metres_with_noisy_odometry_and_imu_stay_within_five_centimetres(seed):
    errors, dr_errors, path, f = run_drive(ODOM_AND_IMU_YAW, seed)
    assert max(errors) < 0.05, "largest error %.3f m" % max(errors)
    assert max(errors) < 0.5 * max(dr_errors)      # the IMU's yaw helps: odometry alone drifts 10-40 cm
    assert f.state[ekf.YAW] == pytest.approx(ekf.wrap(path[-1].yaw), abs=0.02)
    assert abs(f.state[ekf.Z]) < 1e-3 and abs(f.state[ekf.ROLL]) < 1e-3        # two_d_mode


def test_the_same_seed_gives_the_same_estimate():
    a = run_drive(ODOM_AND_IMU_YAW, 7, 5.0)[3].state
    b = run_drive(ODOM_AND_IMU_YAW, 7, 5.0)[3].state
    # equal to rounding: numpy's BLAS may take another summation order for arrays placed
    # differently in memory (seen in the full suite: the same digits, not the same bits)
    assert np.allclose(a, b, rtol=0.0, atol=1e-12)
    assert not np.allclose(a, run_drive(ODOM_AND_IMU_YAW, 8, 5.0)[3].state, rtol=0.0, atol=1e-6)


def test_prediction_follows_an_arc_and_a_climb():
    f = ekf.Ekf()
    f.state[ekf.VX], f.state[ekf.VYAW] = 1.0, 0.5
    f.time = 0.0
    for k in range(1, 1001):
        f.predict(k * 2 * math.pi / 1000.0)        # half a turn of radius 2 (0.5 rad/s for 2 pi s)
    assert (f.state[ekf.X], f.state[ekf.Y]) == pytest.approx((0.0, 4.0), abs=1e-3)
    g = ekf.Ekf()
    g.state[ekf.PITCH], g.state[ekf.VX] = -math.pi / 6, 1.0     # nose up 30 degrees
    g.time = 0.0
    g.predict(2.0)
    assert (g.state[ekf.X], g.state[ekf.Z]) == pytest.approx((2 * math.cos(math.pi / 6), 1.0), abs=1e-9)


def test_the_first_measurement_initialises_what_it_measures():
    f = ekf.Ekf()
    values = np.zeros(ekf.N)
    values[ekf.X], values[ekf.YAW] = 3.0, 1.0
    cov = np.eye(ekf.N) * 0.5
    mask = np.zeros(ekf.N, dtype=bool)
    mask[[ekf.X, ekf.YAW]] = True
    f.process(ekf.Measurement(values, cov, mask, 1.0))
    assert f.initialized and f.state[ekf.X] == 3.0 and f.state[ekf.YAW] == 1.0
    assert f.covariance[ekf.X, ekf.X] == 0.5 and f.covariance[ekf.Y, ekf.Y] == 1e-9


def test_yaw_is_corrected_the_short_way_round():
    f = ekf.Ekf(initial_covariance=np.eye(ekf.N))
    f.initialized, f.time = True, 0.0
    f.state[ekf.YAW] = math.pi - 0.05
    values = np.zeros(ekf.N)
    values[ekf.YAW] = -math.pi + 0.05
    mask = np.zeros(ekf.N, dtype=bool)
    mask[ekf.YAW] = True
    f.process(ekf.Measurement(values, np.eye(ekf.N), mask, 0.0))
    assert abs(abs(f.state[ekf.YAW]) - math.pi) < 0.05          # between the two, near +-pi, not near 0


def test_an_outlier_beyond_the_threshold_is_rejected():
    f = ekf.Ekf(initial_covariance=np.eye(ekf.N) * 0.01)
    f.initialized, f.time = True, 0.0
    values = np.zeros(ekf.N)
    values[ekf.X] = 5.0
    mask = np.zeros(ekf.N, dtype=bool)
    mask[ekf.X] = True
    assert not f.process(ekf.Measurement(values, np.eye(ekf.N) * 0.01, mask, 0.0, threshold=3.0))
    assert f.state[ekf.X] == 0.0 and f.rejected == 1
    assert f.process(ekf.Measurement(values, np.eye(ekf.N) * 0.01, mask, 0.0))
    assert f.state[ekf.X] > 2.0


def test_differential_pose_becomes_body_velocity():
    p = PoseInput([True, True, False, False, False, True] + [False] * 9, differential=True)
    r0 = matrix_of_quaternion(quaternion_of_rpy(0, 0, math.pi / 2))
    assert p.measure((1.0, 1.0, 0.0), r0, np.eye(6) * 0.01, 0.0) is None          # the first one: stored
    r1 = matrix_of_quaternion(quaternion_of_rpy(0, 0, math.pi / 2 + 0.1))
    values, cov, mask = p.measure((1.0, 1.5, 0.0), r1, np.eye(6) * 0.01, 0.5)
    # moved 0.5 m along world y = the body's x (facing +y): vx 1 m/s; yaw rate 0.2 rad/s
    assert values[ekf.VX] == pytest.approx(1.0) and values[ekf.VY] == pytest.approx(0.0, abs=1e-12)
    assert values[ekf.VYAW] == pytest.approx(0.2)
    assert list(np.flatnonzero(mask)) == [ekf.VX, ekf.VY, ekf.VYAW]
    assert cov[ekf.VX, ekf.VX] == pytest.approx(0.02 / 0.25)


def test_relative_pose_starts_at_zero():
    p = PoseInput([True, True, False, False, False, True] + [False] * 9, relative=True)
    r0 = matrix_of_quaternion(quaternion_of_rpy(0, 0, 1.0))
    values, _c, _m = p.measure((5.0, 5.0, 0.0), r0, np.eye(6), 0.0)
    assert values[:6] == pytest.approx([0.0] * 6, abs=1e-12)
    values, _c, _m = p.measure((5.0 + math.cos(1.0), 5.0 + math.sin(1.0), 0.0), r0, np.eye(6), 1.0)
    assert values[ekf.X] == pytest.approx(1.0) and values[ekf.Y] == pytest.approx(0.0, abs=1e-12)


def test_imu_mounted_upside_down_and_gravity_removed():
    # an IMU rolled by pi about x: its z points down; level robot at rest
    mount = Frame.from_quaternion(quaternion_of_rpy(math.pi, 0.0, 0.0))
    sensor_q = quaternion_of_rpy(math.pi, 0.0, 0.3)        # the sensor's own orientation
    cfg = [False] * 3 + [True] * 3 + [False] * 3 + [True] * 3 + [True] * 3
    out = imu_measurements(cfg, PoseInput(cfg), sensor_q, diag3(0.01), (0.0, 0.0, -0.2), diag3(0.01),
                           (0.0, 0.0, -9.80665), diag3(0.01), 0.0, base_from=mount, remove_gravity=True)
    pose, twist, acc = out
    assert pose[0][ekf.ROLL:ekf.YAW + 1] == pytest.approx([0.0, 0.0, 0.3], abs=1e-9)
    assert twist[0][ekf.VYAW] == pytest.approx(0.2)                 # -0.2 about a downward z
    assert acc[0][ekf.AX:] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)


def test_imu_parts_marked_missing_are_left_out():
    cfg = [False] * 3 + [True] * 3 + [False] * 3 + [True] * 3 + [True] * 3
    out = imu_measurements(cfg, PoseInput(cfg), (0, 0, 0, 1), [-1] + [0] * 8, (0, 0, 0.1), [0.01] + [0] * 8,
                           (0, 0, 9.8), [-1] + [0] * 8, 0.0)
    assert len(out) == 1 and out[0][2][ekf.VYAW]


def test_twist_of_a_sensor_ahead_of_base_link_loses_its_lever_arm():
    ahead = Frame(np.eye(3), (0.5, 0.0, 0.0))
    cfg = [False] * 6 + [True] * 6 + [False] * 3
    values, _c, _m = twist_measurement(cfg, (0.0, 0.5, 0.0), (0.0, 0.0, 1.0), np.eye(6), ahead)
    assert values[ekf.VX:ekf.VYAW + 1] == pytest.approx([0, 0, 0, 0, 0, 1.0])   # turning on the spot


@pytest.mark.parametrize("values, words", [
    ({"odom0": "odom", "odom0_config": [True] * 14}, ["odom0_config", "15 true/false"]),
    ({"odom0": 3}, ["odom0 must be a topic"]),
    ({"frequency": 0}, ["frequency must be a positive number"]),
    ({"world_frame": "earth"}, ["world_frame is 'earth'"]),
    ({"process_noise_covariance": [0.1] * 15}, ["process_noise_covariance", "225 numbers", "15 entries"]),
    ({"two_d_mode": "yes"}, ["two_d_mode must be true or false"]),
    ({"imu0": "imu", "imu0_queue_size": 0}, ["imu0_queue_size"]),
])
def test_bad_parameters_name_the_parameter(values, words):
    with pytest.raises(config.ConfigError) as err:
        config.read(getter(values))
    for w in words:
        assert w in str(err.value)


def test_inputs_are_read_until_the_first_gap():
    cfg = config.read(getter({"odom0": "a", "odom1": "b", "odom3": "d", "imu0": "i", "twist0": "t"}))
    assert [i.name for i in cfg.inputs] == ["odom0", "odom1", "twist0", "imu0"]
    assert cfg.sensor_timeout == pytest.approx(1 / 30.0)
    assert config.read(getter({})).warnings
