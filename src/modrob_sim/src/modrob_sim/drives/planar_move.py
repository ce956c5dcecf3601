"""gazebo_ros_planar_move (libgazebo_ros_planar_move.so) without ROS: a holonomic base moved by
setting its velocity (x, y in its heading, the yaw rate; vertical velocity 0) before every
physics step, as the original sets the model's velocity at each world update: no wheels, so
contacts push the model only within a step. Odometry from the world at ``odometryRate``.

Parameters (defaults as gazebo_plugins'): commandTopic cmd_vel, odometryTopic odom,
odometryFrame odom, robotBaseFrame base_footprint, odometryRate 20 Hz (0: none),
cmdTimeout -1 s (negative: the command stays until the next).
"""
import math

from modrob_sim.gazebo_ros.plugin_base import RateGate
from modrob_sim.physics.transforms import rpy_from_quat

from .common import Odom, check_values


class PlanarMoveConfig(object):
    def __init__(self, plugin):
        p = plugin.param
        self.command_topic = p("commandTopic", "cmd_vel")
        self.odometry_topic = p("odometryTopic", "odom")
        self.odometry_frame = p("odometryFrame", "odom")
        self.robot_base_frame = p("robotBaseFrame", "base_footprint")
        self.odometry_rate = p("odometryRate", 20.0, float)
        self.cmd_timeout = p("cmdTimeout", -1.0, float)
        self.odometry_source = "world"
        check_values(plugin, nonnegative=((self.odometry_rate, "odometryRate"),))


class PlanarMove(object):
    joints = ()

    def __init__(self, plugin):
        self.cfg = PlanarMoveConfig(plugin)
        self.model = plugin.model
        self.gate = RateGate(self.cfg.odometry_rate) if self.cfg.odometry_rate > 0 else None
        self.reset()

    def reset(self):
        self.last_pose = None
        self.last_time = None
        self.reading = None
        if self.gate is not None:
            self.gate.reset()

    def update(self, t, dt, command, command_time=None):
        """``command`` = (x, y, yaw rate); ``command_time`` the simulated time it came (for
        cmdTimeout). Sets the model's velocity; returns True when odometry is due."""
        vx, vy, wz = command
        if self.cfg.cmd_timeout >= 0 and (command_time is None or t - command_time > self.cfg.cmd_timeout):
            vx = vy = wz = 0.0
        (_p, q) = self.model.pose
        yaw = rpy_from_quat(q)[2]
        c, s = math.cos(yaw), math.sin(yaw)
        self.model.set_twist(((vx * c - vy * s, vy * c + vx * s, 0.0), (0.0, 0.0, wz)))
        if self.gate is None or not self.gate.due(t):
            return False
        self.reading = self._odometry(t, wz)
        return True

    def _odometry(self, t, wz):
        """Pose from the world; twist from the pose's change since the last reading, turned into
        the heading (as the original differentiates it)."""
        (p, q) = self.model.pose
        yaw = rpy_from_quat(q)[2]
        vx = vy = w = 0.0
        if self.last_pose is not None and t > self.last_time:
            step = t - self.last_time
            dx, dy = (p[0] - self.last_pose[0][0]) / step, (p[1] - self.last_pose[0][1]) / step
            last_yaw = rpy_from_quat(self.last_pose[1])[2]
            if wz > math.pi / step:
                w = wz
            else:
                w = ((yaw - last_yaw + math.pi) % (2.0 * math.pi) - math.pi) / step
            c, s = math.cos(yaw), math.sin(yaw)
            vx, vy = c * dx + s * dy, c * dy - s * dx
        self.last_pose, self.last_time = (p, q), t
        return Odom((p[0], p[1], 0.0), q, (vx, vy, 0.0), (0.0, 0.0, w))

    def odometry(self):
        return self.reading
