"""interactive_marker_twist_server's rules without ROS: controls per configuration, drag to twist
with scales and clamps, parameter errors."""
import math

import pytest

from interactive_marker_twist_server.twist_marker import ConfigError, TwistMarker


def make(**params):
    return TwistMarker(lambda name, default: params.get(name, default))


def yaw_q(yaw):
    return (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def test_defaults_are_a_differential_base_on_base_link():
    m = make()
    assert (m.link_name, m.name) == ("base_link", "robot_twist_marker")
    assert [c[0] for c in m.controls()] == ["move_x", "rotate_z"]
    assert m.twist((0.5, 0.3, 0.0), yaw_q(0.2)) == pytest.approx((0.5, 0.0, 0.0, 0.44))


def test_drags_are_clamped():
    m = make()
    assert m.twist((3.0, 0.0, 0.0), yaw_q(1.5)) == pytest.approx((1.0, 0.0, 0.0, 2.2))
    assert m.twist((-3.0, 0.0, 0.0), yaw_q(-1.5)) == pytest.approx((-1.0, 0.0, 0.0, -2.2))


def test_planar_configuration_moves_in_y_too():
    m = make(linear_scale={"x": 1.0, "y": 0.5}, max_positive_linear_velocity={"x": 1.0, "y": 0.2},
             max_negative_linear_velocity={"x": -1.0, "y": -0.2}, angular_scale=1.0, robot_name="jackal")
    assert [c[0] for c in m.controls()] == ["move_x", "move_y", "rotate_z"]
    assert m.twist((0.2, 0.3, 0.0), yaw_q(0.1)) == pytest.approx((0.2, 0.15, 0.0, 0.1))
    assert m.twist((0.0, 1.0, 0.0), yaw_q(0.0))[1] == pytest.approx(0.2)
    assert m.name == "jackal_twist_marker"


@pytest.mark.parametrize("params, words", [
    ({"linear_scale": {"w": 1.0}}, ["~linear_scale must be a number or a map"]),
    ({"angular_scale": "fast"}, ["~angular_scale must be a number"]),
])
def test_bad_parameters_name_the_parameter(params, words):
    with pytest.raises(ConfigError) as err:
        make(**params)
    for w in words:
        assert w in str(err.value)
