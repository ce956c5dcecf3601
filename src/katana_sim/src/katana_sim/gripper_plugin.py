"""``libgazebo_ros_katana_gripper.so`` for the /gazebo node (the ROS layer of katana_sim.gripper).

Loaded by the simulator when a model has ``<plugin filename="libgazebo_ros_katana_gripper.so">``:
katana_sim's package.xml exports this module for that file name (``<export><modrob_sim>``), so
any launch file finds it, as Gazebo finds a plugin on its plugin path. Elements, as
katana_gazebo_plugins reads them: ``r_finger_joint``, ``l_finger_joint``, ``max_torque`` (0.5 N m),
``node_namespace`` (katana; the ``gripper_controller_state`` topic lives there).

ROS interface:
* action ``posture_action_name`` (``control_msgs/GripperCommand``), resolved through the node's
  remappings as katana_gazebo_plugins does, so katana_arm_gazebo's
  ``<remap from="posture_action_name" to="/gripper_grasp_posture_controller"/>`` puts it there;
  goal ``command.position`` = finger angle (rad, 0.30 open .. -0.44 closed), ``command.max_effort``
  = torque limit per finger (N m, <= 0: max_torque); result ``stalled: true, reached_goal: false``
  with a position above -0.43 rad means an object is held (logged as such);
* no joint states: as katana_gazebo_plugins' plugin, it leaves them to joint_state_controller (the
  finger joints have effort transmissions that no controller claims);
* ``<node_namespace>/gripper_controller_state`` (``control_msgs/JointTrajectoryControllerState``:
  desired/actual/error positions of the fingers), 25 Hz.
"""
import math
import threading

import actionlib
import rospy
from control_msgs.msg import (GripperCommandAction, GripperCommandResult, JointTrajectoryControllerState)
from std_msgs.msg import Header
from trajectory_msgs.msg import JointTrajectoryPoint

from katana_sim.errors import ConfigError
from katana_sim.gripper import GripperController
from modrob_sim.gazebo_ros.action_servers import restamp_after_reset
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.physics import actuators

FILENAME = "libgazebo_ros_katana_gripper.so"


def _text(element, tag, default):
    child = element.find(tag) if element is not None else None
    return child.text.strip() if child is not None and child.text else default


def read_config(element, model):
    """The plugin's elements -> dict; ConfigError naming the element when one is unusable."""
    cfg = {
        "r_finger_joint": _text(element, "r_finger_joint", "katana_r_finger_joint"),
        "l_finger_joint": _text(element, "l_finger_joint", "katana_l_finger_joint"),
        "node_namespace": _text(element, "node_namespace", "katana"),
    }
    raw = _text(element, "max_torque", "0.5")
    try:
        cfg["max_torque"] = float(raw)
    except ValueError:
        raise ConfigError("model '%s': <max_torque>%s</max_torque> of %s is not a number (N m)"
                          % (model.name, raw, FILENAME))
    if not (math.isfinite(cfg["max_torque"]) and cfg["max_torque"] > 0):
        raise ConfigError("model '%s': <max_torque> of %s must be > 0 N m, got %s"
                          % (model.name, FILENAME, raw))
    for key in ("r_finger_joint", "l_finger_joint"):
        if cfg[key] not in model.joints:
            raise ConfigError("model '%s' has no joint '%s' (<%s> of %s); its joints: %s"
                              % (model.name, cfg[key], key, FILENAME, ", ".join(sorted(model.joints))))
    return cfg


class KatanaGripperPlugin(ModelPlugin):
    def load(self, model, spec, context):
        cfg = read_config(spec.element, model)
        self.model_name = model.name
        self.joints = [model.joints[cfg["r_finger_joint"]], model.joints[cfg["l_finger_joint"]]]
        self.names = [j.name for j in self.joints]
        lower = max(j.lower for j in self.joints if j.lower is not None)
        upper = min(j.upper for j in self.joints if j.upper is not None)
        self.core = GripperController(max_torque=cfg["max_torque"], lower=lower, upper=upper)
        # the fingers' actuators: while the gripper holds its set-point (no goal running, the ramp
        # at its end) they carry the controller's PD natively (p (sp - q) - d dq, clamped, is a
        # PID held on a constant with the joint's velocity as the error's rate); while a goal runs
        # the update runs at every step and they apply its efforts
        gains = actuators.PidGains(self.core.p, 0.0, self.core.d)
        self.acts = [context.world.add_actuator(j, actuators.EFFORT, gains=gains) for j in self.joints]
        self.lock = threading.Lock()
        self._done = threading.Condition(self.lock)
        self._next_state = 0.0
        # the node's publisher (roscpp's transport): a rospy publish from the loop thread hands
        # the GIL to rospy's writer thread and waits to get it back
        ns = cfg["node_namespace"].strip("/")
        self._state_pub = context.advertise(("/%s/" % ns if ns else "/") + "gripper_controller_state",
                                            JointTrajectoryControllerState, queue_size=1)
        self.action_name = rospy.resolve_name("posture_action_name")
        self.server = actionlib.SimpleActionServer(self.action_name, GripperCommandAction,
                                                   execute_cb=self._execute, auto_start=False)
        self.server.start()
        rospy.loginfo("model '%s': katana gripper on %s (GripperCommand; fingers %s, max torque %.2f N m)"
                      % (model.name, self.action_name, ", ".join(self.names), cfg["max_torque"]))

    # -- simulation loop -------------------------------------------------------------------
    def _holds(self):
        """True while the fingers hold a set-point (nothing pending, running or ramping)."""
        c = self.core
        return c.setpoint is not None and not c.active and c._pending is None and c.setpoint == c.goal

    def before_due(self):
        with self.lock:
            if not self._holds():
                return None
        return self._next_state

    def before_step(self, t, dt):
        positions = [j.position for j in self.joints]
        velocities = [j.velocity for j in self.joints]
        with self.lock:
            was_active = self.core.active or self.core._pending is not None
            efforts = self.core.update(t, dt, positions, velocities)
            if was_active and not self.core.active:
                self._done.notify_all()
            setpoint = self.core.setpoint
            holds = self._holds()
            limit = self.core.effort_limit
        for a, effort in zip(self.acts, efforts):
            if holds:       # the same effort, from the actuator, at this step and the next ones
                if a.kind != actuators.SEGMENT_PID:
                    a.kind = actuators.SEGMENT_PID
                a.hold(setpoint)
                a.effort_limit = limit
            else:
                if a.kind != actuators.EFFORT:
                    a.kind = actuators.EFFORT
                a.effort_limit = None
                a.command = effort
        if t >= self._next_state:
            self._next_state = t + 0.04
            msg = JointTrajectoryControllerState(joint_names=self.names,
                                                 header=_header(rospy.Time.from_sec(t)))
            msg.desired = JointTrajectoryPoint(positions=[setpoint, setpoint])
            msg.actual = JointTrajectoryPoint(positions=positions, velocities=velocities)
            msg.error = JointTrajectoryPoint(positions=[setpoint - q for q in positions])
            self._state_pub.publish(msg)

    def reset(self):
        with self.lock:
            self.core.cancel(0.0)
            self.core.setpoint = None
            self._next_state = 0.0
            self._done.notify_all()
        restamp_after_reset(self.server, self.context.world.time)

    def shutdown(self):
        with self.lock:
            self.core.cancel(0.0)
            self._done.notify_all()
        self._state_pub.unregister()
        # actionlib has no clean way to stop a SimpleActionServer; its topics go with the node

    # -- action (actionlib's thread) ---------------------------------------------------------
    def _execute(self, goal):
        with self.lock:
            ok, text = self.core.command(goal.command.position, goal.command.max_effort)
        self.context.wake()         # the goal starts at the next step
        if not ok:
            rospy.logerr("%s: goal refused: %s" % (self.action_name, text))
            self.server.set_aborted(GripperCommandResult(), text)
            return
        if text:
            rospy.logwarn("%s: %s" % (self.action_name, text))
        with self.lock:
            while not rospy.is_shutdown():
                if self.core._pending is None and not self.core.active:
                    break
                if self.server.is_preempt_requested():
                    self.core.cancel(0.0)
                    self.context.wake()
                    break
                self._done.wait(0.05)
            res = self.core.result
        if res is None:
            self.server.set_aborted(GripperCommandResult(), "the simulator stopped")
            return
        msg = GripperCommandResult(position=res.position, effort=res.effort, stalled=res.stalled,
                                   reached_goal=res.reached_goal)
        note = res.text + ("; holding an object" if res.holding else "")
        if res.text == "cancelled":
            self.server.set_preempted(msg, note)
        elif res.reached_goal or res.stalled:
            rospy.loginfo("%s: %s" % (self.action_name, note))
            self.server.set_succeeded(msg, note)
        else:
            rospy.logwarn("%s: %s" % (self.action_name, note))
            self.server.set_aborted(msg, note)


def _header(stamp):
    return Header(stamp=stamp)


register_plugin(FILENAME, KatanaGripperPlugin)
