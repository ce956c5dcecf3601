"""effort_controllers/JointVelocityController (ros_controllers, Noetic): a PID on the velocity
error writes an effort. Parameters ``joint`` and ``pid``; starts with command 0; ``state`` every
10th update."""
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller, check_finite
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT

STATE_DECIMATION = 10


class EffortJointVelocityController(Controller):
    TYPE = "effort_controllers/JointVelocityController"
    INTERFACE = EFFORT

    def __init__(self, name, hw, params):
        super(EffortJointVelocityController, self).__init__(name, hw, params)
        joint = params.get("joint", kind=str)
        self.joint = hw.joint(joint, EFFORT, controller=name)
        self.joint_names = [joint]
        self.pid = Pid(PidGains.from_params(params.child("pid", required=True)))
        self.pid_namespace = params.path("pid")
        self.command = CommandBuffer(0.0)
        self._count = 0

    def set_command(self, value):
        value, bad = check_finite(value, "velocity command for joint '%s'" % self.joint.name)
        if bad:
            return bad
        lim = self.joint.velocity_limit
        if lim is not None and abs(value) > lim:
            clamped = max(-lim, min(lim, value))
            self.command.write(clamped)
            return CommandResult(True, clamped, clamped_from=value,
                                 reason="beyond the velocity limit %g of joint '%s'" % (lim, self.joint.name))
        self.command.write(value)
        return CommandResult(True, value)

    def starting(self, t):
        self.command.write(0.0)
        self.pid.reset()
        self._count = 0

    def update(self, t, dt):
        target = self.command.read()
        error = target - self.joint.velocity
        effort = self.pid.compute(error, dt)
        self.joint.command = effort
        if self._count % STATE_DECIMATION == 0:
            g = self.pid.gains
            self.pending = dict(stamp=t, set_point=target, process_value=self.joint.velocity,
                                process_value_dot=0.0, error=error, time_step=dt, command=effort,
                                p=g.p, i=g.i, d=g.d, i_clamp=g.i_max, antiwindup=g.antiwindup)
        self._count += 1
