"""forward_command_controller's single-joint controllers: the ``command`` (std_msgs/Float64) is
written to the joint's command interface unchanged. What happens then is the simulated
hardware's business (gazebo_ros_control: PID from ``pid_gains`` or kinematic/motor).

* effort_controllers/JointEffortController  -- EffortJointInterface, starts at 0
* position_controllers/JointPositionController -- PositionJointInterface, starts holding the
  current position (ros_controllers' specialisation)
* velocity_controllers/JointVelocityController -- VelocityJointInterface, starts at 0
"""
from modrob_sim.ros_control.controllers.base import CommandBuffer, CommandResult, Controller, check_finite
from modrob_sim.ros_control.transmissions import EFFORT, POSITION, VELOCITY


class _ForwardCommandController(Controller):
    def __init__(self, name, hw, params):
        super(_ForwardCommandController, self).__init__(name, hw, params)
        joint = params.get("joint", kind=str)
        self.joint = hw.joint(joint, self.INTERFACE, controller=name)
        self.joint_names = [joint]
        self.command = CommandBuffer(self._initial())

    def _initial(self):
        return 0.0

    def set_command(self, value):
        value, bad = check_finite(value, "command for joint '%s'" % self.joint.name)
        if bad:
            return bad
        return self._store(value)

    def _store(self, value):
        self.command.write(value)
        return CommandResult(True, value)

    def starting(self, t):
        self.command.write(self._initial())

    def update(self, t, dt):
        self.joint.command = self.take_command()

    def update_due(self, t, iteration, dt):
        """An update only when a new command waits: the hardware holds the last one."""
        return t if self.command_waiting() else float("inf")


class EffortJointEffortController(_ForwardCommandController):
    TYPE = "effort_controllers/JointEffortController"
    INTERFACE = EFFORT

    def _store(self, value):
        lim = self.joint.effort_limit
        if lim is not None and abs(value) > lim:
            clamped = max(-lim, min(lim, value))
            self.command.write(clamped)
            return CommandResult(True, clamped, clamped_from=value,
                                 reason="beyond the effort limit %g of joint '%s'" % (lim, self.joint.name))
        return super(EffortJointEffortController, self)._store(value)


class PositionJointPositionController(_ForwardCommandController):
    TYPE = "position_controllers/JointPositionController"
    INTERFACE = POSITION

    def _initial(self):
        return self.joint.position

    def _store(self, value):
        j = self.joint
        if j.has_position_limits and not (j.lower <= value <= j.upper):
            clamped = j.clamp_position(value)
            self.command.write(clamped)
            return CommandResult(True, clamped, clamped_from=value,
                                 reason="outside the limits [%g, %g] of joint '%s'" % (j.lower, j.upper,
                                                                                       j.name))
        return super(PositionJointPositionController, self)._store(value)


class VelocityJointVelocityController(_ForwardCommandController):
    TYPE = "velocity_controllers/JointVelocityController"
    INTERFACE = VELOCITY

    def _store(self, value):
        lim = self.joint.velocity_limit
        if lim is not None and abs(value) > lim:
            clamped = max(-lim, min(lim, value))
            self.command.write(clamped)
            return CommandResult(True, clamped, clamped_from=value,
                                 reason="beyond the velocity limit %g of joint '%s'" % (lim, self.joint.name))
        return super(VelocityJointVelocityController, self)._store(value)
