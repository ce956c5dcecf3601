"""Frame arithmetic of the /gazebo node: relative poses and twists as Gazebo's get/set_model_state."""
import math

import pytest

from modrob_sim.gazebo_ros import transforms as tf


def close(a, b, tol=1e-9):
    return all(abs(x - y) < tol for x, y in zip(a, b))


def test_compose_then_relative_is_identity():
    frame = ((1.0, 2.0, 3.0), tf.quat_from_rpy(0.3, -0.2, 1.1))
    pose = ((0.5, -0.1, 0.2), tf.quat_from_rpy(-0.4, 0.1, 0.2))
    back = tf.relative(frame, tf.compose(frame, pose))
    assert close(back[0], pose[0]) and close(back[1], pose[1])


def test_rotation_of_vector_by_yaw():
    q = tf.quat_from_rpy(0.0, 0.0, math.pi / 2)
    assert close(tf.quat_rotate(q, (1.0, 0.0, 0.0)), (0.0, 1.0, 0.0))


def test_rpy_round_trip():
    rpy = (0.3, -0.7, 2.0)
    assert close(tf.rpy_from_quat(tf.quat_from_rpy(*rpy)), rpy)


def test_zero_quaternion_means_identity():
    assert tf.quat_normalize((0.0, 0.0, 0.0, 0.0)) == (0.0, 0.0, 0.0, 1.0)


def test_twist_relative_to_moving_frame():
    frame = ((0.0, 0.0, 0.0), tf.quat_from_rpy(0.0, 0.0, math.pi / 2))
    frame_twist = ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    twist = ((1.0, 1.0, 0.0), (0.0, 0.0, 0.5))
    lin, ang = tf.twist_in_frame(frame, frame_twist, twist)
    assert close(lin, (1.0, 0.0, 0.0)) and close(ang, (0.0, 0.0, 0.5))


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_is_finite_catches_nan_and_inf(bad):
    assert tf.is_finite(((0.0, 1.0, 2.0), (0.0, 0.0, 0.0, 1.0)))
    assert not tf.is_finite(((0.0, bad, 2.0), (0.0, 0.0, 0.0, 1.0)))
