"""Cartesian targets (``xyz x y z`` in the terminal) solved with KDL IK (modrob_kinematics.kdl_urdf).

The target is a point in the WORLD frame. The chain runs from the URDF's root link to the tip
link (by default the gripper's base when the robot has a gripper, else the deepest link),
optionally extended by a fixed tool offset (``tcp_offset``, in the tip frame) so that "the end
effector" can mean the point between the fingertips. When the URDF root is not the world itself,
``base_pose`` (the robot model's pose in the world, e.g. from /gazebo/get_model_state) maps the
world target into the root frame. Pure: no rospy.
"""
import math

import numpy as np
import PyKDL

from modrob_kinematics import kdl_urdf
from modrob_kinematics.errors import KinematicsError, UnreachableError
from modrob_motion.errors import MotionError
from modrob_motion.robot_info import parse_urdf_joints


def _quat_matrix(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    if n < 1e-12:
        raise MotionError("base pose quaternion is zero")
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def default_tip(urdf_xml, finger_joints):
    """The gripper's grasp centre (a fixed link whose name ends in 'tcp', as gripper.xacro's
    ``<prefix>gripper_tcp``), else the parent link of the finger joints (the gripper's base), else
    None (the deepest link is used)."""
    joints = parse_urdf_joints(urdf_xml)
    tcps = [j.child for j in joints if j.type == "fixed" and (j.child or "").endswith("tcp")]
    if len(tcps) == 1:
        return tcps[0]
    parents = {j.parent for j in joints if j.name in set(finger_joints)}
    return parents.pop() if len(parents) == 1 else None


class CartesianIk(object):
    """IK for one robot's arm: ``solve(info, xyz, seed) -> positions`` in ``info.arm_joints`` order.

    urdf_xml: the robot's URDF; arm_joints: the joints the result is ordered by (all of the
    chain's movable joints must be among them); tip_link / tcp_offset: see the module doc;
    base_pose: ((x, y, z), (qx, qy, qz, qw)) of the URDF root in the world, or a callable returning it.
    """

    def __init__(self, urdf_xml, arm_joints, tip_link=None, tcp_offset=(0.0, 0.0, 0.0), base_pose=None,
                 tol=1e-4):
        self.arm_joints = list(arm_joints)
        try:
            tree = kdl_urdf.tree_from_urdf_string(urdf_xml)
            tip = tip_link or kdl_urdf.default_tip_link(tree)
            if any(abs(v) > 0.0 for v in tcp_offset):
                tip = self._add_tcp(tree, tip, tcp_offset)
            self.chain = kdl_urdf.KinematicChain(tree, tree.root, tip)
        except KinematicsError as exc:
            raise MotionError("cannot build the IK chain: %s" % exc)
        missing = [j for j in self.chain.joint_names if j not in self.arm_joints]
        if missing:
            raise MotionError("the IK chain to '%s' moves %s, which are not arm joints; "
                              "choose another tip link"
                              % (self.chain.tip_link, ", ".join(missing)))
        self.base_pose = base_pose
        self.tol = tol

    @staticmethod
    def _add_tcp(tree, tip, offset):
        name = tip + "_tcp"
        seg = PyKDL.Segment(name, PyKDL.Joint(name + "_joint", PyKDL.Joint.Fixed),
                            PyKDL.Frame(PyKDL.Vector(*[float(v) for v in offset])))
        if name not in tree.segments:
            if not tree.tree.addSegment(seg, tip):
                raise MotionError("could not add the tool point below link '%s'" % tip)
            tree.segments[name] = kdl_urdf.SegmentInfo(seg, tip, name + "_joint", "fixed", None,
                                                       np.zeros((3, 3)))
        return name

    def _base(self):
        pose = self.base_pose() if callable(self.base_pose) else self.base_pose
        if pose is None:
            return np.zeros(3), np.eye(3)
        return np.array(pose[0], dtype=float), _quat_matrix(pose[1])

    def to_root(self, xyz_world):
        p, r = self._base()
        return r.T.dot(np.asarray(xyz_world, dtype=float) - p)

    def to_world(self, xyz_root):
        p, r = self._base()
        return r.dot(np.asarray(xyz_root, dtype=float)) + p

    def forward(self, positions_by_name):
        """World position of the end effector for ``{joint: q}`` (missing joints taken as 0)."""
        q = [float(positions_by_name.get(j, 0.0)) for j in self.chain.joint_names]
        return tuple(self.to_world(self.chain.fk_position(q)))

    def solve(self, info, xyz, seed):
        """Arm joint positions putting the end effector at world point ``xyz``; MotionError if not."""
        target = self.to_root(xyz)
        seed_by_name = dict(zip(info.arm_joints, seed))
        q0 = [seed_by_name.get(j, 0.0) for j in self.chain.joint_names]
        try:
            q = self.chain.ik(tuple(target), q0=q0, position_only=True, tol=self.tol)
        except UnreachableError as exc:
            # KDL's LMA ignores joint limits; when the point is within reach, search again inside
            # the limits (bounded least squares on KDL's forward kinematics)
            q = self._bounded(target, q0) if exc.residual < 0.05 else None
            if q is None:
                raise MotionError("xyz %.3f %.3f %.3f is unreachable for modrob%d: %s"
                                  % (tuple(xyz) + (info.robot_id, exc)))
        except KinematicsError as exc:
            raise MotionError("IK failed for modrob%d: %s" % (info.robot_id, exc))
        solved = dict(zip(self.chain.joint_names, q))
        return [solved.get(j, seed_by_name.get(j, 0.0)) for j in info.arm_joints]

    def _bounded(self, target, q0, attempts=12):
        """Position IK inside the joint limits: scipy least squares from q0 and seeded random starts.
        Returns the joint list or None."""
        import random
        from scipy.optimize import least_squares
        lo = np.array([max(v, -math.pi) for v in self.chain.lower])
        hi = np.array([min(v, math.pi) for v in self.chain.upper])
        rng = random.Random(0)
        starts = [np.clip(np.array(q0, dtype=float), lo, hi)]
        starts += [np.array([rng.uniform(a, b) for a, b in zip(lo, hi)]) for _ in range(attempts - 1)]

        def residual(q):
            return np.array(self.chain.fk_position(list(q))) - target
        best = None
        for s in starts:
            sol = least_squares(residual, s, bounds=(lo, hi), xtol=1e-12, ftol=1e-12, max_nfev=300)
            err = float(np.linalg.norm(residual(sol.x)))
            if best is None or err < best[0]:
                best = (err, sol.x)
            if err <= self.tol:
                return [float(v) for v in sol.x]
        return None

    __call__ = solve
