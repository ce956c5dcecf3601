"""Keyboard teleoperation of the Polaris (pure part): ONE key table gives the bindings and the
help text. Like the seed's teleop it commands the rear wheels' rate (rad/s, the same on both)
and the steering angle (rad, the same on both blocks); with the Ackermann node the same state is
sent as cmd_vel instead (v = rate * r, omega = v tan(steer) / wheelbase)."""
import math
from collections import OrderedDict

from polaris_description import geometry as G
from polaris_description.errors import CommandError

RATE_STEP = 0.5      # rad/s per key press
STEER_STEP = 0.1     # rad per key press
MAX_RATE = 10.0      # rad/s (3.2 m/s)

# key -> (action, help)
KEYS = OrderedDict([
    ("w", ("faster", "wheel rate +%.1f rad/s" % RATE_STEP)),
    ("s", ("slower", "wheel rate -%.1f rad/s (negative: reverse)" % RATE_STEP)),
    ("a", ("left", "steer +%.1f rad (left)" % STEER_STEP)),
    ("d", ("right", "steer -%.1f rad (right)" % STEER_STEP)),
    ("x", ("straight", "steering to 0")),
    (" ", ("stop", "wheel rate to 0 (space)")),
    ("q", ("quit", "stop, then quit (also Ctrl-C)")),
])


def help_text():
    lines = ["Polaris teleop -- keys:"]
    for key, (_, text) in KEYS.items():
        lines.append("  %-6s %s" % ("space" if key == " " else key, text))
    return "\n".join(lines)


class TeleopState(object):
    def __init__(self, rate_step=RATE_STEP, steer_step=STEER_STEP, max_rate=MAX_RATE,
                 steer_limit=G.STEER_LIMIT):
        self.rate_step, self.steer_step = rate_step, steer_step
        self.max_rate, self.steer_limit = max_rate, steer_limit
        self.rate = 0.0
        self.steer = 0.0

    def press(self, key):
        """Apply one key; returns the action name (CommandError for a key not in the table)."""
        if key not in KEYS:
            raise CommandError("key %r is not bound; %s" % (key, help_text()))
        action = KEYS[key][0]
        if action == "faster":
            self.rate = min(self.rate + self.rate_step, self.max_rate)
        elif action == "slower":
            self.rate = max(self.rate - self.rate_step, -self.max_rate)
        elif action == "left":
            self.steer = min(self.steer + self.steer_step, self.steer_limit)
        elif action == "right":
            self.steer = max(self.steer - self.steer_step, -self.steer_limit)
        elif action == "straight":
            self.steer = 0.0
        elif action in ("stop", "quit"):
            self.rate = 0.0
        self.rate = round(self.rate, 6)
        self.steer = round(self.steer, 6)
        return action

    def twist(self):
        """(v, omega) for cmd_vel."""
        v = self.rate * G.WHEEL_RADIUS
        return v, v * math.tan(self.steer) / G.WHEELBASE

    def status(self):
        return ("wheel rate %+.1f rad/s (%.2f m/s), steering %+.2f rad"
                % (self.rate, self.rate * G.WHEEL_RADIUS, self.steer))
