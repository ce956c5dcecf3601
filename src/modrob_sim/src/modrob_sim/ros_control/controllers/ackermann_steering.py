"""ackermann_steering_controller/AckermannSteeringController (ros_controllers, Noetic): one driven
rear wheel joint (velocity interface) and one front steering joint (position interface), a
bicycle model.

As in ros_controllers, ``cmd_vel``'s ``angular.z`` is the STEERING ANGLE (rad) written to the
steering joint, and ``linear.x`` (m/s) becomes the rear wheel's speed ``linear.x / wheel_radius``.

``rear_wheel`` ("rear_wheel_joint"), ``front_steer`` ("front_steer_joint"); ``wheel_separation_h``
(m, the wheelbase) and ``wheel_radius``: when not given, read from the model as ros_controllers
reads them from the URDF: |x of the rear wheel joint's origin - x of the steering joint's origin|,
and the radius of the rear wheel link's collision cylinder. ``wheel_separation_h_multiplier``,
``wheel_radius_multiplier``, ``steer_pos_multiplier`` (1.0) apply to the odometry. The rest
(limits, odometry topics and frames, timeout) is mobile_base's; ``angular/z`` limits apply to the
steering angle, as there.

Odometry: travel = wheel angle change * radius; heading change = travel * tan(steer) / wheelbase.
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.controllers.diff_drive import wheel_radius_of
from modrob_sim.ros_control.controllers.mobile_base import MobileBaseController, positive
from modrob_sim.ros_control.transmissions import POSITION, VELOCITY


class AckermannSteeringController(MobileBaseController):
    TYPE = "ackermann_steering_controller/AckermannSteeringController"
    INTERFACE = VELOCITY

    def __init__(self, name, hw, params):
        super(AckermannSteeringController, self).__init__(name, hw, params)
        rear = params.get("rear_wheel", "rear_wheel_joint", kind=str)
        steer = params.get("front_steer", "front_steer_joint", kind=str)
        self.rear = hw.joint(rear, VELOCITY, controller=name)
        self.steer = hw.joint(steer, POSITION, controller=name)
        self.joint_names = [rear, steer]
        self.wheelbase_multiplier = positive(params, "wheel_separation_h_multiplier", 1.0)
        self.radius_multiplier = positive(params, "wheel_radius_multiplier", 1.0)
        self.steer_multiplier = params.get("steer_pos_multiplier", 1.0, kind=float)
        if params.has("wheel_separation_h"):
            self.wheel_separation_h = positive(params, "wheel_separation_h", 1.0)
        else:
            self.wheel_separation_h = abs(self.rear.sim.origin[0][0] - self.steer.sim.origin[0][0])
            if self.wheel_separation_h <= 0.0:
                raise ControllerError("controller '%s': joints '%s' and '%s' have the same x, so the "
                                      "wheelbase read from the model is 0: set wheel_separation_h"
                                      % (name, rear, steer))
        if params.has("wheel_radius"):
            self.wheel_radius = positive(params, "wheel_radius", 1.0)
        else:
            self.wheel_radius = wheel_radius_of(self.rear, name, shapes=("cylinder",))
        self._last_wheel = None

    def interfaces(self):
        return [(VELOCITY, [self.rear.name]), (POSITION, [self.steer.name])]

    def starting(self, t):
        self._last_wheel = self.rear.position
        super(AckermannSteeringController, self).starting(t)

    def measure(self):
        wheel, steer = self.rear.position, self.steer.position
        if math.isnan(wheel) or math.isnan(steer):
            return None
        last, self._last_wheel = self._last_wheel, wheel
        if last is None:
            return 0.0, 0.0
        travel = (wheel - last) * self.wheel_radius * self.radius_multiplier
        wheelbase = self.wheel_separation_h * self.wheelbase_multiplier
        return travel, travel * math.tan(steer * self.steer_multiplier) / wheelbase

    def drive(self, linear, angular):
        # as ros_controllers: the speed over the radius without its multiplier
        self.rear.command = linear / self.wheel_radius
        self.steer.command = angular

    def _open_loop_rate(self, linear, angular):
        """Open loop: the heading rate of the bicycle for speed ``linear`` and steering angle
        ``angular`` (ros_controllers integrates the angle itself as if it were a rate)."""
        return linear * math.tan(angular) / (self.wheel_separation_h * self.wheelbase_multiplier)
