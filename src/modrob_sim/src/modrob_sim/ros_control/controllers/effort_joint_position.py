"""effort_controllers/JointPositionController (ros_controllers, Noetic): a PID on the position
error writes an effort. Parameters: ``joint``, ``pid`` {p, i, d, i_clamp, i_clamp_min,
i_clamp_max, antiwindup}. The command is clamped to the joint limits (revolute, prismatic);
continuous joints take the shortest angular way. ``state`` (JointControllerState) is due every
10th update, as ros_controllers publishes it.

The PID runs in the joint's actuator (a POSITION_PID of the World, at every step): an update
writes the target and the gains; the state message is built from what the actuator did in the
update's step. Between updates with nothing to publish nothing of this runs in Python.

velocity_controllers/JointPositionController is the same loop writing the PID's output to the
velocity interface: the actuator's output is the joint's motor velocity (OUT_VELOCITY), as the
hardware's velocity write would apply it. On a velocity joint with the hardware's own pid_gains
PID (whose PID would take the controller's output as its target) the controller runs its PID in
Python at every update and writes the joint's command instead."""
from modrob_sim.physics import actuators
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller, check_finite
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT, VELOCITY

STATE_DECIMATION = 10
INF = float("inf")


class _PidController(Controller):
    """A single-joint PID controller whose PID is the joint's actuator (position or velocity),
    its output driving what OUTPUT says."""
    INTERFACE = EFFORT
    KIND = actuators.POSITION_PID
    OUTPUT = actuators.OUT_EFFORT

    def __init__(self, name, hw, params):
        super(_PidController, self).__init__(name, hw, params)
        joint = params.get("joint", kind=str)
        self.joint = hw.joint(joint, self.INTERFACE, controller=name)
        self.joint_names = [joint]
        #: the gains (dynamic_reconfigure swaps them); the PID's state is the actuator's
        self.pid = Pid(PidGains.from_params(params.child("pid", required=True)))
        self.pid_namespace = params.path("pid")
        self.command = CommandBuffer(self._initial())
        self.act = None
        self._gains = None
        self._start = None
        self._dt = 0.0
        #: whether a state message is wanted at all (the ROS layer: its topic has subscribers)
        self.state_wanted = lambda: True

    def _initial(self):
        return 0.0

    def _error_rule(self):
        return actuators.PLAIN

    def starting(self, t):
        self.command.write(self._initial())
        self.pid.reset()
        self.act = self.joint.actuate(self.KIND, self.pid.gains, self._error_rule(), owner=self,
                                      output=self.OUTPUT)
        self._gains = self.pid.gains
        self._start = None
        self.collect_due = False

    def stopping(self, t):
        if self.act is not None and self.joint.owner is self:
            # the hardware keeps applying the last command, as ros_control's does
            if self.joint.interface == self.INTERFACE:
                self.joint.command = self.act.last.output
            self.joint.release()
        self.act = None

    def update(self, t, dt):
        a = self.act
        if self.pid.gains is not self._gains:
            self._gains = a.gains = self.pid.gains
        a.command = self.take_command()
        if self._start is None:
            self._start = self.hw.iteration
        # every 10th update has a state message, as ros_controllers'; with nobody listening it is
        # not collected (which would make the World stop after the update's step for nothing)
        if (self.hw.iteration - self._start) % STATE_DECIMATION == 0 and self.state_wanted():
            self.collect_due = True
            self._dt = dt

    def update_due(self, t, iteration, dt):
        if self.pid.gains is not self._gains or self.command_waiting() or self._start is None:
            return t
        if not self.state_wanted():
            return INF
        k = (STATE_DECIMATION - (iteration - self._start) % STATE_DECIMATION) % STATE_DECIMATION
        return t + k * dt - 0.5 * dt

    def collect(self):
        self.collect_due = False
        s = self.act.last
        g = self.pid.gains
        self.pending = self._state(s, g)


class EffortJointPositionController(_PidController):
    TYPE = "effort_controllers/JointPositionController"
    KIND = actuators.POSITION_PID

    def _initial(self):
        return self.joint.clamp_position(self.joint.position)

    def _error_rule(self):
        return self.joint.position_rule

    def set_command(self, value):
        value, bad = check_finite(value, "position command for joint '%s'" % self.joint.name)
        if bad:
            return bad
        j = self.joint
        if j.has_position_limits and not (j.lower <= value <= j.upper):
            clamped = j.clamp_position(value)
            self.command.write(clamped)
            return CommandResult(True, clamped, clamped_from=value,
                                 reason="outside the limits [%g, %g] of joint '%s'" % (j.lower, j.upper,
                                                                                       j.name))
        self.command.write(value)
        return CommandResult(True, value)

    def _state(self, s, g):
        return dict(stamp=s.t, set_point=s.set_point, process_value=s.position, process_value_dot=s.velocity,
                    error=s.error, time_step=self._dt, command=s.output, p=g.p, i=g.i, d=g.d,
                    i_clamp=g.i_max, antiwindup=g.antiwindup)


class VelocityJointPositionController(EffortJointPositionController):
    """The PID's output is the velocity joint's motor velocity (an OUT_VELOCITY actuator), or,
    where the joint cannot take one, a velocity command computed here at every update."""
    TYPE = "velocity_controllers/JointPositionController"
    INTERFACE = VELOCITY
    OUTPUT = actuators.OUT_VELOCITY

    def starting(self, t):
        if self.joint.can_drive(self.OUTPUT):
            super(VelocityJointPositionController, self).starting(t)
            return
        self.command.write(self._initial())
        self.pid.reset()
        self.act = None
        self._count = 0

    def update_due(self, t, iteration, dt):
        if self.act is None:
            return t
        return super(VelocityJointPositionController, self).update_due(t, iteration, dt)

    def update(self, t, dt):
        if self.act is not None:
            super(VelocityJointPositionController, self).update(t, dt)
            return
        target = self.command.read()
        error = self.joint.position_error(target)
        command = self.pid.compute(error, dt)
        self.joint.command = command
        if self._count % STATE_DECIMATION == 0:
            g = self.pid.gains
            self.pending = dict(stamp=t, set_point=target, process_value=self.joint.position,
                                process_value_dot=self.joint.velocity, error=error, time_step=dt,
                                command=command, p=g.p, i=g.i, d=g.d, i_clamp=g.i_max,
                                antiwindup=g.antiwindup)
        self._count += 1
