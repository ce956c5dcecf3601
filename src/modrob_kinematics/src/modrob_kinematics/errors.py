"""The exception types of modrob_kinematics. They derive from modrob_msgs' ModrobError (the
workspace's one root), so a node can catch every library error at its boundary without catching
bugs."""
from modrob_msgs.errors import ModrobError


class KinematicsError(ModrobError):
    """A kinematic request that cannot be served: an unknown link, no chain between two links,
    a joint vector of the wrong length, NaN in the input."""


class UrdfError(KinematicsError):
    """A robot description that cannot be turned into a kinematic tree (malformed XML, several
    root links, a joint whose link is missing, a revolute joint without limits ...)."""


class UnreachableError(KinematicsError):
    """An IK target that no configuration within the joint limits reaches. ``residual`` holds
    the best position error found [m] (``float('inf')`` when the solver never converged)."""

    def __init__(self, message, residual=float("inf")):
        super().__init__(message)
        self.residual = residual
