"""joy_node's event rules without a device: decoding, axis scaling with the dead zone and sign,
buttons (sticky too), initial events."""
import pytest

from joy.joystick import AXIS, BUTTON, INIT, JoyState, check_deadzone, decode, encode


def test_events_decode_across_partial_reads():
    data = encode(1, BUTTON, 3, 10) + encode(-32767, AXIS, 1, 11)
    events, rest = decode(data[:12])
    assert events == [(10, 1, BUTTON, 3)] and len(rest) == 4
    events, rest = decode(rest + data[12:])
    assert events == [(11, -32767, AXIS, 1)] and rest == b""


def test_axes_are_negated_scaled_and_have_a_smooth_dead_zone():
    s = JoyState(deadzone=0.1)
    assert s.apply((0, -32767, AXIS, 1)) == "soon"
    assert s.axes == [0.0, pytest.approx(1.0)]            # stick pushed forward: +1
    s.apply((0, 32767, AXIS, 1))
    assert s.axes[1] == pytest.approx(-1.0)
    s.apply((0, 3000, AXIS, 1))                            # inside the dead zone (3276.7)
    assert s.axes[1] == 0.0
    s.apply((0, -(3276.7 + 0.5 * (32767 - 3276.7)), AXIS, 1))
    assert s.axes[1] == pytest.approx(0.5)                 # half way between the dead zone and the end


def test_buttons_publish_at_once_and_sticky_buttons_toggle():
    s = JoyState()
    assert s.apply((0, 1, BUTTON, 4)) == "now"
    assert s.buttons == [0, 0, 0, 0, 1]
    s.apply((0, 0, BUTTON, 4))
    assert s.buttons[4] == 0
    sticky = JoyState(sticky_buttons=True)
    for v in (1, 0, 1, 0, 1, 0):
        sticky.apply((0, v, BUTTON, 0))
    assert sticky.buttons == [1]


def test_initial_events_set_sizes_but_not_axis_values():
    s = JoyState()
    assert s.apply((0, 1, BUTTON | INIT, 2)) == "soon"
    assert s.apply((0, -20000, AXIS | INIT, 3)) == "soon"
    assert s.buttons == [0, 0, 1] and s.axes == [0.0] * 4
    t = JoyState(default_trig_val=True)
    t.apply((0, 32767, AXIS | INIT, 0))                   # a trigger resting at one end
    assert t.axes == [pytest.approx(-1.0)]


def test_deadzone_corrections():
    warnings = []
    assert check_deadzone(3276.7, warnings.append) == pytest.approx(0.1)
    assert check_deadzone(0.95, warnings.append) == 0.9
    assert check_deadzone(-1, warnings.append) == 0.0
    assert len(warnings) == 3
