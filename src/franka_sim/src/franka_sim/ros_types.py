"""The ROS side of franka_sim, and the registration of its types with modrob_sim's ros_control
emulation (this module is what franka_sim's package.xml exports):

- robotSimType ``franka_gazebo/FrankaHWSim``: reads ``<ns>/arm_id`` (default: the robot
  namespace) and ``<ns>/motion_generators``, publishes ``<ns>/initialized`` (std_msgs/Bool,
  latched: false at load, true from the first update);
- ``franka_control/FrankaStateController``: ``<controller>/joint_states``,
  ``<controller>/joint_states_desired`` (sensor_msgs/JointState), ``<controller>/franka_states``
  (franka_msgs/FrankaState) and ``/tf`` for ``<arm_id>_link8 -> _NE -> _EE -> _K``;
- ``franka_gazebo/FrankaGripperSim``: the actions ``<controller>/move``, ``grasp``, ``homing``,
  ``stop`` (franka_gripper) and ``gripper_action`` (control_msgs/GripperCommand), and
  ``<controller>/joint_states``.
"""
import types

import actionlib
import rospy
from control_msgs.msg import GripperCommandAction, GripperCommandResult
from franka_gripper.msg import (GraspAction, GraspResult, HomingAction, HomingResult, MoveAction, MoveResult,
                                StopAction, StopResult)
from franka_msgs.msg import FrankaState
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from tf2_msgs.msg import TFMessage

from modrob_sim.errors import InputError
from modrob_sim.physics.transforms import quat_from_matrix
from modrob_sim.ros_control.extensions import register_controller_type, register_robot_sim_type
from modrob_sim.ros_control.params import Params, join
from modrob_sim.ros_control.ros_adapters import Adapter, _status_in_sim_time

from franka_sim.gripper import GRASPING, HOLDING, HOMING_SPEED, MAX_WIDTH, MIN_GRASP_FORCE, MOVING
from franka_sim.gripper import FrankaGripperSim
from franka_sim.hw_sim import SIM_TYPE, FrankaHWSim
from franka_sim.state_controller import FrankaStateController

# franka_gazebo's transforms of the flange (F), nominal end effector (NE), end effector (EE) and
# stiffness frame (K), column-major 4x4 as franka_msgs carries them
IDENTITY = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]
F_T_NE_HAND = [0.7071, -0.7071, 0, 0, 0.7071, 0.7071, 0, 0, 0, 0, 1, 0, 0, 0, 0.1034, 1]


def _param(name, default=None):
    try:
        return rospy.get_param(name)
    except KeyError:
        return default


def _stamp(t):
    return rospy.Time.from_sec(max(0.0, t))


# ---- FrankaHWSim -------------------------------------------------------------------------------
def make_hw(plugin, model, transmissions, pid_gains, warn):
    ns = plugin.namespace
    default_id = ns.strip("/") or model.name
    arm_id = str(_param(join(ns, "arm_id"), default_id))
    if arm_id != default_id:
        rospy.loginfo("model '%s': FrankaHWSim uses arm_id '%s' from %s"
                      % (model.name, arm_id, join(ns, "arm_id")))
    mg_ns = join(ns, "motion_generators")
    hw = FrankaHWSim(model, transmissions, arm_id, Params(_param(mg_ns, {}), mg_ns), warn=warn,
                     world=plugin.context.world)
    publisher = plugin.context.advertise(join(ns, "initialized"), Bool, queue_size=1, latch=True)
    publisher.publish(Bool(data=False))
    hw.on_initialized = lambda: publisher.publish(Bool(data=True))
    rospy.loginfo("model '%s': FrankaHWSim for arm '%s': %d arm joints, gravity compensated on %d links"
                  % (model.name, arm_id, len(hw.arm), len(hw.gravity_free_links)))
    return hw


# ---- FrankaStateController ---------------------------------------------------------------------
class FrankaStateAdapter(Adapter):
    def __init__(self, plugin, controller):
        super(FrankaStateAdapter, self).__init__(plugin, controller)
        self.joint_states = rospy.Publisher(self.ns + "/joint_states", JointState, queue_size=1)
        self.desired = rospy.Publisher(self.ns + "/joint_states_desired", JointState, queue_size=1)
        self.states = rospy.Publisher(self.ns + "/franka_states", FrankaState, queue_size=1)
        self.tf = rospy.Publisher("/tf", TFMessage, queue_size=10)
        self.handles += [self.joint_states, self.desired, self.states, self.tf]
        arm = controller.arm_id
        hand = (arm + "_hand") in plugin.hw.model.links
        ns = plugin.namespace
        self.F_T_NE = self._matrix(join(ns, "F_T_NE"), F_T_NE_HAND if hand else IDENTITY)
        self.NE_T_EE = self._matrix(join(ns, "NE_T_EE"), IDENTITY)
        self.EE_T_K = self._matrix(join(ns, "EE_T_K"), IDENTITY)
        self.frames = [(arm + "_link8", arm + "_NE", self.F_T_NE), (arm + "_NE", arm + "_EE", self.NE_T_EE),
                       (arm + "_EE", arm + "_K", self.EE_T_K)]

    @staticmethod
    def _matrix(name, default):
        text = _param(name)
        if text is None:
            return list(default)
        values = [float(v) for v in str(text).split()]
        if len(values) != 16:
            rospy.logwarn("%s must be 16 numbers (a column-major 4x4 transform); using the default" % name)
            return list(default)
        return values

    def after_update(self, t):
        data, self.c.pending = self.c.pending, None
        if data is None:
            return
        stamp = _stamp(data["t"])
        self.joint_states.publish(JointState(header=_header(stamp), name=data["names"], position=data["q"],
                                             velocity=data["dq"], effort=data["tau_J"]))
        self.desired.publish(JointState(header=_header(stamp), name=data["names"], position=data["q_d"],
                                        velocity=data["dq_d"], effort=[0.0] * 7))
        msg = FrankaState(q=data["q"], dq=data["dq"], tau_J=data["tau_J"], q_d=data["q_d"], dq_d=data["dq_d"],
                          theta=data["q"], dtheta=data["dq"], robot_mode=data["robot_mode"], time=data["t"],
                          F_T_NE=self.F_T_NE, NE_T_EE=self.NE_T_EE, EE_T_K=self.EE_T_K,
                          control_command_success_rate=1.0)
        msg.header.stamp = stamp
        self.states.publish(msg)
        self.tf.publish(TFMessage([_transform(stamp, parent, child, m) for parent, child, m in self.frames]))


def _header(stamp):
    h = JointState().header
    h.stamp = stamp
    return h


def _transform(stamp, parent, child, m):
    """A TransformStamped from a column-major 4x4 rotation+translation."""
    ts = TransformStamped()
    ts.header.stamp, ts.header.frame_id, ts.child_frame_id = stamp, parent, child
    ts.transform.translation.x, ts.transform.translation.y, ts.transform.translation.z = m[12], m[13], m[14]
    q = quat_from_matrix(((m[0], m[4], m[8]), (m[1], m[5], m[9]), (m[2], m[6], m[10])))
    ts.transform.rotation.x, ts.transform.rotation.y, ts.transform.rotation.z, ts.transform.rotation.w = q
    return ts


# ---- FrankaGripperSim --------------------------------------------------------------------------
class FrankaGripperAdapter(Adapter):
    """The gripper's actions (simple action servers: one goal at a time per action, as
    franka_gazebo's) and its joint states."""

    def __init__(self, plugin, controller):
        super(FrankaGripperAdapter, self).__init__(plugin, controller)
        self.pub = rospy.Publisher(self.ns + "/joint_states", JointState, queue_size=1)
        self.handles.append(self.pub)
        controller.on_change = self.wake        # a command, stop or release: the next update at once
        self.servers = []
        actions = (("move", MoveAction, self._move), ("grasp", GraspAction, self._grasp),
                   ("homing", HomingAction, self._homing), ("stop", StopAction, self._stop),
                   ("gripper_action", GripperCommandAction, self._gripper_action))
        for name, action, execute in actions:
            server = actionlib.SimpleActionServer(self.ns + "/" + name, action, execute_cb=execute,
                                                  auto_start=False)
            server.start()
            _status_in_sim_time(types.SimpleNamespace(server=server.action_server, plugin=plugin,
                                                      handles=self.handles))
            self.servers.append(server)

    def action_servers(self):
        return self.servers

    def shutdown(self):
        self.c.stop()
        super(FrankaGripperAdapter, self).shutdown()

    def after_update(self, t):
        data, self.c.pending = self.c.pending, None
        if data is not None:
            stamp, names, pos, vel, eff = data
            self.pub.publish(JointState(header=_header(_stamp(stamp)), name=names, position=pos, velocity=vel,
                                        effort=eff))

    def _run(self, server, state, width, speed, force=0.0, inner=None, outer=None):
        """Start a motion and wait (in this action thread) until the simulation ends it."""
        req = self.c.command(state, width, speed, force, inner, outer)
        while not req.done.wait(0.1):
            if rospy.is_shutdown():
                self.c.stop()
                return None
            if server.is_preempt_requested():
                self.c.stop()
                req.done.wait(1.0)
                return None
        return req

    def _fail(self, server, result, text):
        result.success = False
        result.error = text
        rospy.logwarn("%s: %s" % (server.action_server.ns, text))
        server.set_aborted(result, text)

    def _move(self, goal):
        server = self.servers[0]
        if goal.speed < 0:
            return self._fail(server, MoveResult(), "Only positive speeds allowed")
        if not (0.0 <= goal.width <= MAX_WIDTH):
            return self._fail(server, MoveResult(), "Target width has to lie between 0 .. %g" % MAX_WIDTH)
        try:
            req = self._run(server, MOVING, goal.width, goal.speed)
        except InputError as exc:
            return self._fail(server, MoveResult(), str(exc))
        if req is None:
            return server.set_preempted(MoveResult(success=False, error="preempted"))
        if req.interrupted:
            return self._fail(server, MoveResult(), req.interrupted)
        if not req.within():
            return self._fail(server, MoveResult(), "The gripper stopped at %.4f m, not at %.4f m (+-%g)"
                              % (req.final_width, goal.width, req.inner))
        server.set_succeeded(MoveResult(success=True))

    def _grasp(self, goal):
        server = self.servers[1]
        if not (0.0 <= goal.width < MAX_WIDTH):
            return self._fail(server, GraspResult(),
                              "Can only grasp inside finger width from [0 .. %g[" % MAX_WIDTH)
        if goal.speed < 0:
            return self._fail(server, GraspResult(), "Only positive speeds allowed")
        try:
            req = self._run(server, GRASPING, goal.width, goal.speed, goal.force, goal.epsilon.inner,
                            goal.epsilon.outer)
        except InputError as exc:
            return self._fail(server, GraspResult(), str(exc))
        if req is None:
            return server.set_preempted(GraspResult(success=False, error="preempted"))
        if req.interrupted:
            return self._fail(server, GraspResult(), req.interrupted)
        if req.final_state != HOLDING:
            return self._fail(server, GraspResult(), "Unexpected state transition: the gripper is not "
                                                     "holding as expected")
        if not req.within():
            self.c.release()
            text = ("When the gripper stopped (below %g m/s) the width between the fingers was not at %g m "
                    "(-%g m/+%g m) but at %g m" % (self.c.resting_threshold, goal.width, goal.epsilon.inner,
                                                   goal.epsilon.outer, req.final_width))
            return server.set_succeeded(GraspResult(success=False, error=text))
        server.set_succeeded(GraspResult(success=True))

    def _homing(self, goal):
        server = self.servers[2]
        for width in (0.0, MAX_WIDTH):
            req = self._run(server, MOVING, width, HOMING_SPEED)
            if req is None:
                return server.set_preempted(HomingResult(success=False, error="preempted"))
            if req.interrupted:
                return self._fail(server, HomingResult(), req.interrupted)
        server.set_succeeded(HomingResult(success=True))

    def _stop(self, goal):
        self.c.stop()
        self.servers[3].set_succeeded(StopResult(success=True))

    def _gripper_action(self, goal):
        server = self.servers[4]
        width = goal.command.position * 2.0     # one finger's position, as MoveIt sends it
        if not (0.0 <= width <= MAX_WIDTH):
            text = ("Commanding out of range position! max_position = %g, commanded position = %g. Be aware "
                    "that you command the position of each finger which is half of the total opening width!"
                    % (MAX_WIDTH / 2.0, goal.command.position))
            rospy.logerr("%s: %s" % (server.action_server.ns, text))
            return server.set_aborted(GripperCommandResult(reached_goal=False), text)
        tol = self.c.tolerance_gripper_action
        grasp = not (abs(goal.command.max_effort) < MIN_GRASP_FORCE or width > self.c.width())
        try:    # (a move does not use the force; it is passed along to be checked all the same)
            req = self._run(server, GRASPING if grasp else MOVING, width, self.c.default_speed,
                            goal.command.max_effort, tol, tol)
        except InputError as exc:
            rospy.logerr("%s: %s" % (server.action_server.ns, exc))
            return server.set_aborted(GripperCommandResult(reached_goal=False), str(exc))
        if grasp and req is not None and not req.interrupted and req.final_state != HOLDING:
            text = "Unexpected state transition: the gripper is not holding as expected"
            return server.set_aborted(GripperCommandResult(reached_goal=False), text)
        if req is None:
            return server.set_preempted(GripperCommandResult(reached_goal=False))
        if req.interrupted:
            return server.set_aborted(GripperCommandResult(reached_goal=False), req.interrupted)
        ok = req.within()
        if not ok:
            self.c.release()
        server.set_succeeded(GripperCommandResult(position=req.final_width, effort=0.0, stalled=False,
                                                  reached_goal=ok))


register_robot_sim_type(SIM_TYPE, make_hw)
register_controller_type(FrankaStateController, adapter=FrankaStateAdapter)
register_controller_type(FrankaGripperSim, adapter=FrankaGripperAdapter)
