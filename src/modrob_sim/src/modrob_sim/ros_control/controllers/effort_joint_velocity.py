"""effort_controllers/JointVelocityController (ros_controllers, Noetic): a PID on the velocity
error writes an effort. Parameters ``joint`` and ``pid``; starts with command 0; ``state`` every
10th update. The PID runs in the joint's actuator (a VELOCITY_PID of the World)."""
from modrob_sim.physics import actuators
from modrob_sim.ros_control.controllers.base import CommandResult, check_finite
from modrob_sim.ros_control.controllers.effort_joint_position import STATE_DECIMATION, _PidController

__all__ = ["EffortJointVelocityController", "STATE_DECIMATION"]


class EffortJointVelocityController(_PidController):
    TYPE = "effort_controllers/JointVelocityController"
    KIND = actuators.VELOCITY_PID

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

    def _state(self, s, g):
        return dict(stamp=s.t, set_point=s.set_point, process_value=s.velocity, process_value_dot=0.0,
                    error=s.error, time_step=self._dt, command=s.output, p=g.p, i=g.i, d=g.d,
                    i_clamp=g.i_max, antiwindup=g.antiwindup)
