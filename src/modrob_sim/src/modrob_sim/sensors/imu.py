"""IMUs: Gazebo's ImuSensor with the gazebo_ros_imu_sensor plugin, and the gazebo_ros_imu model
plugin.

ImuSensor (``<sensor type="imu">`` on a link, at the sensor's <update_rate>): the angular velocity
and the linear acceleration are in the sensor frame; the acceleration is the finite difference of
the world velocity of the sensor point between two sensor updates minus gravity (a resting IMU
reads +9.81 m/s^2 along its up axis, as Gazebo's); the orientation is relative to the world
(``initialOrientationAsReference`` false, the plugin's default since REP 145) or to the sensor's
initial orientation (true, the deprecated behaviour). gazebo_ros_imu_sensor rotates the
orientation by ``rpyOffset`` (``offset * q``), adds ``gaussianNoise`` to every component (the
four quaternion components too, as the plugin does), sets every covariance diagonal to
gaussianNoise^2 and publishes at most ``updateRateHZ`` times a second with frame_id ``frameName``
(``bodyName`` in older files).

gazebo_ros_imu (model plugin, ``bodyName`` link, ``updateRate`` Hz, 0 = every step): orientation
``rpyOffset * q_link``, angular velocity and the finite-difference acceleration (gravity removed
like the sensor, so both IMUs read the same physical quantity) in the link frame.
"""
import math

from modrob_sim.physics.transforms import (cross, pose_mul, quat_conj, quat_from_rpy, quat_mul,
                                           quat_normalize, quat_rotate)

from .core import MountedSensor, Rate, noise_rng
from .errors import SensorConfigError
from .sdf import Params


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _point_velocity(twist, origin, point):
    """World velocity of a world point rigidly attached to a link whose frame is at ``origin``
    and moves with ``twist`` (the link's)."""
    (v, w) = twist
    r = _sub(point, origin)
    c = cross(w, r)
    return (v[0] + c[0], v[1] + c[1], v[2] + c[2])


class ImuReading(object):
    __slots__ = ("orientation", "angular_velocity", "linear_acceleration")

    def __init__(self, orientation, angular_velocity, linear_acceleration):
        self.orientation = orientation
        self.angular_velocity = angular_velocity
        self.linear_acceleration = linear_acceleration


class ImuCore(object):
    """Finite-difference IMU on the frame ``offset`` (a pose in the link frame; None: the link
    frame itself) of ``link``. A measurement reads the link's pose and twist once each."""

    def __init__(self, world, link, offset=None):
        self.world = world
        self.link = link
        self.offset = offset
        self.reference = (0.0, 0.0, 0.0, 1.0)
        self.reset()

    def reset(self):
        self._last_v = None
        self._last_t = None
        self._acc = None

    def measure(self, t):
        link = self.link
        lp = link.pose
        pos, rot = lp if self.offset is None else pose_mul(lp, self.offset)
        twist = link.twist
        v = _point_velocity(twist, lp[0], pos)
        g = self.world.gravity
        if self._last_t is not None and t > self._last_t:
            dt = t - self._last_t
            a = ((v[0] - self._last_v[0]) / dt, (v[1] - self._last_v[1]) / dt, (v[2] - self._last_v[2]) / dt)
        elif self._acc is not None:
            a = self._acc
        else:
            a = (0.0, 0.0, 0.0)
        self._acc = a
        self._last_v, self._last_t = v, t
        inv = quat_conj(rot)
        spec = quat_rotate(inv, (a[0] - g[0], a[1] - g[1], a[2] - g[2]))
        w = quat_rotate(inv, twist[1])
        q = quat_normalize(quat_mul(quat_conj(self.reference), rot))
        return ImuReading(q, w, spec)


class ImuSensor(MountedSensor):
    """Gazebo's ImuSensor + gazebo_ros_imu_sensor parameters."""

    FILENAME = "libgazebo_ros_imu_sensor.so"

    def __init__(self, world, model, link_name, sensor_elem, plugin_elem, filename=FILENAME, seed=None):
        MountedSensor.__init__(self, model, link_name, sensor_elem, filename)
        p = Params(plugin_elem, self.where)
        self.topic = p.string("topicName", "imu_data")
        self.frame = p.string("frameName") or p.string("bodyName") or link_name
        self.publish_rate = p.float("updateRateHZ", 1.0, nonneg=True)
        self.noise = p.float("gaussianNoise", 0.0, nonneg=True)
        self.xyz_offset = p.floats("xyzOffset", 3, (0.0, 0.0, 0.0))
        rpy = p.floats("rpyOffset", 3, (0.0, 0.0, 0.0))
        self.rot_offset = quat_from_rpy(*rpy)
        self.initial_reference = p.bool("initialOrientationAsReference", False)
        self.world = world
        self.core = ImuCore(world, self.link, self.offset)
        self.sensor_rate = Rate(self.update_rate)
        self.publish_gate = Rate(self.publish_rate)
        self.seed = seed
        self.rng = noise_rng(world, seed)
        self._reference_set = False
        self.last = None

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            self.rng = noise_rng(self.world, self.seed)
        self.core.reset()
        self.sensor_rate.reset()
        self.publish_gate.reset()
        self._reference_set = False

    def step(self, t):
        """Call after each physics step; returns an ImuReading when the plugin publishes one."""
        if not self.sensor_rate.due(t):
            return None
        if not self._reference_set:
            self.core.reference = self.pose()[1] if self.initial_reference else (0.0, 0.0, 0.0, 1.0)
            self._reference_set = True
        r = self.core.measure(t)
        self.last = r
        if not self.publish_gate.due(t):
            return None
        q = quat_mul(self.rot_offset, r.orientation)
        return noisy(ImuReading(q, r.angular_velocity, r.linear_acceleration), self.noise, self.rng)


class ImuModelPlugin(object):
    """gazebo_ros_imu (model plugin) parameters and readings."""

    FILENAME = "libgazebo_ros_imu.so"

    def __init__(self, world, model, plugin_elem, where, seed=None):
        p = Params(plugin_elem, where)
        body = p.string("bodyName")
        if not body:
            raise SensorConfigError("%s: <bodyName> is required (the link the IMU is on)" % where)
        self.world, self.seed = world, seed
        if body not in model.links:
            p.fail("bodyName", body, "is not a link of model '%s'" % model.name)
        self.link = model.links[body]
        self.topic = p.string("topicName", "/default_imu")
        self.service = p.string("serviceName", "/default_imu")
        self.frame = p.string("frameName", body)
        self.noise = p.float("gaussianNoise", 0.0, nonneg=True)
        self.xyz_offset = p.floats("xyzOffset", 3) or p.floats("xyzOffsets", 3, (0.0, 0.0, 0.0))
        rpy = p.floats("rpyOffset", 3) or p.floats("rpyOffsets", 3, (0.0, 0.0, 0.0))
        self.rot_offset = quat_from_rpy(*rpy)
        self.rate = Rate(p.float("updateRate", 0.0, nonneg=True))
        self.core = ImuCore(world, self.link)
        self.rng = noise_rng(world, seed)

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            self.rng = noise_rng(self.world, self.seed)
        self.core.reset()
        self.rate.reset()

    def step(self, t):
        if not self.rate.due(t):
            return None
        r = self.core.measure(t)
        q = quat_normalize(quat_mul(self.rot_offset, r.orientation))
        return noisy(ImuReading(q, r.angular_velocity, r.linear_acceleration), self.noise, self.rng,
                     orient=False)


def noisy(r, sigma, rng, orient=True):
    if not sigma:
        return r
    n = rng.normal(0.0, sigma, 10)
    q = r.orientation
    if orient:
        q = (q[0] + n[0], q[1] + n[1], q[2] + n[2], q[3] + n[3])
    w = r.angular_velocity
    a = r.linear_acceleration
    return ImuReading(q, (w[0] + n[4], w[1] + n[5], w[2] + n[6]), (a[0] + n[7], a[1] + n[8], a[2] + n[9]))


def covariance(sigma):
    s2 = sigma * sigma
    return [s2, 0.0, 0.0, 0.0, s2, 0.0, 0.0, 0.0, s2]


__all__ = ["ImuSensor", "ImuModelPlugin", "ImuCore", "ImuReading", "covariance", "math"]
