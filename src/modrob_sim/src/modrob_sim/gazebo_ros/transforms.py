"""Pose and twist arithmetic for the /gazebo node (pure, no rospy).

Conventions of the physics contract: a pose is ``((x, y, z), (qx, qy, qz, qw))``, a twist is
``((vx, vy, vz), (wx, wy, wz))`` in the world frame; all plain floats.
"""
import math

# The quaternion and pose primitives are the physics core's (one implementation); this module
# adds what only the node needs: Gazebo's zero-quaternion rule, frames, twists.
from modrob_sim.physics.transforms import (  # noqa: F401  (re-exported for the node's modules)
    cross, pose_inv as inverse, quat_conj, quat_from_rpy, quat_mul, quat_rotate, rpy_from_quat)

IDENTITY = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
ZERO_TWIST = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def quat_normalize(q):
    """Unit quaternion; an all-zero quaternion (a default-constructed geometry_msgs/Quaternion)
    means identity, as Gazebo treats it."""
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if n < 1e-12:
        return (0.0, 0.0, 0.0, 1.0)
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def compose(a, b):
    """Pose a * b: b expressed in frame a, returned in a's parent frame."""
    return (add(a[0], quat_rotate(a[1], b[0])), quat_normalize(quat_mul(a[1], b[1])))


def relative(frame, pose):
    """World pose ``pose`` expressed in the frame whose world pose is ``frame``."""
    return compose(inverse(frame), pose)


def twist_in_frame(frame_pose, frame_twist, twist):
    """World twist expressed relative to a moving frame, as Gazebo's get_model_state does:
    the difference of the velocities rotated into the frame."""
    qi = quat_conj(frame_pose[1])
    return (quat_rotate(qi, sub(twist[0], frame_twist[0])),
            quat_rotate(qi, sub(twist[1], frame_twist[1])))


def twist_to_world(frame_pose, twist):
    """A twist given in a reference frame, rotated into the world (Gazebo's set_model_state)."""
    q = frame_pose[1]
    return (quat_rotate(q, twist[0]), quat_rotate(q, twist[1]))


def is_finite(*values):
    """True when every number in the (nested) tuples is finite."""
    for v in values:
        if isinstance(v, (tuple, list)):
            if not is_finite(*v):
                return False
        elif not math.isfinite(v):
            return False
    return True


def pose_distance(a, b):
    """(translation distance, rotation angle) between two poses."""
    d = sub(a[0], b[0])
    dist = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    dot = abs(sum(x * y for x, y in zip(a[1], b[1])))
    return dist, 2.0 * math.acos(min(1.0, dot))
