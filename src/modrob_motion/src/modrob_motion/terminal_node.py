"""ROS layer of ``motion_terminal``: lines from stdin -> JointState on /modrob<N>/motion_command.

Robots are found on the parameter server as ``/modrob<N>/robot_description``; the measured joint
angles come from ``/modrob<N>/joint_states``; ``xyz`` targets are solved with KDL
(:mod:`modrob_motion.cartesian`) in the world frame, using the robot model's pose from
``/gazebo/get_model_state`` when its URDF root is not ``world``.
Parameters: ~robot (start robot id, 0), ~tip_link, ~tcp_offset [x,y,z] (tool point in the tip
frame, default the gripper's fingertip centre when ~tcp_offset is unset: [0,0,0]),
~connect_timeout (wall-clock s to wait for a motion_publisher before sending, 3), ~linger (s to stay after
end of input so the last command is delivered, 0.5).
"""
import re
import sys
import threading
import time

import rospy
from sensor_msgs.msg import JointState

from modrob_msgs.errors import ModrobError
from modrob_motion.cartesian import CartesianIk, default_tip
from modrob_motion.errors import MotionError
from modrob_motion.robot_info import robot_info_from_urdf
from modrob_motion.terminal import MotionTerminal

ROBOT_PARAM = re.compile(r"^/modrob(\d+)/robot_description$")


class RosRobotDirectory(object):
    """Robots on the parameter server, read once each (a changed description needs a restart)."""

    def __init__(self):
        self.cache = {}
        self.errors = {}

    def ids(self):
        return sorted(int(m.group(1)) for m in (ROBOT_PARAM.match(n) for n in rospy.get_param_names()) if m)

    def urdf(self, robot_id):
        return rospy.get_param("/modrob%d/robot_description" % robot_id, None)

    def get(self, robot_id):
        if robot_id in self.cache:
            return self.cache[robot_id]
        urdf = self.urdf(robot_id)
        if not urdf:
            return None
        info = robot_info_from_urdf(robot_id, urdf)   # MotionError reaches the terminal's reply
        self.cache[robot_id] = info
        return info


class MotionTerminalNode(object):

    def __init__(self, robot_id=0, tip_link=None, tcp_offset=(0.0, 0.0, 0.0), connect_timeout=3.0,
                 out=sys.stdout):
        self.out = out
        self.directory = RosRobotDirectory()
        self.connect_timeout = connect_timeout
        self.tip_link = tip_link
        self.tcp_offset = tcp_offset
        self._lock = threading.Lock()
        self._measured = {}
        self._subs = {}
        self._pubs = {}
        self._iks = {}
        self.terminal = MotionTerminal(self.directory, robot_id, ik_solver=self._ik,
                                       measured=self._measured_of)

    # -- ROS plumbing --------------------------------------------------------------------
    def _measured_of(self, robot_id):
        self._ensure_sub(robot_id)
        with self._lock:
            return dict(self._measured.get(robot_id, {}))

    def _ensure_sub(self, robot_id):
        if robot_id not in self._subs:
            self._subs[robot_id] = rospy.Subscriber("/modrob%d/joint_states" % robot_id, JointState,
                                                    self._on_joint_states, callback_args=robot_id,
                                                    queue_size=1)

    def _on_joint_states(self, msg, robot_id):
        with self._lock:
            self._measured.setdefault(robot_id, {}).update(zip(msg.name, msg.position))

    def _publisher(self, robot_id):
        if robot_id not in self._pubs:
            self._pubs[robot_id] = rospy.Publisher("/modrob%d/motion_command" % robot_id, JointState,
                                                   queue_size=10)
        return self._pubs[robot_id]

    def _base_pose(self, robot_id):
        from gazebo_msgs.srv import GetModelState
        try:
            rospy.wait_for_service("/gazebo/get_model_state", timeout=2.0)
            res = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)("modrob%d" % robot_id, "world")
        except (rospy.ROSException, rospy.ServiceException) as exc:
            raise MotionError("cannot get modrob%d's pose from /gazebo/get_model_state: %s" % (robot_id, exc))
        if not res.success:
            raise MotionError("/gazebo/get_model_state: %s" % res.status_message)
        p, o = res.pose.position, res.pose.orientation
        return (p.x, p.y, p.z), (o.x, o.y, o.z, o.w)

    def _ik(self, info, xyz, seed):
        if info.robot_id not in self._iks:
            urdf = self.directory.urdf(info.robot_id)
            tip = self.tip_link or (default_tip(urdf, info.gripper.joints) if info.gripper else None)
            rid = info.robot_id
            root_is_world = "<link name=\"world\"" in urdf or "<link name='world'" in urdf
            base = None if root_is_world else (lambda: self._base_pose(rid))
            self._iks[rid] = CartesianIk(urdf, info.arm_joints, tip_link=tip, tcp_offset=self.tcp_offset,
                                         base_pose=base)
        return self._iks[info.robot_id].solve(info, xyz, seed)

    def send(self, command):
        pub = self._publisher(command.robot_id)
        # connecting to a subscriber takes wall-clock time: at real_time_factor 0 the simulated
        # seconds of connect_timeout pass long before the handshake ends
        deadline = time.monotonic() + self.connect_timeout
        while pub.get_num_connections() == 0 and time.monotonic() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
        if pub.get_num_connections() == 0:
            self.write("warning: nothing listens on /modrob%d/motion_command (start motion_publisher); "
                       "sent anyway" % command.robot_id)
        msg = JointState(name=command.names, position=command.positions)
        msg.header.stamp = rospy.Time.now()
        pub.publish(msg)

    def write(self, text):
        if text:
            self.out.write(text + "\n")
            self.out.flush()

    # -- the loop ------------------------------------------------------------------------
    def handle(self, line):
        reply = self.terminal.handle(line)
        self.write(reply.text)
        if reply.command is not None:
            self.send(reply.command)
        return reply

    def run(self, stream=sys.stdin):
        interactive = stream.isatty()
        self.write("motion_terminal: type help for the commands; controlling modrob%d"
                   % self.terminal.robot_id)
        while not rospy.is_shutdown():
            if interactive:
                self.out.write(self.terminal.prompt())
                self.out.flush()
            line = stream.readline()
            if not line:
                break
            try:
                reply = self.handle(line)
            except ModrobError as exc:
                self.write(str(exc))
                continue
            if reply.quit:
                break


def main():
    rospy.init_node("motion_terminal", disable_signals=False)
    offset = rospy.get_param("~tcp_offset", [0.0, 0.0, 0.0])
    node = MotionTerminalNode(int(rospy.get_param("~robot", 0)), rospy.get_param("~tip_link", None) or None,
                              tuple(float(v) for v in offset),
                              float(rospy.get_param("~connect_timeout", 3.0)))
    node.run()
    time.sleep(float(rospy.get_param("~linger", 0.5)))  # wall time: let the last messages go out
