"""gazebo_ros_tricycle_drive (libgazebo_ros_tricycle_drive.so) without ROS: one steered and driven
front wheel, two free rear wheels that carry the encoders. ``cmd_vel``'s linear.x is the speed
of the driven wheel's rim, its angular.z the steering ANGLE (rad, within +-pi/2). The driven
wheel and the steering joint are turned by ODE joint motors (at most ``wheelTorque``).

Parameters (defaults as gazebo_plugins'): steeringJoint front_steering_joint, actuatedWheelJoint
front_wheel_joint, encoderWheelLeftJoint left_wheel_joint, encoderWheelRightJoint
right_wheel_joint, actuatedWheelDiameter 0.15, encoderWheelDiameter 0.15, encoderWheelSeparation
0.5, wheelTorque 5, wheelAcceleration 0 and wheelDeceleration (= wheelAcceleration; rad/s^2 of
the driven wheel, 0 = no limit), wheelSpeedTolerance 0.01, steeringSpeed 0 (rad/s; 0 = reach the
angle within one update), steeringAngleTolerance 0.01, updateRate 100, odometrySource world (or
encoder), commandTopic cmd_vel, odometryTopic odom, odometryFrame odom, robotBaseFrame base_link,
publishWheelTF, publishWheelJointState (false).
"""
import math

from modrob_sim.gazebo_ros.plugin_base import RateGate

from .common import EncoderOdometry, check_values, odometry_source, wheel_joint, world_odometry


class TricycleConfig(object):
    def __init__(self, plugin):
        p = plugin.param
        self.command_topic = p("commandTopic", "cmd_vel")
        self.odometry_topic = p("odometryTopic", "odom")
        self.odometry_frame = p("odometryFrame", "odom")
        self.robot_base_frame = p("robotBaseFrame", "base_link")
        self.actuated_diameter = p("actuatedWheelDiameter", 0.15, float)
        self.encoder_diameter = p("encoderWheelDiameter", 0.15, float)
        self.encoder_separation = p("encoderWheelSeparation", 0.5, float)
        self.wheel_torque = p("wheelTorque", 5.0, float)
        self.update_rate = p("updateRate", 100.0, float)
        self.acceleration = p("wheelAcceleration", 0.0, float)
        self.deceleration = p("wheelDeceleration", self.acceleration, float)
        self.speed_tolerance = p("wheelSpeedTolerance", 0.01, float)
        self.steering_speed = p("steeringSpeed", 0.0, float)
        self.angle_tolerance = p("steeringAngleTolerance", 0.01, float)
        self.publish_wheel_tf = p("publishWheelTF", False, bool)
        self.publish_wheel_joint_state = p("publishWheelJointState", False, bool)
        self.odometry_source = odometry_source(plugin)
        check_values(plugin,
                     positive=((self.actuated_diameter, "actuatedWheelDiameter"),
                               (self.encoder_diameter, "encoderWheelDiameter"),
                               (self.encoder_separation, "encoderWheelSeparation")),
                     nonnegative=((self.wheel_torque, "wheelTorque"), (self.update_rate, "updateRate"),
                                  (self.acceleration, "wheelAcceleration"),
                                  (self.deceleration, "wheelDeceleration"),
                                  (self.steering_speed, "steeringSpeed")))


class Tricycle(object):
    def __init__(self, plugin):
        self.cfg = cfg = TricycleConfig(plugin)
        self.model = plugin.model
        self.steering = wheel_joint(plugin, "steeringJoint", "front_steering_joint")
        self.actuated = wheel_joint(plugin, "actuatedWheelJoint", "front_wheel_joint")
        self.left = wheel_joint(plugin, "encoderWheelLeftJoint", "left_wheel_joint")
        self.right = wheel_joint(plugin, "encoderWheelRightJoint", "right_wheel_joint")
        self.joints = [self.steering, self.actuated, self.left, self.right]
        self.gate = RateGate(cfg.update_rate)
        self.encoder = EncoderOdometry(0.5 * cfg.encoder_diameter, cfg.encoder_separation)
        self.reset()

    def reset(self):
        self.gate.reset()
        self.encoder.reset()
        self.last_update = None
        self.actuated.set_velocity_target(0.0, self.cfg.wheel_torque)
        self.steering.set_velocity_target(0.0, self.cfg.wheel_torque)

    def update(self, t, dt, command):
        """``command`` = (rim speed, steering angle). Returns True when due."""
        cfg = self.cfg
        if cfg.odometry_source == "encoder":
            self.encoder.update(self.left, self.right)
        if not self.gate.due(t):
            return False
        since = t - self.last_update if self.last_update is not None else (self.gate.period or dt)
        self.last_update = t
        speed, angle = command
        target = speed / (0.5 * cfg.actuated_diameter)
        current = self.actuated.velocity
        applied = target
        if cfg.acceleration > 0:
            diff = current - target
            if abs(diff) < cfg.speed_tolerance:
                applied = current
            elif abs(diff) > cfg.acceleration * since:
                applied = (current - cfg.acceleration * since) if diff > 0 else \
                    (current + cfg.deceleration * since)
        self.actuated.set_velocity_target(applied, cfg.wheel_torque)
        angle = max(-0.5 * math.pi, min(0.5 * math.pi, angle))
        error = angle - self.steering.position
        if abs(error) < cfg.angle_tolerance:
            rate = 0.0
        elif cfg.steering_speed > 0:
            rate = math.copysign(cfg.steering_speed, error)
        else:
            rate = error / max(since, dt)       # there within one update, as far as the torque allows
        self.steering.set_velocity_target(rate, cfg.wheel_torque)
        return True

    def next_due(self):
        """The next update (the motors hold the targets, the encoders' travel adds up)."""
        return self.gate.next_time

    def odometry(self):
        if self.cfg.odometry_source == "encoder":
            return self.encoder.reading()
        return world_odometry(self.model)

    def wheel_states(self):
        """[(name, position, velocity)] of steering, driven and encoder wheels."""
        return [(j.name, j.position, j.velocity) for j in self.joints]
