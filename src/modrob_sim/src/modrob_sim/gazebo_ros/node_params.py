"""The /gazebo node's parameters (docs/simulator.md, "Parameters") and gzserver's command line."""
import rospy

from modrob_sim.errors import ModelError


class Params(object):
    """The node's parameters (see docs/simulator.md)."""

    def __init__(self, time_step=None, real_time_factor=None, paused=False, seed=0, world_name="",
                 pub_clock_frequency=1000.0, publish_rate=100.0, marker_rate=10.0, marker_models="props",
                 rtf_log_period=5.0, plugin_modules=(), gravity=None, scene_rate=30.0,
                 native_publishing=True, enable_ros_network=True):
        self.time_step = time_step
        self.real_time_factor = real_time_factor
        self.paused = paused
        self.seed = seed
        self.world_name = world_name
        self.pub_clock_frequency = pub_clock_frequency
        self.publish_rate = publish_rate
        self.marker_rate = marker_rate
        self.marker_models = marker_models
        self.rtf_log_period = rtf_log_period
        self.plugin_modules = list(plugin_modules)
        self.gravity = gravity
        self.scene_rate = scene_rate
        self.native_publishing = native_publishing
        self.enable_ros_network = enable_ros_network

    @classmethod
    def from_ros(cls, argv=()):
        """Read ``~params`` and gzserver's arguments in ``argv`` (``-u`` start paused, ``--verbose``,
        ``-e ode``, a world file). An unset time_step / real_time_factor comes from the world
        file's <physics> (else 0.001 s and 1.0), as Gazebo takes them from the world."""
        def opt(name):
            return rospy.get_param("~" + name) if rospy.has_param("~" + name) else None

        def number(name, default, cast=float):
            value = rospy.get_param("~" + name, default)
            try:
                return cast(value)
            except (TypeError, ValueError):
                raise ModelError("~%s must be a number, got %r" % (name, value))
        args = parse_server_args(argv)
        engine = str(rospy.get_param("~physics", args["physics"] or "ode"))
        if engine != "ode":
            rospy.logwarn("physics engine '%s' requested; this simulator has only ode: using ode" % engine)
        return cls(time_step=opt("time_step"), real_time_factor=opt("real_time_factor"),
                   paused=bool(rospy.get_param("~paused", False)) or args["paused"],
                   seed=number("seed", 0, int),
                   world_name=str(rospy.get_param("~world_name", args["world"] or "")),
                   pub_clock_frequency=number("pub_clock_frequency", 1000.0),
                   publish_rate=number("publish_rate", 100.0),
                   marker_rate=number("marker_rate", 10.0),
                   marker_models=str(rospy.get_param("~marker_models", "props")),
                   rtf_log_period=number("rtf_log_period", 5.0),
                   scene_rate=number("scene_rate", 30.0),
                   native_publishing=_as_bool(rospy.get_param("~native_publishing", True)),
                   plugin_modules=_as_list(rospy.get_param("~plugin_modules", [])),
                   enable_ros_network=_as_bool(rospy.get_param("~enable_ros_network", True)))


def _as_bool(value):
    """A boolean parameter; launch files may give it as the text "false"."""
    if isinstance(value, str):
        return value.strip().lower() not in ("false", "0", "no", "off", "")
    return bool(value)


def _as_list(value):
    """A parameter that should be a list: "a, b" or "a" become ["a", "b"] / ["a"]."""
    if isinstance(value, str):
        return [v.strip() for v in value.replace(",", " ").split() if v.strip()]
    return list(value or [])


def parse_server_args(argv):
    """gzserver's command line as gazebo_ros's launch files pass it: -u, --verbose, -e ENGINE,
    a world file; other flags are ignored (they are Gazebo's, without meaning here)."""
    out = {"paused": False, "verbose": False, "physics": None, "world": None, "ignored": []}
    it = iter(argv)
    for a in it:
        if a in ("-u", "--pause"):
            out["paused"] = True
        elif a == "--verbose":
            out["verbose"] = True
        elif a in ("-e", "--physics"):
            out["physics"] = next(it, None)
        elif a.startswith("-"):
            out["ignored"].append(a)
        elif a:
            out["world"] = a
    return out
