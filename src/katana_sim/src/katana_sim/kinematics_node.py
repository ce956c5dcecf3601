"""``katana_arm_kinematics`` node: FK and IK of the Katana's tool frame as ROS services, in the
spirit of katana_driver's arm kinematics node.

Services (in the node's namespace): ``~get_fk`` (katana_sim/GetFK), ``~get_ik`` (katana_sim/GetIK).
Solvers: ``kdl`` (modrob_kinematics' KDL chain from ``robot_description``, numeric
Levenberg-Marquardt within the joint limits), ``triangle`` (the seed's section 4.4 B),
``grasp`` (closed form, tool horizontal). Unreachable targets: ``success: false`` and the reason.
Parameters (~): base_link (katana_base_link), tip_link (katana_gripper_tool_frame).
"""
import math
import threading

import numpy as np
import rospy
import tf2_ros
from geometry_msgs.msg import PoseStamped
from sensor_msgs.msg import JointState

from katana_sim import kinematics as kin
from katana_sim.errors import KatanaError
from katana_sim.srv import GetFK, GetFKResponse, GetIK, GetIKResponse
from katana_sim.tf_util import apply_transform
from modrob_kinematics.errors import KinematicsError, UnreachableError as KdlUnreachable
from modrob_kinematics.kdl_urdf import KinematicChain
from modrob_sim import waits

# wall seconds a request in another frame waits for tf (the first one creates the listener)
TF_WAIT = 5.0


def _quat_of(m):
    """(x, y, z, w) of a 3x3 rotation matrix."""
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + m[0, 0] - m[1, 1] - m[2, 2])) / 2.0, m[2, 1] - m[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] + m[1, 1] - m[2, 2])) / 2.0, m[0, 2] - m[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - m[0, 0] - m[1, 1] + m[2, 2])) / 2.0, m[1, 0] - m[0, 1])
    return x, y, z, w


class KatanaKinematics(object):
    """Pure-ish core of the services: the KDL chain plus the analytic solvers."""

    def __init__(self, urdf_xml, base_link="katana_base_link", tip_link="katana_gripper_tool_frame"):
        self.chain = KinematicChain.from_urdf_string(urdf_xml, base_link, tip_link)
        if list(self.chain.joint_names) != list(kin.JOINTS):
            raise KatanaError("the chain %s -> %s has joints %s, expected the Katana's %s"
                              % (base_link, tip_link, self.chain.joint_names, list(kin.JOINTS)))

    def fk(self, q, solver="kdl"):
        if solver in ("", "kdl"):
            return self.chain.fk_matrix(q)
        if solver == "analytic":
            return kin.fk(q)
        raise KatanaError("unknown FK solver '%s' (kdl | analytic)" % solver)

    def ik(self, position, quaternion=None, solver="kdl", position_only=True, seed=None):
        if solver == "triangle":
            return kin.triangle_ik(position)
        if solver == "grasp":
            return kin.grasp_ik(position)
        if solver not in ("", "kdl"):
            raise KatanaError("unknown IK solver '%s' (kdl | triangle | grasp)" % solver)
        if position_only or quaternion is None:
            target = tuple(position)
        else:
            target = (tuple(position), tuple(quaternion))
        try:
            return self.chain.ik(target, q0=seed, position_only=position_only)
        except KdlUnreachable as exc:
            raise kin.UnreachableError(str(exc))


class KinematicsNode(object):
    def __init__(self):
        base = rospy.get_param("~base_link", "katana_base_link")
        tip = rospy.get_param("~tip_link", "katana_gripper_tool_frame")
        xml = rospy.get_param("robot_description")
        self.core = KatanaKinematics(xml, base, tip)
        self.base = base
        self.lock = threading.Lock()
        self.current = None
        rospy.Subscriber("joint_states", JointState, self._joint_states, queue_size=5)
        self.tf_buffer = tf2_ros.Buffer()
        # from the first target in another frame on: until then the node has no use for the arm's
        # /tf messages (50 per simulated second, each deserialised in Python)
        self.tf_listener = None
        self.services = [rospy.Service("~get_fk", GetFK, self.get_fk),
                         rospy.Service("~get_ik", GetIK, self.get_ik)]
        rospy.loginfo("katana_arm_kinematics: ~get_fk, ~get_ik for %s -> %s" % (base, tip))

    def _joint_states(self, msg):
        with self.lock:
            cur = dict(self.current or {})
            cur.update(zip(msg.name, msg.position))
            self.current = cur

    def get_fk(self, req):
        names = list(req.joint_names) or list(kin.JOINTS)
        res = GetFKResponse()
        unknown = [n for n in names if n not in kin.JOINTS]
        if unknown or len(names) != len(req.positions):
            res.message = ("unknown joint(s) %s (the arm's: %s)" % (unknown, ", ".join(kin.JOINTS)) if unknown
                           else "%d joint names but %d positions" % (len(names), len(req.positions)))
            return res
        q = dict(zip(names, req.positions))
        missing = [j for j in kin.JOINTS if j not in q]
        if missing:
            with self.lock:
                cur = dict(self.current or {})
            for j in missing:
                if j not in cur:
                    res.message = "joint %s not given and no joint state received for it" % j
                    return res
                q[j] = cur[j]
        try:
            m = self.core.fk([q[j] for j in kin.JOINTS], req.solver)
        except (KatanaError, KinematicsError, ValueError) as exc:
            res.message = str(exc)
            return res
        res.pose = PoseStamped()
        res.pose.header.frame_id = self.base
        res.pose.header.stamp = rospy.Time.now()
        p = res.pose.pose
        p.position.x, p.position.y, p.position.z = (float(v) for v in m[:3, 3])
        p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = _quat_of(np.asarray(m)[:3, :3])
        res.success, res.message = True, "ok"
        return res

    def get_ik(self, req):
        res = GetIKResponse()
        target = req.target
        pos = target.pose.position
        ori = target.pose.orientation
        p = [pos.x, pos.y, pos.z]
        quat = [ori.x, ori.y, ori.z, ori.w]
        frame = target.header.frame_id or self.base
        if frame != self.base:
            with self.lock:
                if self.tf_listener is None:
                    self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
            try:
                tf = waits.lookup_transform(self.tf_buffer, self.base, frame, TF_WAIT)
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException) as exc:
                res.message = "cannot transform the target from '%s' to '%s': %s" % (frame, self.base, exc)
                return res
            p = list(apply_transform(tf, p))
            if not req.position_only:
                res.message = "orientation targets must be given in %s" % self.base
                return res
        seed = list(req.seed) if req.seed else None
        if seed is None:
            with self.lock:
                cur = dict(self.current or {})
            if all(j in cur for j in kin.JOINTS):
                seed = [cur[j] for j in kin.JOINTS]
        if seed is not None and len(seed) != 5:
            res.message = "seed has %d values; the arm has 5 joints" % len(seed)
            return res
        norm = math.sqrt(sum(v * v for v in quat))
        position_only = req.position_only or norm < 1e-9
        try:
            q = self.core.ik(p, [v / norm for v in quat] if norm > 0 else None, req.solver or "kdl",
                             position_only, seed)
        except (KatanaError, KinematicsError, ValueError) as exc:
            res.message = "refused: %s" % exc
            return res
        res.success, res.message = True, "ok"
        res.joint_names, res.positions = list(kin.JOINTS), [float(v) for v in q]
        return res


def main():
    rospy.init_node("katana_arm_kinematics")
    try:
        KinematicsNode()
    except (KatanaError, KinematicsError, KeyError) as exc:
        rospy.logfatal("katana_arm_kinematics: %s (is robot_description loaded?)" % exc)
        return 2
    rospy.spin()
    return 0
