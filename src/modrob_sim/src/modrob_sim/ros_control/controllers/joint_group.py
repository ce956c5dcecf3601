"""ros_controllers' joint group controllers (Noetic): one ``command`` (std_msgs/Float64MultiArray,
one value per joint in the order of the ``joints`` parameter) for several joints.

* position_controllers/JointGroupPositionController -- PositionJointInterface; starts holding the
  current positions
* velocity_controllers/JointGroupVelocityController -- VelocityJointInterface; starts at 0
* effort_controllers/JointGroupEffortController -- EffortJointInterface; starts at 0
  (forward_command_controller's ForwardJointGroupCommandController: values go to the command
  interfaces unchanged, what then happens is the hardware's business)
* effort_controllers/JointGroupPositionController -- EffortJointInterface: a PID per joint
  (``<joint>/pid``) on the position error writes an effort; starts holding the current positions
  (clamped to the joint limits). The PIDs are the joints' actuators (POSITION_PID, run by the
  World at every step); an update writes the targets and the gains when they change.

A command whose length is not the number of joints is refused (nothing changes), as
ros_controllers refuses it; a NaN or infinite value refuses the whole command; values beyond a
joint's limits are clamped, and the result says so.
"""
from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller, check_finite
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT, POSITION, VELOCITY

INF = float("inf")


class JointGroupControllerBase(Controller):
    #: what each value is ("position", "velocity", "effort"): for the messages and the limits
    QUANTITY = ""

    def __init__(self, name, hw, params):
        super(JointGroupControllerBase, self).__init__(name, hw, params)
        joints = params.get("joints", kind=list)
        if not joints:
            raise ControllerError("Parameter %s is empty: list the joints this group controller drives"
                                  % params.path("joints"))
        if len(set(joints)) != len(joints):
            raise ControllerError("Parameter %s names a joint twice: %s" % (params.path("joints"), joints))
        self.joint_names = list(joints)
        self.joints = [hw.joint(j, self.INTERFACE, controller=name) for j in joints]
        self.n = len(joints)
        self.command = CommandBuffer([0.0] * self.n)

    def _initial(self):
        return [0.0] * self.n

    def set_command(self, values):
        """A Float64MultiArray's data: a CommandResult (``value`` the list stored)."""
        values = list(values)
        if len(values) != self.n:
            return CommandResult(False, reason="Dimension of command (%d) does not match number of joints "
                                               "(%d: %s)! Not executing"
                                               % (len(values), self.n, ", ".join(self.joint_names)))
        out, clamped = [], []
        for j, v in zip(self.joints, values):
            v, bad = check_finite(v, "%s command for joint '%s'" % (self.QUANTITY, j.name))
            if bad:
                return bad
            limited, why = self._limit(j, v)
            if why:
                clamped.append(why)
            out.append(limited)
        self.command.write(out)
        if clamped:
            return CommandResult(True, out, clamped_from=values, reason="; ".join(clamped))
        return CommandResult(True, out)

    def _limit(self, j, v):
        """(value, '' or why it was clamped)."""
        return v, ""

    def starting(self, t):
        self.command.write(self._initial())

    def update(self, t, dt):
        for j, v in zip(self.joints, self.take_command()):
            j.command = v

    def update_due(self, t, iteration, dt):
        """An update only when a new command waits: the hardware holds the last ones."""
        return t if self.command_waiting() else INF


def _clamp_position(j, v):
    if j.has_position_limits and not (j.lower <= v <= j.upper):
        return j.clamp_position(v), ("%g is outside the limits [%g, %g] of joint '%s'"
                                     % (v, j.lower, j.upper, j.name))
    return v, ""


def _clamp_symmetric(v, lim, what, j):
    if lim is not None and abs(v) > lim:
        return max(-lim, min(lim, v)), "%g is beyond the %s limit %g of joint '%s'" % (v, what, lim, j.name)
    return v, ""


class PositionJointGroupPositionController(JointGroupControllerBase):
    TYPE = "position_controllers/JointGroupPositionController"
    INTERFACE = POSITION
    QUANTITY = "position"

    def _initial(self):
        return [j.position for j in self.joints]

    def _limit(self, j, v):
        return _clamp_position(j, v)


class VelocityJointGroupVelocityController(JointGroupControllerBase):
    TYPE = "velocity_controllers/JointGroupVelocityController"
    INTERFACE = VELOCITY
    QUANTITY = "velocity"

    def _limit(self, j, v):
        return _clamp_symmetric(v, j.velocity_limit, "velocity", j)


class EffortJointGroupEffortController(JointGroupControllerBase):
    TYPE = "effort_controllers/JointGroupEffortController"
    INTERFACE = EFFORT
    QUANTITY = "effort"

    def _limit(self, j, v):
        return _clamp_symmetric(v, j.effort_limit, "effort", j)


class EffortJointGroupPositionController(JointGroupControllerBase):
    TYPE = "effort_controllers/JointGroupPositionController"
    INTERFACE = EFFORT
    QUANTITY = "position"

    def __init__(self, name, hw, params):
        super(EffortJointGroupPositionController, self).__init__(name, hw, params)
        #: the gains per joint (dynamic_reconfigure swaps them); the PIDs' state is the actuators'
        self.pids = [Pid(PidGains.from_params(params.child(j).child("pid", required=True)))
                     for j in self.joint_names]
        self.pid_namespaces = [params.path(j, "pid") for j in self.joint_names]
        self.acts = []
        self._gains = []

    def _initial(self):
        return [j.clamp_position(j.position) for j in self.joints]

    def _limit(self, j, v):
        return _clamp_position(j, v)

    def starting(self, t):
        super(EffortJointGroupPositionController, self).starting(t)
        for pid in self.pids:
            pid.reset()
        # each joint's PID is its actuator's (the World runs it at every step, between updates too)
        self.acts = [j.actuate(actuators.POSITION_PID, pid.gains, j.position_rule, owner=self)
                     for j, pid in zip(self.joints, self.pids)]
        self._gains = [pid.gains for pid in self.pids]

    def stopping(self, t):
        for j, a in zip(self.joints, self.acts):
            if j.owner is self:
                # the hardware keeps applying the last effort, as ros_control's does
                j.command = a.last.output
                j.release()
        self.acts = []

    def update(self, t, dt):
        for k, (a, pid) in enumerate(zip(self.acts, self.pids)):
            if pid.gains is not self._gains[k]:
                self._gains[k] = a.gains = pid.gains
        for a, target in zip(self.acts, self.take_command()):
            a.command = target

    def update_due(self, t, iteration, dt):
        """An update when a command or new gains wait; the actuators hold the targets."""
        if self.command_waiting() or any(p.gains is not g for p, g in zip(self.pids, self._gains)):
            return t
        return INF
