"""Pieces every modrob_viz node uses: parameter reading, the robot description, tf sampling of
the end effector, latched publishers, and the boundary that turns library errors into one clear
log line and an exit code instead of a traceback."""
import math
import threading
import time

import rospy
import tf2_ros

from modrob_msgs.errors import ModrobError
from modrob_kinematics import kdl_urdf
from modrob_viz.errors import ConfigError, UrdfError

EXIT_OK = 0
EXIT_CONFIG = 2   # a parameter, the robot description or an input file is unusable


def run(main):
    """Run a node's ``main`` and return the process exit code (scripts do ``sys.exit(run(main))``)."""
    try:
        main()
    except ModrobError as err:
        rospy.logfatal("%s: %s", rospy.get_name(), err)
        return EXIT_CONFIG
    except (rospy.ROSInterruptException, KeyboardInterrupt):
        pass
    return EXIT_OK


def param(name, default, kind=None):
    """``rospy.get_param(name, default)`` converted to ``kind`` (type of ``default`` when None),
    with a ConfigError naming the parameter when the value does not convert or is not finite."""
    value = rospy.get_param(name, default)
    kind = kind or type(default)
    try:
        if kind is bool and isinstance(value, str):
            if value.lower() not in ("true", "false", "1", "0"):
                raise ValueError(value)
            out = value.lower() in ("true", "1")
        elif kind is list:
            out = [float(v) for v in (value.replace(",", " ").split() if isinstance(value, str) else value)]
        else:
            out = kind(value)
    except (TypeError, ValueError):
        raise ConfigError("parameter %s = %r is not a valid %s" % (rospy.resolve_name(name), value,
                                                                   kind.__name__))
    if isinstance(out, float) and not math.isfinite(out):
        raise ConfigError("parameter %s = %r is not finite" % (rospy.resolve_name(name), value))
    return out


def positive(name, default):
    value = param(name, float(default), float)
    if value <= 0:
        raise ConfigError("parameter %s must be > 0, got %g" % (rospy.resolve_name(name), value))
    return value


def robot_description(name="robot_description", timeout=5.0):
    """The URDF string of parameter ``name``; waits up to ``timeout`` s for it to appear."""
    resolved = rospy.resolve_name(name)
    deadline = rospy.get_time() + timeout
    while not rospy.has_param(resolved):
        if rospy.is_shutdown() or rospy.get_time() > deadline:
            raise ConfigError("parameter %s is not set: load a URDF first, e.g. "
                              "<param name=\"robot_description\" "
                              "textfile=\"$(find modrob_description)/urdf/modrob_4dof_demo.urdf\"/>, or set "
                              "~robot_description_param to the parameter that holds it" % resolved)
        rospy.sleep(0.1)
    xml = rospy.get_param(resolved)
    if not isinstance(xml, str):
        raise ConfigError("parameter %s holds a %s, not a URDF string" % (resolved, type(xml).__name__))
    return xml


def load_tree(name="robot_description", timeout=5.0):
    """A :class:`modrob_kinematics.kdl_urdf.KdlTree` from a robot-description parameter."""
    try:
        tree = kdl_urdf.tree_from_urdf_string(robot_description(name, timeout))
    except UrdfError as err:
        raise UrdfError("%s (parameter %s)" % (err, rospy.resolve_name(name)))
    for warning in tree.warnings:
        rospy.logwarn("%s", warning)
    return tree


def check_link(tree, link, what):
    if not tree.has_link(link):
        raise ConfigError("%s '%s' is not a link of robot '%s' (links: %s)"
                          % (what, link, tree.robot_name, ", ".join(sorted(tree.link_names))))


def latched(topic, msg_class):
    return rospy.Publisher(topic, msg_class, queue_size=1, latch=True)


class EndEffectorSampler(object):
    """Position of ``ee_frame`` in ``base_frame`` from tf2, with the failure explained (throttled).
    For its first ``STARTUP_GRACE`` wall seconds a missing transform is normal (the nodes of a launch
    start together; robot_state_publisher has not published yet) and is not warned about."""

    STARTUP_GRACE = 5.0

    def __init__(self, base_frame, ee_frame, cache_time=60.0, clock=time.monotonic):
        self.base_frame = base_frame
        self.ee_frame = ee_frame
        self.clock = clock
        self.started = clock()
        self.buffer = tf2_ros.Buffer(rospy.Duration(cache_time))
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.lock = threading.Lock()

    def sample(self, stamp=None, timeout=0.0):
        """((x, y, z), stamp) or None when tf cannot answer (yet)."""
        try:
            t = self.buffer.lookup_transform(self.base_frame, self.ee_frame, stamp or rospy.Time(0),
                                             rospy.Duration(timeout))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as err:
            if self.clock() - self.started < self.STARTUP_GRACE:
                return None
            rospy.logwarn_throttle(5.0, "no transform %s -> %s yet (is robot_state_publisher running and are "
                                   "~base_frame/~ee_frame right?): %s" % (self.base_frame, self.ee_frame,
                                                                          err))
            return None
        p = t.transform.translation
        return (p.x, p.y, p.z), t.header.stamp
