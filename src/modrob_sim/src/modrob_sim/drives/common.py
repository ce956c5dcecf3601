"""What the gazebo_plugins drives share: finding their wheel joints, odometry from the world
(``odometrySource`` world) and from wheel encoders, the odometry covariances. Pure: no rospy."""
import collections
import math

from modrob_sim.errors import PluginError
from modrob_sim.physics.transforms import pose_inv, pose_mul, quat_from_rpy, rpy_from_quat
from modrob_sim.ros_control.controllers.mobile_base import Odometry as ArcOdometry

#: One odometry reading: pose (position, quaternion x y z w) in the odometry frame, twist in the
#: robot's base frame (linear x y z, angular x y z), as nav_msgs/Odometry carries them.
Odom = collections.namedtuple("Odom", "position orientation linear angular")

#: gazebo_plugins' fixed pose covariance diagonal of the diff drive, tricycle and planar move
#: (x, y, z, roll, pitch, yaw): the planar pose is known well, the rest "not at all".
POSE_COVARIANCE = (0.00001, 0.00001, 1e12, 1e12, 1e12, 0.001)

ODOM_SOURCES = ("encoder", "world")


def diagonal(values):
    """A 6x6 covariance (row-major, 36 floats) with ``values`` on the diagonal."""
    c = [0.0] * 36
    for i, v in enumerate(values):
        c[7 * i] = float(v)
    return c


def check_values(plugin, positive=(), nonnegative=()):
    """PluginError naming the tag of the first value of ``positive`` ((value, tag) pairs) that is
    not above 0, or of ``nonnegative`` that is below 0."""
    for value, tag in positive:
        if not value > 0:
            raise PluginError("%s: <%s> must be positive, got %r" % (plugin.name, tag, value))
    for value, tag in nonnegative:
        if value < 0:
            raise PluginError("%s: <%s> must not be negative, got %r" % (plugin.name, tag, value))


def wheel_joint(plugin, tag, default):
    """The model's joint named by ``<tag>`` (``default`` when absent), which must turn: revolute
    or continuous. PluginError naming the tag and the joints there are otherwise."""
    name = plugin.param(tag, default)
    joint = plugin.model.joints.get(name)
    if joint is None:
        raise PluginError("%s: <%s> '%s' is not a joint of the model (joints: %s)"
                          % (plugin.name, tag, name, ", ".join(sorted(plugin.model.joints)) or "none"))
    if joint.type not in ("revolute", "continuous"):
        raise PluginError("%s: <%s> '%s' is a %s joint; a wheel needs a revolute or continuous one"
                          % (plugin.name, tag, name, joint.type))
    return joint


def odometry_source(plugin, default="world"):
    """``<odometrySource>``: encoder or world (gazebo_ros also takes 0 and 1)."""
    text = plugin.param("odometrySource", default).strip().lower()
    text = {"0": "encoder", "1": "world"}.get(text, text)
    if text not in ODOM_SOURCES:
        raise PluginError("%s: <odometrySource> '%s' is neither encoder nor world"
                          % (plugin.name, text))
    return text


def world_odometry(model):
    """``odometrySource`` world: the model's pose in the world, its velocity turned into the
    robot's heading (gazebo_plugins rotate by the yaw only: x forward, y left), its yaw rate."""
    (p, q) = model.pose
    (v, w) = model.twist
    yaw = rpy_from_quat(q)[2]
    c, s = math.cos(yaw), math.sin(yaw)
    return Odom(p, q, (c * v[0] + s * v[1], c * v[1] - s * v[0], 0.0), (0.0, 0.0, w[2]))


def joint_transforms(model, joints):
    """[(parent link, child link, pose of the child link in the parent link)] of ``joints``
    (the drives' publishWheelTF)."""
    out = []
    for j in joints:
        parent, child = model.links[j.parent], model.links[j.child]
        out.append((j.parent, j.child, pose_mul(pose_inv(parent.pose), child.pose)))
    return out


class EncoderOdometry(object):
    """Dead reckoning of a differential pair of wheels of radius ``r`` and track ``b``
    (gazebo_plugins' encoder odometry): at each :meth:`update`, the wheels' travel since the last
    one moves the pose along one arc (DiffDriveController's rule, the one implementation:
    ros_control's mobile_base.Odometry), so it may run at the plugin's updates only; the twist is
    the wheels' speeds then. The pose stays in the plane (z, roll, pitch 0) and starts at zero at
    the first update after a reset."""

    def __init__(self, radius, separation):
        self.r = radius
        self.b = separation
        self.arc = ArcOdometry()
        self.reset()

    def reset(self):
        self.arc.reset()
        self.last = None             # the wheels' positions at the last update
        self.v = self.w = 0.0

    def update(self, left, right):
        """The travel of the joints ``left`` and ``right`` since the last update."""
        ql, qr = left.position, right.position
        if self.last is not None:
            sl = (ql - self.last[0]) * self.r
            sr = (qr - self.last[1]) * self.r
            self.arc.integrate(0.5 * (sl + sr), (sr - sl) / self.b)
        self.last = (ql, qr)
        vl, vr = left.velocity * self.r, right.velocity * self.r
        # signed, along the heading (gazebo_plugins report the speed without its sign)
        self.v = 0.5 * (vl + vr)
        self.w = (vr - vl) / self.b

    def reading(self):
        a = self.arc
        return Odom((a.x, a.y, 0.0), quat_from_rpy(0.0, 0.0, a.heading), (self.v, 0.0, 0.0),
                    (0.0, 0.0, self.w))
