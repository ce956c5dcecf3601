"""``keyboard_teleop`` node: keys -> katana_arm_controller's trajectory action and the gripper
action (keys in katana_sim.teleop.KEYS). The terminal is restored on every exit path.

Parameters (~): increment (rad, default 5 deg), step (rad, default 1 deg), move_time (s per
step, default 0.6).
"""
import math
import os
import select
import sys
import termios
import threading
import tty

import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal, GripperCommandAction, \
    GripperCommandGoal
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from katana_sim import kinematics as kin
from modrob_sim import waits
from modrob_sim.action_client import SimpleActionClient
from katana_sim.teleop import TeleopState, help_text


class TeleopNode(object):
    def __init__(self):
        self.state = TeleopState(increment=float(rospy.get_param("~increment", math.radians(5.0))),
                                 step=float(rospy.get_param("~step", math.radians(1.0))))
        self.move_time = float(rospy.get_param("~move_time", 0.6))
        self.lock = threading.Lock()
        self.q = {}
        self.target = None
        rospy.Subscriber("joint_states", JointState, self._joint_states, queue_size=5)
        self.arm = SimpleActionClient("katana_arm_controller/follow_joint_trajectory",
                                      FollowJointTrajectoryAction)
        self.gripper = SimpleActionClient("gripper_grasp_posture_controller", GripperCommandAction)

    def _joint_states(self, msg):
        with self.lock:
            self.q.update(zip(msg.name, msg.position))

    def current(self):
        with self.lock:
            if self.target is not None:
                return list(self.target)
            return [self.q.get(j, 0.0) for j in kin.JOINTS]

    def wait_ready(self, timeout=60.0):
        missing = waits.wait_for_action_servers(
            ((self.arm, "katana_arm_controller/follow_joint_trajectory"),
             (self.gripper, "gripper_grasp_posture_controller")), timeout)
        if missing:
            print("keyboard_teleop: no action server %s after %.0f s (is katana.launch running?)"
                  % (rospy.resolve_name(missing), timeout))
            return False
        if not waits.wait_until(self._has_arm_joints, timeout):
            if not rospy.is_shutdown():
                print("keyboard_teleop: no joint_states with the arm's joints after %.0f s" % timeout)
            return False
        return True

    def _has_arm_joints(self):
        with self.lock:
            return all(j in self.q for j in kin.JOINTS)

    def apply(self, cmd):
        if cmd.kind == "move":
            goal = FollowJointTrajectoryGoal()
            goal.trajectory.joint_names = list(kin.JOINTS)
            goal.trajectory.points = [JointTrajectoryPoint(positions=cmd.positions, velocities=[0.0] * 5,
                                                           time_from_start=rospy.Duration(self.move_time))]
            with self.lock:
                self.target = list(cmd.positions)
            self.arm.send_goal(goal)
        elif cmd.kind == "grip":
            goal = GripperCommandGoal()
            goal.command.position = cmd.gripper
            self.gripper.send_goal(goal)
        if cmd.text:
            say(cmd.text)


def say(text):
    sys.stdout.write(text.replace("\n", "\r\n") + "\r\n")
    sys.stdout.flush()


def main():
    rospy.init_node("keyboard_teleop")
    node = TeleopNode()
    if not node.wait_ready():
        return 2
    say(help_text(node.state))
    fd = sys.stdin.fileno()
    interactive = sys.stdin.isatty()
    saved = termios.tcgetattr(fd) if interactive else None
    try:
        if interactive:
            tty.setcbreak(fd)
        while not rospy.is_shutdown():
            ready, _, _ = select.select([fd], [], [], 0.1)
            if not ready:
                continue
            data = os.read(fd, 1)          # unbuffered: select() must see every pending key
            if not data:
                break
            key = data.decode("latin-1")
            cmd = node.state.handle(key, node.current())
            if cmd.kind == "quit":
                say(cmd.text)
                break
            node.apply(cmd)
    except KeyboardInterrupt:
        pass
    finally:
        if saved is not None:
            termios.tcsetattr(fd, termios.TCSADRAIN, saved)
    return 0
