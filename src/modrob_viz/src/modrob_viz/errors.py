"""The exception types of modrob_viz. They derive from modrob_msgs' ModrobError (the workspace's
one root), so a node can catch every library error at its boundary without catching bugs."""
from modrob_msgs.errors import ModrobError


class VizError(ModrobError):
    """Root of the errors raised by modrob_viz's libraries."""


class UrdfError(VizError):
    """A robot description that cannot be turned into a kinematic tree (malformed XML, several
    root links, a joint whose link is missing, a revolute joint without limits ...)."""


class KinematicsError(VizError):
    """A kinematic request that cannot be served: an unknown link, no chain between two links,
    a joint vector of the wrong length, NaN in the input."""


class UnreachableError(KinematicsError):
    """An IK target that no configuration within the joint limits reaches. ``residual`` holds
    the best position error found [m] (``float('inf')`` when the solver never converged)."""

    def __init__(self, message, residual=float("inf")):
        super().__init__(message)
        self.residual = residual


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
