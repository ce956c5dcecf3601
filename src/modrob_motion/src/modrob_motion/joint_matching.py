"""Match a joint command (names + positions, as in sensor_msgs/JointState) to a robot's joints.

Pure: no rospy. Used by ``motion_publisher`` for every incoming message and by the terminal.
"""
import math
from collections import OrderedDict

from modrob_motion.errors import MotionError, UnknownJointError

# A command this close outside a limit is taken as the limit (planners that command exactly
# the limit produce such round-off).
LIMIT_TOLERANCE = 1e-6


class JointLimits(object):
    """Position limits of one joint; ``None`` means unlimited on that side."""

    __slots__ = ("lower", "upper")

    def __init__(self, lower=None, upper=None):
        self.lower = lower
        self.upper = upper

    def __repr__(self):
        return "JointLimits(%r, %r)" % (self.lower, self.upper)


class JointCommandMatcher(object):
    """Checks commands for one robot.

    joint_names: the robot's commandable joints, in the order positional commands use.
    limits: optional ``{name: JointLimits}``; commands outside them are refused.
    robot: a name used in messages (for example ``"modrob0"``).
    """

    def __init__(self, joint_names, limits=None, robot="robot"):
        if not joint_names:
            raise MotionError("%s has no commandable joints: is its controller YAML loaded?" % robot)
        if len(set(joint_names)) != len(joint_names):
            raise MotionError("%s: duplicate joint names in %s" % (robot, list(joint_names)))
        self.joint_names = list(joint_names)
        self.limits = dict(limits or {})
        self.robot = robot

    def match(self, names, positions):
        """Returns an OrderedDict ``{joint: position}`` in the robot's joint order.

        With ``names`` empty, ``positions`` must give every joint in order. With names, any
        subset of the joints may be commanded. Raises MotionError (UnknownJointError for a
        name the robot does not have) and commands nothing on any error.
        """
        names = list(names or [])
        positions = list(positions or [])
        if not names:
            if len(positions) != len(self.joint_names):
                raise MotionError(
                    "%s: a command without joint names needs %d positions (%s), got %d"
                    % (self.robot, len(self.joint_names), ", ".join(self.joint_names), len(positions)))
            names = list(self.joint_names)
        elif len(names) != len(positions):
            raise MotionError("%s: %d joint names but %d positions; give one position per name"
                              % (self.robot, len(names), len(positions)))
        if not names:
            raise MotionError("%s: empty command (no names, no positions)" % self.robot)
        known = set(self.joint_names)
        seen = set()
        values = {}
        for name, value in zip(names, positions):
            if name not in known:
                raise UnknownJointError(
                    "%s has no joint '%s'; its joints are: %s"
                    % (self.robot, name, ", ".join(self.joint_names)))
            if name in seen:
                raise MotionError("%s: joint '%s' is named twice in one command" % (self.robot, name))
            seen.add(name)
            values[name] = self._checked(name, value)
        return OrderedDict((n, values[n]) for n in self.joint_names if n in values)

    def _checked(self, name, value):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise MotionError("%s: position %r for joint '%s' is not a number" % (self.robot, value, name))
        if not math.isfinite(value):
            raise MotionError("%s: position %s for joint '%s' is not finite; nothing was commanded"
                              % (self.robot, value, name))
        lim = self.limits.get(name)
        if lim is not None:
            if lim.lower is not None and value < lim.lower - LIMIT_TOLERANCE:
                raise MotionError("%s: joint '%s' position %.4f is below its lower limit %.4f"
                                  % (self.robot, name, value, lim.lower))
            if lim.upper is not None and value > lim.upper + LIMIT_TOLERANCE:
                raise MotionError("%s: joint '%s' position %.4f is above its upper limit %.4f"
                                  % (self.robot, name, value, lim.upper))
            if lim.lower is not None:
                value = max(value, lim.lower)
            if lim.upper is not None:
                value = min(value, lim.upper)
        return value
