"""Odometry from the simulator's model state, as the seed did (section 5.3.1): pure part.

The model state gives the root link's (base_link_polaris) pose and twist in the world frame; the
odometry frame is the world frame (the vehicle's spawn point is its origin only when it spawns at
the world origin, as in the seed). nav_msgs/Odometry wants the twist in the child frame, so the
linear and angular velocities are rotated into base_link_polaris.
"""
import math
from collections import namedtuple

from polaris_description.errors import ConfigError
from polaris_description.transforms import rotate_inverse

OdomState = namedtuple("OdomState", "position orientation linear angular")


def odom_from_model_state(position, orientation, linear_world, angular_world):
    """(position, orientation) unchanged; twist rotated from the world into the body frame."""
    for name, v in (("position", position), ("orientation", orientation), ("linear", linear_world),
                    ("angular", angular_world)):
        if not all(math.isfinite(c) for c in v):
            raise ConfigError("model state %s is not finite: %r" % (name, v))
    q = tuple(orientation)
    n = math.sqrt(sum(c * c for c in q))
    if n < 1e-9:
        q = (0.0, 0.0, 0.0, 1.0)
    else:
        q = tuple(c / n for c in q)
    return OdomState(tuple(position), q, rotate_inverse(q, linear_world), rotate_inverse(q, angular_world))


def find_model(names, model_name):
    """Index of ``model_name`` in a ModelStates name list (None when absent)."""
    try:
        return list(names).index(model_name)
    except ValueError:
        return None
