"""gazebo_ros_diff_drive (Noetic's libgazebo_ros_diff_drive.so) without ROS: two wheel joints
driven through the physics by ODE joint motors (target velocity, at most ``wheelTorque``), so
that slip, slopes and obstacles act on the wheels; odometry from the world or the wheel
encoders. The ROS side (topics, tf) is ``modrob_sim.drives.ros_plugins``.

Parameters (the ``<plugin>`` children; defaults as gazebo_plugins'):

    leftJoint left_joint, rightJoint right_joint, wheelSeparation 0.34, wheelDiameter 0.15,
    wheelTorque 5, wheelAcceleration 0 (m/s^2 at the rim; 0 = no limit), updateRate 100 Hz
    (0 = every step), odometrySource world (or encoder), commandTopic cmd_vel, odometryTopic
    odom, odometryFrame odom, robotBaseFrame base_footprint, publishTf true (the odometry
    message), publishOdomTF true, publishWheelTF false, publishWheelJointState false;
    legacyMode and rosDebugLevel are accepted (Noetic's plugin reads neither).
"""
from modrob_sim.gazebo_ros.plugin_base import RateGate

from .common import EncoderOdometry, check_values, odometry_source, wheel_joint, world_odometry

LEFT, RIGHT = 0, 1


class DiffDriveConfig(object):
    """The plugin's parameters, read through ``plugin.param`` (errors name the model and tag)."""

    def __init__(self, plugin):
        p = plugin.param
        self.command_topic = p("commandTopic", "cmd_vel")
        self.odometry_topic = p("odometryTopic", "odom")
        self.odometry_frame = p("odometryFrame", "odom")
        self.robot_base_frame = p("robotBaseFrame", "base_footprint")
        self.publish_wheel_tf = p("publishWheelTF", False, bool)
        self.publish_odom_tf = p("publishOdomTF", True, bool)
        self.publish_wheel_joint_state = p("publishWheelJointState", False, bool)
        self.publish_odom = p("publishTf", True, bool)
        self.legacy_mode = p("legacyMode", False, bool)
        self.wheel_separation = p("wheelSeparation", 0.34, float)
        self.wheel_diameter = p("wheelDiameter", 0.15, float)
        self.wheel_acceleration = p("wheelAcceleration", 0.0, float)
        self.wheel_torque = p("wheelTorque", 5.0, float)
        self.update_rate = p("updateRate", 100.0, float)
        self.odometry_source = odometry_source(plugin)
        check_values(plugin,
                     positive=((self.wheel_separation, "wheelSeparation"),
                               (self.wheel_diameter, "wheelDiameter")),
                     nonnegative=((self.wheel_acceleration, "wheelAcceleration"),
                                  (self.wheel_torque, "wheelTorque"), (self.update_rate, "updateRate")))


class DiffDrive(object):
    """The drive of one model. ``update`` runs before a physics step, at least at its due times
    (:meth:`next_due`); it returns True at the steps at which the plugin publishes
    (``updateRate``)."""

    def __init__(self, plugin):
        self.cfg = cfg = DiffDriveConfig(plugin)
        self.model = plugin.model
        self.joints = [wheel_joint(plugin, "leftJoint", "left_joint"),
                       wheel_joint(plugin, "rightJoint", "right_joint")]
        self.radius = 0.5 * cfg.wheel_diameter
        self.gate = RateGate(cfg.update_rate)
        self.encoder = EncoderOdometry(self.radius, cfg.wheel_separation)
        self.reset()

    def reset(self):
        self.target = [0.0, 0.0]         # rim speeds asked for (m/s)
        self.instructed = [0.0, 0.0]     # rim speeds given to the motors under wheelAcceleration
        self.last_update = None
        self.encoder.reset()
        self.gate.reset()
        for j in self.joints:
            j.set_velocity_target(0.0, self.cfg.wheel_torque)

    def update(self, t, dt, command):
        """``command`` = (linear x, angular z) of the latest cmd_vel. Returns True when due."""
        if self.cfg.odometry_source == "encoder":
            self.encoder.update(self.joints[LEFT], self.joints[RIGHT])
        if not self.gate.due(t):
            return False
        since = t - self.last_update if self.last_update is not None else self.gate.period or dt
        self.last_update = t
        v, w = command
        half = 0.5 * w * self.cfg.wheel_separation
        self.target = [v - half, v + half]
        r = self.radius
        current = [j.velocity * r for j in self.joints]
        a = self.cfg.wheel_acceleration
        if a == 0.0 or any(abs(self.target[i] - current[i]) < 0.01 for i in (LEFT, RIGHT)):
            self.instructed = list(self.target)
        else:
            step = a * since
            for i in (LEFT, RIGHT):
                delta = self.target[i] - current[i]
                self.instructed[i] += max(-step, min(step, delta))
        for i, j in enumerate(self.joints):
            j.set_velocity_target(self.instructed[i] / r, self.cfg.wheel_torque)
        return True

    def next_due(self):
        """When :meth:`update` next has work: the next update (the motors hold the wheels'
        targets and the encoders' travel adds up in between)."""
        return self.gate.next_time

    def odometry(self):
        """The reading the plugin publishes (an Odom of modrob_sim.drives.common)."""
        if self.cfg.odometry_source == "encoder":
            return self.encoder.reading()
        return world_odometry(self.model)

    def wheel_positions(self):
        """[(joint name, position)] of the two wheels (publishWheelJointState)."""
        return [(j.name, j.position) for j in self.joints]
