"""Errors of the motion interface; all derive from :class:`modrob_sim.errors.ModrobError`."""
from modrob_msgs.errors import ModrobError


class MotionError(ModrobError):
    """A motion command that cannot be carried out (wrong count, NaN, out of limits, IK failed)."""


class UnknownJointError(MotionError):
    """A command names a joint the robot does not have."""


class ParseError(MotionError):
    """A terminal line that cannot be understood. The message is one line, fit to show a user."""
