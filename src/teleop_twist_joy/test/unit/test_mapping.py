"""teleop_twist_joy's mapping without ROS: defaults, maps, turbo, the single zero on release, short
arrays, and parameter errors."""
import pytest

from teleop_twist_joy.mapping import ConfigError, TeleopTwistJoy


def make(**params):
    return TeleopTwistJoy(lambda name, default: params.get(name, default))


def test_defaults_drive_x_on_axis_1_and_yaw_on_axis_0_while_button_0_is_held():
    t = make()
    assert t.on_joy([0.5, 1.0], [1]) == (0.5, 0.0, 0.0, 0.0, 0.0, 0.25)
    assert t.on_joy([0.5, 1.0], [0]) == (0.0,) * 6
    assert t.on_joy([0.5, 1.0], [0]) is None                    # one zero, then silence
    assert t.on_joy([0.0, -1.0], [1]) == (-0.5, 0.0, 0.0, 0.0, 0.0, 0.0)


def test_husky_ps4_configuration_with_turbo():
    t = make(axis_linear=1, scale_linear=0.4, scale_linear_turbo=2.0, axis_angular=0, scale_angular=1.4,
             enable_button=4, enable_turbo_button=5)
    buttons = [0] * 6
    buttons[4] = 1
    assert t.on_joy([1.0, 1.0], buttons) == pytest.approx((0.4, 0, 0, 0, 0, 1.4))
    buttons[5] = 1
    # the turbo angular scale defaults to the normal one
    assert t.on_joy([1.0, 1.0], buttons) == pytest.approx((2.0, 0, 0, 0, 0, 1.4))
    assert t.on_joy([1.0, 1.0], [0, 0, 0, 0, 0, 1]) == pytest.approx((2.0, 0, 0, 0, 0, 1.4))   # turbo alone


def test_maps_of_axes_for_holonomic_and_aerial_robots():
    t = make(axis_linear={"x": 1, "y": 0, "z": 4}, scale_linear={"x": 1.0, "y": 0.5, "z": 0.2},
             axis_angular={"yaw": 3, "pitch": 2}, scale_angular={"yaw": 2.0, "pitch": 1.0})
    assert t.on_joy([0.2, 0.4, 0.6, 0.8, 1.0], [1]) == pytest.approx((0.4, 0.1, 0.2, 0.0, 0.6, 1.6))
    # no turbo scales given for maps: turbo gives 0 there (as teleop_twist_joy)
    assert t.on_joy([0.2, 0.4], [1]) == pytest.approx((0.4, 0.1, 0.0, 0.0, 0.0, 0.0))


def test_short_messages_count_as_zero():
    t = make(enable_button=7)
    assert t.on_joy([1.0], [1]) == (0.0,) * 6                    # button 7 absent: released
    t2 = make()
    assert t2.on_joy([], [1]) == (0.0,) * 6


@pytest.mark.parametrize("params, words", [
    ({"enable_button": "L1"}, ["~enable_button must be a button number"]),
    ({"axis_linear": {"forward": 1}}, ["~axis_linear names forward", "x, y, z"]),
    ({"axis_angular": 1.5}, ["~axis_angular must be an axis number"]),
    ({"scale_linear": "fast"}, ["~scale_linear must be a number"]),
])
def test_bad_parameters_name_the_parameter(params, words):
    with pytest.raises(ConfigError) as err:
        make(**params)
    for w in words:
        assert w in str(err.value)
