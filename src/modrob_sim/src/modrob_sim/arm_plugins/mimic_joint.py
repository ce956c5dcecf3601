"""roboticsgroup_gazebo_plugins' ``libroboticsgroup_gazebo_mimic_joint_plugin.so`` (and its
successor's ``libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so``, roboticsgroup_upatras_
gazebo_plugins, same parameters): one joint follows another, ``mimicJoint = multiplier * joint +
offset``.

Parameters as the original reads them: ``<joint>`` and ``<mimicJoint>`` (required), ``<multiplier>``
(1), ``<offset>`` (0), ``<sensitiveness>`` (0: an error below it is left alone), ``<maxEffort>``
(the mimic joint's effort limit), ``<hasPID>`` and ``<robotNamespace>``.

- Without ``<hasPID>`` the original sets the mimic joint's position at every step (Gazebo 9+:
  keeping the link velocities). Here the World's mimic coupling does it (``World.set_mimic``: the
  rule URDF ``<mimic>`` joints follow, a stiff constraint inside ODE's solver, run natively between
  Python hooks), so the joint follows within a fraction of a milliradian and pushes back on what it
  meets as a linkage would. ``sensitiveness`` is accepted and not needed.
- With ``<hasPID>`` it applies ``clamp(pid(target - position), +-maxEffort)`` to the mimic joint at
  every step (none, and the PID left as it is, while the error is below ``sensitiveness``), with
  control_toolbox gains read from the ROS parameters in the namespace that ``<hasPID>`` names,
  relative to the robot namespace (empty: ``gazebo_ros_control/pid_gains/<mimicJoint>``), as
  ``control_toolbox::Pid::init`` reads them, with a dynamic_reconfigure server for them in that
  namespace as that ``init`` starts (p, i, d, i_clamp_min, i_clamp_max, antiwindup; a change is
  handed to the PID at the next step). The World's actuator of the joint does it
  (physics.actuators FOLLOW_PID, ``maxEffort`` its hardware clamp), natively between Python
  hooks; the plugin has a step hook only for handing over new gains. Reset and reset_world zero
  the PID's state. A joint that already has an actuator when the plugin loads (another plugin's,
  or ros_control's for a joint with pid_gains) keeps it: the plugin then adds its PID's effort to
  that joint with set_effort at every step, in Python, as Gazebo adds the two, and says so in a
  warning. A URDF ``<mimic>`` on that joint (which Gazebo's physics ignores) is released, so that
  only the plugin's PID drives it, as on Gazebo.
"""
import logging
import math

from modrob_sim.errors import PluginError
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin
from modrob_sim.physics.actuators import FOLLOW_PID, Pid

FILENAMES = ("libroboticsgroup_gazebo_mimic_joint_plugin.so",
             "libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so")
INF = math.inf
LOG = logging.getLogger("modrob_sim.mimic_joint")


def _join(ns, name):
    if name.startswith("/"):
        return name
    ns = (ns or "").strip("/")
    return "/" + (ns + "/" if ns else "") + name


class _TunedGains(object):
    """The PID's gains as the reconfigure server sets them (a reference swap, from its thread)."""

    def __init__(self, gains):
        self.gains = gains

    def set_gains(self, gains):
        self.gains = gains


class MimicJointPlugin(ModelPlugin):
    def load(self, model, spec, context):
        self.world = context.world
        names = (self.param("joint"), self.param("mimicJoint"))
        for n in names:
            if n not in model.joints:
                raise PluginError("%s: no joint named '%s' (joints: %s)"
                                  % (self.name, n, ", ".join(model.joints)))
        if names[0] == names[1]:
            raise PluginError("%s: <joint> and <mimicJoint> are both '%s': a joint cannot mimic itself; "
                              "<joint> names the joint to follow" % (self.name, names[0]))
        self.master, self.joint = model.joints[names[0]], model.joints[names[1]]
        self.multiplier = self.param("multiplier", 1.0, float)
        self.offset = self.param("offset", 0.0, float)
        self.sensitiveness = self.param("sensitiveness", 0.0, float)
        limit = self.joint.effort_limit
        default = limit if limit and limit > 0 else INF
        self.max_effort = self.param("maxEffort", default, float)
        if not self.max_effort >= 0.0:
            # the original clamps to [-maxEffort, maxEffort], which is no range for a negative one
            fixed = abs(self.max_effort) if math.isfinite(self.max_effort) else default
            LOG.warning("%s: <maxEffort> %s must be >= 0: using %g (the joint '%s' effort limit is %s)",
                        self.name, self.max_effort, fixed, self.joint.name, limit)
            self.max_effort = fixed
        self.urdf_mimic = self.joint.mimic
        has_pid = self.element.find("hasPID")
        self.pid = None         # the PID run in Python (a joint that has another actuator)
        self.actuator = None    # the World's FOLLOW_PID actuator of the joint
        self.reconfigure = None
        if has_pid is None:
            self.world.set_mimic(self.joint, self.master, self.multiplier, self.offset)
            LOG.info("%s: joint '%s' follows '%s' (multiplier %g, offset %g), coupled by the physics",
                     self.name, self.joint.name, self.master.name, self.multiplier, self.offset)
            return
        rel = (has_pid.text or "").strip() or "gazebo_ros_control/pid_gains/" + self.joint.name
        self.gains_ns = _join(spec.robot_namespace, rel)
        gains = self.read_gains(self.gains_ns)
        if self.urdf_mimic is not None:
            self.world.set_mimic(self.joint, None)
        other = self.joint.actuator
        if other is None:
            self.actuator = self.world.add_actuator(
                self.joint, FOLLOW_PID, gains=gains,
                effort_limit=self.max_effort if math.isfinite(self.max_effort) else None)
            # (a negative or NaN sensitiveness leaves no error alone, as the original: deadband 0)
            self.actuator.follow(self.master, self.multiplier, self.offset, max(0.0, self.sensitiveness))
            self.tuned, self._synced = _TunedGains(gains), gains
        else:
            self.pid = self.tuned = Pid(gains)
            LOG.warning("%s: joint '%s' is driven by %r already: the PID's effort is added to it at every "
                        "step, in Python (as Gazebo adds the two efforts)", self.name, self.joint.name, other)
        self.reconfigure = self.serve_gains(self.gains_ns, self.tuned)
        LOG.info("%s: joint '%s' follows '%s' (multiplier %g, offset %g) by a PID (gains from %s, max "
                 "effort %g)", self.name, self.joint.name, self.master.name, self.multiplier, self.offset,
                 self.gains_ns, self.max_effort)

    def read_gains(self, ns):
        """control_toolbox gains from the ROS parameters under ``ns`` (PluginError when absent)."""
        import rospy
        from modrob_sim.ros_control.params import Params
        from modrob_sim.ros_control.pid import PidGains
        from modrob_sim.errors import ControllerError
        if not rospy.core.is_initialized():
            raise PluginError("%s: <hasPID> needs the gains in the ROS parameters under %s" % (self.name, ns))
        try:
            values = rospy.get_param(ns, {})
        except (KeyError, OSError, rospy.ROSException) as e:
            raise PluginError("%s: cannot read the PID gains under %s: %s" % (self.name, ns, e))
        try:
            return PidGains.from_params(Params(values if isinstance(values, dict) else {}, ns))
        except ControllerError as e:
            raise PluginError("%s: <hasPID>: %s" % (self.name, e))

    def serve_gains(self, ns, tuned):
        """control_toolbox's dynamic_reconfigure server for the gains at ``ns``, setting ``tuned``'s
        (None without a ROS node: read_gains needs one, so only a test gets here without it)."""
        import rospy
        from modrob_sim.ros_control.ros_pid_reconfigure import PidReconfigure
        if not rospy.core.is_initialized():
            return None
        return PidReconfigure(tuned, ns, on_change=lambda _gains: self.context.wake())

    def before_due(self):
        if self.pid is not None or (self.actuator is not None and self.tuned.gains is not self._synced):
            return -INF
        return INF

    def before_step(self, t, dt):
        if self.actuator is not None:
            gains = self.tuned.gains
            if gains is not self._synced:       # the reconfigure server's (the World's thread sets them)
                self.actuator.gains = self._synced = gains
            return
        if self.pid is None:
            return
        error = self.multiplier * self.master.position + self.offset - self.joint.position
        if abs(error) < self.sensitiveness:
            return
        effort = self.pid.compute(error, dt)
        self.joint.set_effort(max(-self.max_effort, min(self.max_effort, effort)))

    def reset(self):
        if self.pid is not None:
            self.pid.reset()
        if self.actuator is not None:
            self.actuator.reset()

    def shutdown(self):
        if self.reconfigure is not None:
            self.reconfigure.shutdown()
            self.reconfigure = None
        a, self.actuator = self.actuator, None
        if a is not None and a in self.world.actuators:     # (a removed model took it along)
            self.world.remove_actuator(a)
        # the joint's own <mimic> (or nothing) again, unless the model is gone
        if self.joint.ode_joint is None:
            return
        if self.urdf_mimic is not None:
            master = self.joint.model.joints.get(self.urdf_mimic[0])
            self.world.set_mimic(self.joint, master, self.urdf_mimic[1], self.urdf_mimic[2])
        else:
            self.world.set_mimic(self.joint, None)


for _name in FILENAMES:
    register_plugin(_name, MimicJointPlugin)
