"""The Linux joystick API (linux/joystick.h) and joy_node's event rules, pure.

A device /dev/input/jsN delivers 8-byte events: time (ms, u32), value (s16), type (u8), number
(u8); type 1 is a button, 2 an axis, with 0x80 set on the initial state events sent when the
device opens. Axes become -1..1 with joy_node's sign (pushing a stick forward or left is
positive: the raw value is negated), a dead zone cut out smoothly around 0; buttons 0 or 1
(``sticky_buttons``: a press toggles).
"""
import struct

EVENT = struct.Struct("<IhBB")
BUTTON, AXIS, INIT = 0x01, 0x02, 0x80
AXIS_MAX = 32767.0


def decode(data):
    """Complete 8-byte events in ``data`` -> [(time_ms, value, type, number)], rest bytes."""
    n = len(data) // EVENT.size
    events = [EVENT.unpack_from(data, k * EVENT.size) for k in range(n)]
    return events, data[n * EVENT.size:]


def encode(value, type_, number, time_ms=0):
    return EVENT.pack(time_ms, value, type_, number)


def check_deadzone(deadzone, warn):
    """joy_node's corrections of ``~deadzone``."""
    if deadzone >= 1.0:
        warn("joy_node: deadzone greater than 1 was requested; it is relative to [-1, 1] now: dividing "
             "it by 32767")
        deadzone /= AXIS_MAX
    if deadzone > 0.9:
        warn("joy_node: deadzone (%g) greater than 0.9, setting it to 0.9" % deadzone)
        deadzone = 0.9
    if deadzone < 0.0:
        warn("joy_node: deadzone (%g) less than 0, setting it to 0" % deadzone)
        deadzone = 0.0
    return deadzone


class JoyState(object):
    """Axes and buttons as the events leave them. ``apply(event)`` returns 'now' (publish at once:
    a button), 'soon' (publish after the coalesce interval: an axis or an initial event) or None."""

    def __init__(self, deadzone=0.05, sticky_buttons=False, default_trig_val=False):
        self.deadzone = deadzone
        self.sticky = sticky_buttons
        self.default_trig_val = default_trig_val
        self.axes = []
        self.buttons = []

    def axis_value(self, raw):
        dz = AXIS_MAX * self.deadzone
        if raw > dz:
            raw -= dz
        elif raw < -dz:
            raw += dz
        else:
            raw = 0.0
        return -raw / (1.0 - self.deadzone) / AXIS_MAX

    def apply(self, event):
        _t, value, type_, number = event
        kind = type_ & ~INIT
        initial = bool(type_ & INIT)
        if kind == BUTTON:
            if number >= len(self.buttons):
                self.buttons.extend([0] * (number + 1 - len(self.buttons)))
            if self.sticky:
                if value == 1:
                    self.buttons[number] = 1 - self.buttons[number]
            else:
                self.buttons[number] = 1 if value else 0
            return "soon" if initial else "now"
        if kind == AXIS:
            if number >= len(self.axes):
                self.axes.extend([0.0] * (number + 1 - len(self.axes)))
            # an initial axis event is the resting position: kept unless default_trig_val asks for it
            if not initial or self.default_trig_val:
                self.axes[number] = self.axis_value(value)
            return "soon"
        return None
