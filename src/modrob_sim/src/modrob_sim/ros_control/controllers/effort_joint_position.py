"""effort_controllers/JointPositionController (ros_controllers, Noetic): a PID on the position
error writes an effort. Parameters: ``joint``, ``pid`` {p, i, d, i_clamp, i_clamp_min,
i_clamp_max, antiwindup}. The command is clamped to the joint limits (revolute, prismatic);
continuous joints take the shortest angular way. ``state`` (JointControllerState) is due every
10th update, as ros_controllers publishes it.

velocity_controllers/JointPositionController is the same loop writing the PID's output to the
velocity interface (a velocity command)."""
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller, check_finite
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT, VELOCITY

STATE_DECIMATION = 10


class EffortJointPositionController(Controller):
    TYPE = "effort_controllers/JointPositionController"
    INTERFACE = EFFORT

    def __init__(self, name, hw, params):
        super(EffortJointPositionController, self).__init__(name, hw, params)
        joint = params.get("joint", kind=str)
        self.joint = hw.joint(joint, self.INTERFACE, controller=name)
        self.joint_names = [joint]
        self.pid = Pid(PidGains.from_params(params.child("pid", required=True)))
        self.pid_namespace = params.path("pid")
        self.command = CommandBuffer(self.joint.position)
        self._count = 0
        self.last_effort = 0.0

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

    def starting(self, t):
        self.command.write(self.joint.clamp_position(self.joint.position))
        self.pid.reset()
        self._count = 0

    def update(self, t, dt):
        target = self.command.read()
        error = self.joint.position_error(target)
        effort = self.pid.compute(error, dt)
        self.joint.command = effort
        self.last_effort = effort
        if self._count % STATE_DECIMATION == 0:
            g = self.pid.gains
            self.pending = dict(stamp=t, set_point=target, process_value=self.joint.position,
                                process_value_dot=self.joint.velocity, error=error, time_step=dt,
                                command=effort, p=g.p, i=g.i, d=g.d, i_clamp=g.i_max,
                                antiwindup=g.antiwindup)
        self._count += 1


class VelocityJointPositionController(EffortJointPositionController):
    TYPE = "velocity_controllers/JointPositionController"
    INTERFACE = VELOCITY
