"""gazebo_ros_skid_steer_drive (libgazebo_ros_skid_steer_drive.so) without ROS: four wheel joints
driven by ODE joint motors (target velocity, at most ``torque``), the two of a side at the same
rim speed; a turn drags the wheels sideways, as on the real robot. Odometry from the world.

Parameters (defaults as gazebo_plugins'): leftFrontJoint left_front_joint, rightFrontJoint
right_front_joint, leftRearJoint left_rear_joint, rightRearJoint right_rear_joint,
wheelSeparation 0.4, wheelDiameter 0.15, torque 5, updateRate 100 Hz (0 = every step),
commandTopic cmd_vel, odometryTopic odom, odometryFrame odom, robotBaseFrame base_footprint,
broadcastTF false, covariance_x 0.0001, covariance_y 0.0001, covariance_yaw 0.01.

As Noetic's plugin (Gazebo > 2: the joints' "vel" and "fmax" parameters), the motors alone turn
the wheels, so that a blocked robot's wheels are held by their torque.
"""
from modrob_sim.gazebo_ros.plugin_base import RateGate

from .common import Odom, check_values, wheel_joint, world_odometry

WHEELS = (("leftFrontJoint", "left_front_joint", -1), ("rightFrontJoint", "right_front_joint", 1),
          ("leftRearJoint", "left_rear_joint", -1), ("rightRearJoint", "right_rear_joint", 1))


class SkidSteerConfig(object):
    def __init__(self, plugin):
        p = plugin.param
        self.command_topic = p("commandTopic", "cmd_vel")
        self.odometry_topic = p("odometryTopic", "odom")
        self.odometry_frame = p("odometryFrame", "odom")
        self.robot_base_frame = p("robotBaseFrame", "base_footprint")
        self.broadcast_tf = p("broadcastTF", False, bool)
        self.wheel_separation = p("wheelSeparation", 0.4, float)
        self.wheel_diameter = p("wheelDiameter", 0.15, float)
        self.torque = p("torque", 5.0, float)
        self.update_rate = p("updateRate", 100.0, float)
        self.covariance = (p("covariance_x", 0.0001, float), p("covariance_y", 0.0001, float),
                           p("covariance_yaw", 0.01, float))
        self.odometry_source = "world"
        check_values(plugin,
                     positive=((self.wheel_separation, "wheelSeparation"),
                               (self.wheel_diameter, "wheelDiameter")),
                     nonnegative=((self.torque, "torque"), (self.update_rate, "updateRate")))


class SkidSteer(object):
    def __init__(self, plugin):
        self.cfg = SkidSteerConfig(plugin)
        self.model = plugin.model
        self.joints = [wheel_joint(plugin, tag, default) for tag, default, _side in WHEELS]
        self.sides = [side for _tag, _default, side in WHEELS]
        self.radius = 0.5 * self.cfg.wheel_diameter
        self.gate = RateGate(self.cfg.update_rate)
        self.reset()

    def reset(self):
        self.gate.reset()
        for j in self.joints:
            j.set_velocity_target(0.0, self.cfg.torque)

    def update(self, t, dt, command):
        """``command`` = (linear x, angular z). Returns True when due (publish, new targets)."""
        if not self.gate.due(t):
            return False
        v, w = command
        half = 0.5 * w * self.cfg.wheel_separation
        for j, side in zip(self.joints, self.sides):
            j.set_velocity_target((v + side * half) / self.radius, self.cfg.torque)
        return True

    def next_due(self):
        """The next update (the motors hold the wheels' targets in between)."""
        return self.gate.next_time

    def odometry(self):
        """The model's pose and velocity; the position's z is left at 0 as gazebo_plugins do."""
        o = world_odometry(self.model)
        return Odom((o.position[0], o.position[1], 0.0), o.orientation, o.linear, o.angular)
