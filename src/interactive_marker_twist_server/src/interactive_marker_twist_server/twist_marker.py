"""interactive_marker_twist_server's rules, pure: which controls the marker has, and how a dragged
pose becomes a twist.

``linear_scale`` is a number (for x) or a map {x, y, z: scale}; each axis in it gets a MOVE_AXIS
control, and a drag of d metres along it commands scale * d, clamped to
[``max_negative_linear_velocity``, ``max_positive_linear_velocity``] (numbers or maps; defaults
-1 and 1). A ROTATE_AXIS control about z: a turn of yaw radians commands ``angular_scale`` * yaw
(2.2), clamped to +-``max_angular_velocity`` (2.2). The marker snaps back after each drag.
"""
import math

AXES = ("x", "y", "z")
# control orientations (x, y, z, w) as interactive_marker_twist_server places them
ORIENTATION = {"x": (1.0, 0.0, 0.0, 1.0), "y": (0.0, 0.0, 1.0, 1.0), "z": (0.0, 1.0, 0.0, 1.0)}


class ConfigError(ValueError):
    """A malformed parameter; the message names it."""


def _per_axis(value, default, param):
    if value is None:
        return {"x": float(default)}
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return {"x": float(value)}
    if (isinstance(value, dict) and all(k in AXES for k in value)
            and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value.values())):
        return {k: float(v) for k, v in value.items()}
    raise ConfigError("%s must be a number or a map {x, y, z: number}, got %r" % (param, value))


def _number(get, name, default):
    v = get(name, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ConfigError("~%s must be a number, got %r" % (name, v))
    return float(v)


class TwistMarker(object):
    def __init__(self, get):
        self.link_name = str(get("link_name", "base_link"))
        self.robot_name = str(get("robot_name", "robot"))
        self.linear_scale = _per_axis(get("linear_scale", None), 1.0, "~linear_scale")
        self.max_positive = _per_axis(get("max_positive_linear_velocity", None), 1.0,
                                      "~max_positive_linear_velocity")
        self.max_negative = _per_axis(get("max_negative_linear_velocity", None), -1.0,
                                      "~max_negative_linear_velocity")
        self.angular_scale = _number(get, "angular_scale", 2.2)
        self.max_angular = _number(get, "max_angular_velocity", 2.2)
        self.marker_size_scale = _number(get, "marker_size_scale", 1.0)

    @property
    def name(self):
        return self.robot_name + "_twist_marker"

    def controls(self):
        """[(name, orientation, 'move' | 'rotate')] in the order the marker gets them."""
        out = [("move_" + a, ORIENTATION[a], "move") for a in AXES if a in self.linear_scale]
        out.append(("rotate_z", ORIENTATION["z"], "rotate"))
        return out

    def twist(self, position, orientation):
        """The dragged pose (in link_name) -> (linear x, y, z, angular z)."""
        x, y, z, w = orientation
        yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
        ang = min(max(self.angular_scale * yaw, -self.max_angular), self.max_angular)
        lin = []
        for a, d in zip(AXES, position):
            if a not in self.linear_scale:
                lin.append(0.0)
                continue
            v = self.linear_scale[a] * d
            v = min(v, self.max_positive.get(a, 1.0))
            v = max(v, self.max_negative.get(a, -1.0))
            lin.append(v)
        return lin[0], lin[1], lin[2], ang
