"""The can stacker's ROS layer: runs a ``planner.StackPlanner`` plan through katana_arm_gazebo's
interfaces (the ``follow_joint_trajectory`` action, the GripperCommand action, ``/joint_states``),
shows the planned path in RViz, and judges the result from the simulator's model states.

Load compensation: the published gains are soft (p = 1 N m/rad at the wrist), so a held can pulls
the joints off their set-points by up to ~0.15 rad. After a move that ends holding the can the
stacker measures the remaining joint error and re-commands set-point + error until the error is
below ``settle_tolerance`` (integral action on top of the controller's PD), then keeps that offset
for the next moves while the can is held. Those moves tell the controller so: their goals carry a
position tolerance of ``HOLD_TOLERANCE`` (the goal's ``goal_tolerance``, which overrides the
controller's 0.05 rad for that goal), so a sag the stacker corrects is not a failed goal.
"""
import math
import threading

import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal, GripperCommandAction,
                              GripperCommandGoal, JointTolerance)
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Point
from sensor_msgs.msg import JointState
from std_msgs.msg import ColorRGBA
from trajectory_msgs.msg import JointTrajectoryPoint
from visualization_msgs.msg import Marker, MarkerArray

from katana_sim import kinematics as kin
from modrob_sim import waits
from modrob_sim.action_client import SimpleActionClient
from katana_sim.errors import KatanaError
from katana_sim.planner import Grip, Move, judge_stack

#: rad: the goal tolerance of moves made holding a can (its load sags the soft arm by up to ~0.15)
HOLD_TOLERANCE = 0.2


class StackError(KatanaError):
    """The stack could not be built (a failed move or grasp); the message says which step."""


class ArmInterface(object):
    """katana_arm_gazebo's arm and gripper actions, joint states and the simulator's model states
    (read when asked: the stacker needs them before the plan and for the judgement, and the
    simulator sends them 100 times per simulated second to whoever subscribes)."""

    def __init__(self, wait=120.0):
        self.lock = threading.Lock()
        self.wait = wait
        self.q = {}
        self.joint_log = []          # (t, desired, actual) samples for the tracking plot
        self.desired = None
        rospy.Subscriber("/joint_states", JointState, self._joint_states, queue_size=5)
        self.arm = SimpleActionClient("/katana_arm_controller/follow_joint_trajectory",
                                      FollowJointTrajectoryAction)
        self.gripper = SimpleActionClient("/gripper_grasp_posture_controller", GripperCommandAction)
        missing = waits.wait_for_action_servers(
            ((self.arm, "/katana_arm_controller/follow_joint_trajectory"),
             (self.gripper, "/gripper_grasp_posture_controller")), wait)
        if missing:
            raise StackError("no action server %s after %.0f s: is katana.launch running?" % (missing, wait))
        if not waits.wait_until(self._has_arm_joints, wait):
            raise StackError("no /joint_states with the Katana's arm joints after %.0f s" % wait)

    def _has_arm_joints(self):
        with self.lock:
            return all(j in self.q for j in kin.JOINTS)

    def _joint_states(self, msg):
        with self.lock:
            for n, p in zip(msg.name, msg.position):
                self.q[n] = p
            if msg.name and msg.name[0] == kin.JOINTS[0] and self.desired is not None:
                self.joint_log.append((msg.header.stamp.to_sec(), list(self.desired),
                                       [self.q[j] for j in kin.JOINTS]))

    def joints(self):
        with self.lock:
            return [self.q[j] for j in kin.JOINTS]

    def model_poses(self):
        """{model name: ((x, y, z), (qx, qy, qz, qw))} of the next /gazebo/model_states."""
        try:
            msg = rospy.wait_for_message("/gazebo/model_states", ModelStates, timeout=self.wait)
        except rospy.ROSException:
            raise StackError("no /gazebo/model_states within %.0f s: is the simulator running?" % self.wait)
        return {name: ((pose.position.x, pose.position.y, pose.position.z),
                       (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w))
                for name, pose in zip(msg.name, msg.pose)}

    def model_pose(self, name):
        return self.model_poses().get(name)

    def follow(self, points, tolerance=None):
        """points [(t, q)]; ``tolerance`` (rad): the goal's position tolerance for every joint
        instead of the controller's; returns (ok, error_code, text). The result is waited for in
        wall time (modrob_sim.waits): the move's own duration plus ``wait``; a limit in simulated
        time would run out in wall milliseconds at real_time_factor 0 while this client waits for
        its turn on the CPU."""
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(kin.JOINTS)
        if tolerance is not None:
            goal.goal_tolerance = [JointTolerance(name=j, position=tolerance) for j in kin.JOINTS]
        for t, q in points:
            goal.trajectory.points.append(JointTrajectoryPoint(positions=list(q),
                                                               time_from_start=rospy.Duration(t)))
        goal.trajectory.points[-1].velocities = [0.0] * 5
        with self.lock:
            self.desired = list(points[-1][1])
        self.arm.send_goal(goal)
        limit = points[-1][0] + self.wait
        if not waits.wait_for_result(self.arm, limit):
            self.arm.cancel_goal()
            return False, None, "no result within %.0f wall seconds" % limit
        res = self.arm.get_result()
        ok = self.arm.get_state() == GoalStatus.SUCCEEDED
        code = res.error_code if res is not None else None
        return ok, code, (res.error_string if res is not None else "") or self.arm.get_goal_status_text()

    def grip(self, position, max_effort):
        goal = GripperCommandGoal()
        goal.command.position, goal.command.max_effort = position, max_effort
        self.gripper.send_goal(goal)
        if not waits.wait_for_result(self.gripper, self.wait):
            self.gripper.cancel_goal()
            return False, None, "the gripper gave no result within %.0f wall seconds" % self.wait
        return (self.gripper.get_state() == GoalStatus.SUCCEEDED, self.gripper.get_result(),
                self.gripper.get_goal_status_text())


class Stacker(object):
    def __init__(self, arm, planner, settle_tolerance=0.004, settle_iterations=6,
                 marker_frame="katana_base_link",
                 log=rospy.loginfo):
        self.arm, self.planner = arm, planner
        self.settle_tolerance, self.settle_iterations = settle_tolerance, settle_iterations
        self.offset = [0.0] * 5
        self.holding = False
        self.marker_frame = marker_frame
        self.log = log
        self.path_pub = rospy.Publisher("/katana/planned_path", MarkerArray, queue_size=1, latch=True)
        self.release_time = None

    def run(self, top, bottom):
        steps = self.planner.plan(self.arm.joints(), top, bottom)
        self.publish_path(steps)
        for i, step in enumerate(steps):
            self.log("step %d/%d: %s" % (i + 1, len(steps), step.name))
            if isinstance(step, Move):
                self.move(step)
            elif isinstance(step, Grip):
                self.grip(step)
        return steps

    def move(self, step):
        points = [(t, [q + o for q, o in zip(qs, self.offset)]) for t, qs in step.points]
        # holding a can, the soft controller sags beyond its own goal tolerance: settle() corrects that
        ok, code, text = self.arm.follow(points, tolerance=HOLD_TOLERANCE if self.holding else None)
        if not ok:
            raise StackError("move '%s' failed: %s" % (step.name, text))
        if self.holding:
            self.settle(step.target)

    def settle(self, target):
        """Integral correction of the load's static joint error (see the module doc)."""
        for n in range(self.settle_iterations + 1):
            rospy.sleep(0.3)        # simulated time for the arm to come to rest before measuring
            err = [t - a for t, a in zip(target, self.arm.joints())]
            worst = max(abs(e) for e in err)
            if worst < self.settle_tolerance:
                return
            if n == self.settle_iterations:     # measured after the last correction too
                break
            self.offset = [o + e for o, e in zip(self.offset, err)]
            cmd = [t + o for t, o in zip(target, self.offset)]
            self.arm.follow([(0.8, cmd)], tolerance=HOLD_TOLERANCE)
        rospy.logwarn("joint error still %.4f rad (more than %.4f) after %d corrections"
                      % (worst, self.settle_tolerance, self.settle_iterations))

    def grip(self, step):
        ok, res, text = self.arm.grip(step.position, step.max_effort)
        if step.name == "close":
            if not ok or res is None or not res.stalled:
                raise StackError("grasp failed: the gripper did not stop on the can (%s)" % text)
            self.holding = True
            self.log("grasp: %s" % text)
        else:
            if not ok:
                raise StackError("gripper '%s' failed: %s" % (step.name, text))
            if self.holding:
                self.release_time = rospy.get_time()
            self.holding = False
            self.offset = [0.0] * 5

    def publish_path(self, steps):
        arr = MarkerArray()
        arr.markers.append(Marker(action=Marker.DELETEALL))
        for i, step in enumerate(s for s in steps if isinstance(s, Move)):
            m = Marker(type=Marker.LINE_STRIP, action=Marker.ADD, ns="planned_path", id=i)
            m.header.frame_id = self.marker_frame
            m.header.stamp = rospy.Time(0)
            m.pose.orientation.w = 1.0
            m.scale.x = 0.004
            straight = step.name in ("approach", "lift", "back", "raise", "place", "retreat")
            m.color = ColorRGBA(0.1, 0.8, 0.1, 1.0) if straight else ColorRGBA(0.95, 0.6, 0.1, 1.0)
            m.points = [Point(*p) for p in step.tool_path]
            arr.markers.append(m)
        self.path_pub.publish(arr)

    def judge(self, top_name, bottom_name, wait=5.0, can_height=0.122):
        """Wait ``wait`` s of simulated time after the release, then judge the stack."""
        start = self.release_time if self.release_time is not None else rospy.get_time()
        while not rospy.is_shutdown() and rospy.get_time() < start + wait:
            rospy.sleep(0.1)
        poses = self.arm.model_poses()
        top, bottom = poses.get(top_name), poses.get(bottom_name)
        if top is None or bottom is None:
            raise StackError("the simulator reports no model '%s' or '%s'" % (top_name, bottom_name))
        return judge_stack(top, bottom, can_height=can_height)


def degrees(rad):
    return rad * 180.0 / math.pi
