"""The exception types of modrob_viz (kinematics errors come from modrob_kinematics and are
re-exported here). They derive from modrob_msgs' ModrobError (the workspace's
one root), so a node can catch every library error at its boundary without catching bugs."""
from modrob_kinematics.errors import KinematicsError, UnreachableError, UrdfError  # noqa: F401 (re-exported)
from modrob_msgs.errors import ModrobError


class VizError(ModrobError):
    """Root of the errors raised by modrob_viz's libraries."""


class TrajectoryError(VizError):
    """A trajectory that cannot be used: joint names the robot lacks, ragged points, NaN."""


class BagError(VizError):
    """A bag that cannot be read or written, or that lacks the expected topic. ``waiting`` is
    True when the bag does not exist yet or holds no messages at all (a recorder may fill it)."""

    def __init__(self, message, waiting=False):
        super().__init__(message)
        self.waiting = waiting


class ConfigError(VizError):
    """A node parameter or the robot description is missing or unusable."""
