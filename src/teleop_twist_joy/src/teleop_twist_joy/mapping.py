"""teleop_twist_joy's mapping, pure.

``axis_linear`` is an axis number (for x) or a map {x, y, z: axis}; ``scale_linear`` and
``scale_linear_turbo`` a number or a map of the same keys. ``axis_angular`` likewise with
{yaw, pitch, roll} (a number: yaw). Defaults: linear x on axis 1 at 0.5 (turbo 1.0), yaw on axis
0 at 0.5 (turbo: the normal scale). While ``enable_turbo_button`` (default -1: none) is held the
turbo scales apply, while ``enable_button`` (0) is held the normal ones; on release one zero twist
is sent, then nothing until a button is held again. An axis or button beyond the message's arrays
counts as 0.
"""
LINEAR_KEYS = ("x", "y", "z")
ANGULAR_KEYS = ("yaw", "pitch", "roll")


class ConfigError(ValueError):
    """A malformed parameter; the message names it."""


def _axes(value, single_key, param):
    if isinstance(value, bool):
        raise ConfigError("%s must be an axis number or a map of axis numbers, got %r" % (param, value))
    if isinstance(value, int):
        return {single_key: value}
    if isinstance(value, dict) and all(isinstance(v, int) and not isinstance(v, bool)
                                       for v in value.values()):
        return dict(value)
    raise ConfigError("%s must be an axis number or a map of axis numbers, got %r" % (param, value))


def _scales(value, keys, single_key, param):
    if value is None:
        return {}
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return {single_key: float(value)}
    if isinstance(value, dict) and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                       for v in value.values()):
        return {k: float(v) for k, v in value.items()}
    raise ConfigError("%s must be a number or a map of numbers (%s), got %r" % (param, "/".join(keys), value))


class TeleopTwistJoy(object):
    def __init__(self, get):
        """``get(name, default)``: the node's private parameters."""
        self.enable_button = get("enable_button", 0)
        self.turbo_button = get("enable_turbo_button", -1)
        for name, v in (("enable_button", self.enable_button), ("enable_turbo_button", self.turbo_button)):
            if isinstance(v, bool) or not isinstance(v, int):
                raise ConfigError("~%s must be a button number, got %r" % (name, v))
        self.linear = self._group(get, "linear", LINEAR_KEYS, "x", 1, 0.5, 1.0)
        self.angular = self._group(get, "angular", ANGULAR_KEYS, "yaw", 0, 0.5, None)
        self.sent_disable = False

    @staticmethod
    def _group(get, what, keys, single_key, axis_default, scale_default, turbo_default):
        axes_value = get("axis_" + what, None)
        if axes_value is None or (isinstance(axes_value, int) and not isinstance(axes_value, bool)):
            # one axis: the scales are numbers, the turbo one defaulting as teleop_twist_joy does
            axes = {single_key: axis_default if axes_value is None else axes_value}
            normal = _scales(get("scale_" + what, scale_default), keys, single_key, "~scale_" + what)
            turbo = _scales(get("scale_%s_turbo" % what, turbo_default if turbo_default is not None
                                else normal[single_key]), keys, single_key, "~scale_%s_turbo" % what)
        else:
            axes = _axes(axes_value, single_key, "~axis_" + what)
            normal = _scales(get("scale_" + what, None), keys, single_key, "~scale_" + what)
            turbo = _scales(get("scale_%s_turbo" % what, None), keys, single_key, "~scale_%s_turbo" % what)
        unknown = [k for k in axes if k not in keys]
        if unknown:
            raise ConfigError("~axis_%s names %s; the keys are %s"
                              % (what, ", ".join(unknown), ", ".join(keys)))
        return axes, {"normal": normal, "turbo": turbo}

    def describe(self):
        lines = ["Teleop enable button %d." % self.enable_button]
        if self.turbo_button >= 0:
            lines.append("Turbo on button %d." % self.turbo_button)
        for what, (axes, scales) in (("Linear", self.linear), ("Angular", self.angular)):
            for k, a in sorted(axes.items()):
                lines.append("%s axis %s on %d at scale %g." % (what, k, a, scales["normal"].get(k, 0.0)))
        return lines

    @staticmethod
    def _value(axes_msg, group, which, key):
        axes, scales = group
        if key not in axes or key not in scales[which] or not 0 <= axes[key] < len(axes_msg):
            return 0.0
        return axes_msg[axes[key]] * scales[which][key]

    def on_joy(self, axes, buttons):
        """A Joy message -> (linear x, y, z, angular x, y, z) to send, or None."""
        def held(b):
            return 0 <= b < len(buttons) and buttons[b]
        if self.turbo_button >= 0 and held(self.turbo_button):
            which = "turbo"
        elif held(self.enable_button):
            which = "normal"
        else:
            if self.sent_disable:
                return None
            self.sent_disable = True
            return (0.0,) * 6
        self.sent_disable = False
        lin = [self._value(axes, self.linear, which, k) for k in LINEAR_KEYS]
        ang = [self._value(axes, self.angular, which, k) for k in ("roll", "pitch", "yaw")]
        return tuple(lin + ang)
