"""Joint-space trajectories as arrays (no rospy): validation against a robot, end-effector
path by KDL forward kinematics, decimation (the seed's keep-1-of-5) and milestone reduction."""
import math

import numpy as np
import PyKDL

from modrob_viz import geometry
from modrob_viz.errors import KinematicsError, TrajectoryError
from modrob_kinematics.kdl_urdf import TreeFkSolverPos


class JointPath(object):
    """``names`` (J joint names) and ``positions`` (N x J array); ``times`` (N seconds from start,
    may be all zero when the source had none)."""

    def __init__(self, names, positions, times=None):
        self.names = [str(n) for n in names]
        if len(set(self.names)) != len(self.names):
            raise TrajectoryError("trajectory names a joint twice: %s" % ", ".join(self.names))
        pos = np.asarray(positions, dtype=float)
        if pos.size == 0:
            pos = pos.reshape(0, len(self.names))
        if pos.ndim != 2 or pos.shape[1] != len(self.names):
            raise TrajectoryError("trajectory has %d joint names but points of shape %s"
                                  % (len(self.names), pos.shape))
        if not np.all(np.isfinite(pos)):
            bad = int(np.argmax(~np.all(np.isfinite(pos), axis=1)))
            raise TrajectoryError("trajectory point %d has a non-finite position %s"
                                  % (bad, pos[bad].tolist()))
        self.positions = pos
        self.times = np.zeros(len(pos)) if times is None else np.asarray(times, dtype=float)

    def __len__(self):
        return len(self.positions)

    @classmethod
    def from_points(cls, names, points):
        """From ``trajectory_msgs/JointTrajectoryPoint``-like objects (``positions``,
        ``time_from_start``); every point must have one position per name."""
        rows, times = [], []
        for i, p in enumerate(points):
            if len(p.positions) != len(names):
                raise TrajectoryError("trajectory point %d has %d positions for %d joint names (%s)"
                                      % (i, len(p.positions), len(names), ", ".join(names)))
            rows.append(list(p.positions))
            t = getattr(p, "time_from_start", None)
            times.append(t.to_sec() if t is not None else 0.0)
        return cls(names, rows, times)

    def subset(self, indices):
        idx = list(indices)
        return JointPath(self.names, self.positions[idx], self.times[idx])

    def check_against(self, kdl_tree, needed=None):
        """Refuse joint names the robot lacks and missing joints the FK needs (``needed``)."""
        unknown = [n for n in self.names if n not in kdl_tree.joint_types]
        if unknown:
            raise TrajectoryError("trajectory names joint(s) %s that robot '%s' lacks "
                                  "(its movable joints: %s)" % (", ".join(unknown), kdl_tree.robot_name,
                                                                ", ".join(kdl_tree.joint_names)))
        missing = [n for n in (needed or []) if n not in self.names]
        if missing:
            raise TrajectoryError("trajectory lacks joint(s) %s needed for the end-effector pose "
                                  "of robot '%s'"
                                  % (", ".join(missing), kdl_tree.robot_name))


def end_effector_path(kdl_tree, joint_path, ee_link, base_link=None):
    """(N, 3) array of ``ee_link`` positions in ``base_link`` (default: the tree root) for every
    point, with :class:`TreeFkSolverPos` (KDL's TreeFkSolverPos_recursive)."""
    base_link = base_link or kdl_tree.root
    needed = set(kdl_tree.joints_between(kdl_tree.root, ee_link))
    if base_link != kdl_tree.root:
        needed |= set(kdl_tree.joints_between(kdl_tree.root, base_link))
    joint_path.check_against(kdl_tree, sorted(needed))
    solver = TreeFkSolverPos(kdl_tree)
    out = np.zeros((len(joint_path), 3))
    movable = [n for n in joint_path.names if n in kdl_tree.limits]
    cols = [joint_path.names.index(n) for n in movable]
    for i, row in enumerate(joint_path.positions):
        q = dict(zip(movable, row[cols]))
        frame = solver.jnt_to_cart(q, ee_link)
        if base_link != kdl_tree.root:
            frame = solver.jnt_to_cart(q, base_link).Inverse() * frame
        out[i] = (frame.p[0], frame.p[1], frame.p[2])
    return out


def decimate(n, keep_every):
    """Indices kept when only the last of every ``keep_every`` points is played (the seed's
    strategy with 5); the final point is always kept so the path ends where it should."""
    if int(keep_every) != keep_every or keep_every < 1:
        raise TrajectoryError("keep_every must be an integer >= 1, got %r" % (keep_every,))
    keep_every = int(keep_every)
    idx = list(range(keep_every - 1, n, keep_every))
    if n and (not idx or idx[-1] != n - 1):
        idx.append(n - 1)
    return idx


def reduce_milestones(ee_points, tolerance):
    """Indices of the joint points to keep: those whose end-effector point survives a
    Douglas-Peucker reduction of the end-effector path with ``tolerance`` [m]."""
    return geometry.douglas_peucker(ee_points, tolerance)


def frame_position(frame):
    if not isinstance(frame, PyKDL.Frame):
        raise KinematicsError("expected a PyKDL.Frame")
    p = frame.p
    if not all(math.isfinite(v) for v in (p[0], p[1], p[2])):
        raise KinematicsError("forward kinematics gave a non-finite position")
    return (p[0], p[1], p[2])
