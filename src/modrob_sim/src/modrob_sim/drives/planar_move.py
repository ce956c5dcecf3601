"""gazebo_ros_planar_move (libgazebo_ros_planar_move.so) without ROS: a holonomic base moved by
setting its velocity (x, y in its heading, the yaw rate; vertical velocity 0) before every
physics step, as the original sets the model's velocity at each world update: no wheels, so
contacts push the model only within a step. The World does that at every step (a PLANAR_VELOCITY
model actuator, physics.actuators); the plugin's Python runs only when the command changes, at
``cmdTimeout`` and at ``odometryRate`` (odometry from the world).

Parameters (defaults as gazebo_plugins'): commandTopic cmd_vel, odometryTopic odom,
odometryFrame odom, robotBaseFrame base_footprint, odometryRate 20 Hz (0: none),
cmdTimeout -1 s (negative: the command stays until the next).
"""
import math

from modrob_sim.errors import InputError
from modrob_sim.gazebo_ros.plugin_base import RateGate
from modrob_sim.physics.actuators import PLANAR_VELOCITY
from modrob_sim.physics.transforms import rpy_from_quat

from .common import Odom, check_values

INF = float("inf")


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
        #: why the base cannot move (its canonical link is static), else None: the ROS side warns
        self.problem = None
        try:
            self.actuator = plugin.context.world.add_model_actuator(self.model, PLANAR_VELOCITY)
        except InputError as e:      # Gazebo's SetLinearVel moves a static model no more
            self.actuator = None
            self.problem = str(e)
        self.reset()

    def reset(self):
        self.last_pose = None
        self.last_time = None
        self.reading = None
        self.expires = INF
        if self.actuator is not None:
            self.actuator.command = (0.0, 0.0, 0.0)
        if self.gate is not None:
            self.gate.reset()

    def update(self, t, dt, command, command_time=None):
        """``command`` = (x, y, yaw rate); ``command_time`` the simulated time it came (for
        cmdTimeout). Gives the model actuator the velocity it holds at every step until the next
        update; returns True when odometry is due."""
        vx, vy, wz = command
        timeout = self.cfg.cmd_timeout
        self.expires = INF
        if timeout >= 0:
            if command_time is None or t - command_time > timeout:
                vx = vy = wz = 0.0
            else:
                self.expires = command_time + timeout
        if self.actuator is not None:
            self.actuator.command = (vx, vy, wz)
        if self.gate is None or not self.gate.due(t):
            return False
        self.reading = self._odometry(t, wz)
        return True

    def next_due(self):
        """When :meth:`update` next has work without a new command: the odometry's next reading,
        or the step after ``cmdTimeout`` ends (the hook is asked again at each step from then on
        until the timeout holds, ``t - command_time > cmdTimeout``, which is at most two steps)."""
        due = self.gate.next_time if self.gate is not None else INF
        return min(due, self.expires)

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

    def shutdown(self):
        if self.actuator is not None:
            self.actuator.remove()
            self.actuator = None
