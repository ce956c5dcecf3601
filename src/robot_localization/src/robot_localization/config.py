"""ekf_localization_node's parameters, read and checked (pure: ``get(name, default)`` is given).

Inputs are found as robot_localization finds them: ``odom0``, ``odom1``, ... until the first
missing number, the same for ``twist``, ``imu`` and ``pose``; each with ``<input>_config`` (15
booleans: x y z roll pitch yaw vx vy vz vroll vpitch vyaw ax ay az; all false when missing),
``_differential``, ``_relative``, ``_queue_size``, ``_nodelay`` (accepted), the rejection
thresholds, and for IMUs ``_remove_gravitational_acceleration``.
"""
import math

import numpy as np

from robot_localization import ekf

KINDS = ("odom", "twist", "imu", "pose")


class ConfigError(ValueError):
    """A malformed parameter; the message names it and says what it should be."""


class InputConfig(object):
    def __init__(self, kind, index, topic):
        self.kind, self.index, self.topic = kind, index, topic
        self.name = "%s%d" % (kind, index)
        self.config = [False] * ekf.N
        self.differential = self.relative = False
        self.queue_size = 1
        self.pose_threshold = self.twist_threshold = self.accel_threshold = math.inf
        self.remove_gravity = False

    def describe(self):
        used = [ekf.NAMES[i] for i in range(ekf.N) if self.config[i]]
        return "%s on %s: %s%s%s" % (self.name, self.topic, " ".join(used) or "nothing",
                                     " (differential)" if self.differential else "",
                                     " (relative)" if self.relative else "")


class Config(object):
    def __init__(self):
        self.frequency = 30.0
        self.sensor_timeout = None
        self.two_d_mode = False
        self.map_frame, self.odom_frame, self.base_link_frame = "map", "odom", "base_link"
        self.world_frame = "odom"
        self.publish_tf = True
        self.publish_acceleration = False
        self.predict_to_current_time = False
        self.transform_time_offset = 0.0
        self.gravity = 9.80665
        self.process_noise = ekf.DEFAULT_PROCESS_NOISE.copy()
        self.initial_covariance = ekf.DEFAULT_INITIAL_COVARIANCE.copy()
        self.inputs = []
        self.warnings = []


def _bool(get, name, default):
    v = get(name, default)
    if not isinstance(v, bool):
        raise ConfigError("parameter %s must be true or false, got %r" % (name, v))
    return v


def _number(get, name, default, positive=False):
    v = get(name, default)
    if v is default:
        return float(v)
    if (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
            or (positive and v <= 0)):
        raise ConfigError("parameter %s must be a %snumber, got %r"
                          % (name, "positive " if positive else "", v))
    return float(v)


def _string(get, name, default):
    v = get(name, default)
    if not isinstance(v, str) or not v:
        raise ConfigError("parameter %s must be a frame name, got %r" % (name, v))
    return v.lstrip("/")


def _matrix(get, name, default):
    v = get(name, None)
    if v is None:
        return default
    if (not isinstance(v, list) or len(v) != ekf.N * ekf.N
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)
                       for x in v)):
        raise ConfigError("parameter %s must be a list of %d numbers (a 15 x 15 matrix, row by row), got %s"
                          % (name, ekf.N * ekf.N, "%d entries" % len(v) if isinstance(v, list) else repr(v)))
    return np.array(v, dtype=float).reshape(ekf.N, ekf.N)


def read(get):
    """A Config from ``get(name, default)`` (names as in the node's private namespace)."""
    c = Config()
    c.frequency = _number(get, "frequency", 30.0, positive=True)
    c.sensor_timeout = _number(get, "sensor_timeout", 1.0 / c.frequency, positive=True)
    c.two_d_mode = _bool(get, "two_d_mode", False)
    c.map_frame = _string(get, "map_frame", "map")
    c.odom_frame = _string(get, "odom_frame", "odom")
    c.base_link_frame = _string(get, "base_link_frame", "base_link")
    c.world_frame = _string(get, "world_frame", c.odom_frame)
    if c.world_frame not in (c.map_frame, c.odom_frame):
        raise ConfigError("parameter world_frame is '%s': it must be the map_frame ('%s') or the "
                          "odom_frame ('%s')"
                          % (c.world_frame, c.map_frame, c.odom_frame))
    if len({c.map_frame, c.odom_frame, c.base_link_frame}) < 3:
        raise ConfigError("map_frame, odom_frame and base_link_frame must differ (got '%s', '%s', '%s')"
                          % (c.map_frame, c.odom_frame, c.base_link_frame))
    c.publish_tf = _bool(get, "publish_tf", True)
    c.publish_acceleration = _bool(get, "publish_acceleration", False)
    c.predict_to_current_time = _bool(get, "predict_to_current_time", False)
    c.transform_time_offset = _number(get, "transform_time_offset", 0.0)
    c.gravity = _number(get, "gravitational_acceleration", 9.80665)
    c.process_noise = _matrix(get, "process_noise_covariance", c.process_noise)
    c.initial_covariance = _matrix(get, "initial_estimate_covariance", c.initial_covariance)
    for kind in KINDS:
        i = 0
        while True:
            topic = get("%s%d" % (kind, i), None)
            if topic is None:
                break
            c.inputs.append(_input(get, kind, i, topic))
            i += 1
    if not c.inputs:
        c.warnings.append("no inputs: set odom0, imu0, twist0 or pose0 (a topic) with its _config vector")
    return c


def _input(get, kind, i, topic):
    name = "%s%d" % (kind, i)
    if not isinstance(topic, str) or not topic:
        raise ConfigError("parameter %s must be a topic name, got %r" % (name, topic))
    inp = InputConfig(kind, i, topic)
    cfg = get(name + "_config", [False] * ekf.N)
    if not isinstance(cfg, list) or len(cfg) != ekf.N or not all(isinstance(v, bool) for v in cfg):
        raise ConfigError("parameter %s_config must be 15 true/false values (x y z, roll pitch yaw, "
                          "vx vy vz, vroll vpitch vyaw, ax ay az), got %r" % (name, cfg))
    inp.config = list(cfg)
    inp.differential = _bool(get, name + "_differential", False)
    inp.relative = _bool(get, name + "_relative", False)
    q = get(name + "_queue_size", 1)
    if isinstance(q, bool) or not isinstance(q, int) or q < 1:
        raise ConfigError("parameter %s_queue_size must be a whole number >= 1, got %r" % (name, q))
    inp.queue_size = q
    _bool(get, name + "_nodelay", False)
    if kind in ("pose", "twist"):
        t = _number(get, name + "_rejection_threshold", math.inf, positive=True)
        inp.pose_threshold = inp.twist_threshold = t
    else:
        inp.pose_threshold = _number(get, name + "_pose_rejection_threshold", math.inf, positive=True)
        inp.twist_threshold = _number(get, name + "_twist_rejection_threshold", math.inf, positive=True)
    if kind == "imu":
        inp.accel_threshold = _number(get, name + "_linear_acceleration_rejection_threshold", math.inf,
                                      positive=True)
        inp.remove_gravity = _bool(get, name + "_remove_gravitational_acceleration", False)
    if kind == "twist":
        inp.config[:6] = [False] * 6
        inp.config[12:] = [False] * 3
    if kind in ("pose",):
        inp.config[6:] = [False] * 9
    if kind == "odom":
        inp.config[12:] = [False] * 3
    return inp
