"""hector_gazebo_plugins' IMU (libhector_gazebo_ros_imu.so) and magnetometer
(libhector_gazebo_ros_magnetic.so) as model plugins on a link, with hector's error model
(sensor_model.SensorModel) and update timer (``updateRate`` Hz, absent or 0: every step).

IMU, at each update (dt since the last): the orientation is ``rpyOffset * q_link``; the
acceleration is R^T ((v - v_prev) / dt - g) of the link origin's world velocity v; the angular
rate comes from the change of orientation since the last update, ``2 acos(w) axis / dt``, turned
back by the offset. Then acceleration and rate go through their models (``accel``, ``rate``
prefixes: Offset, Drift, DriftFrequency, GaussianNoise, ScaleError; an old-style
``gaussianNoise`` sets both noises) and the ``yaw`` model drifts; the published orientation
carries the accelerometer bias as roll/pitch error and the yaw bias as heading error (a pseudo
AHRS). Covariances: rate and acceleration noise^2 on their diagonals, orientation
(accel noise / g)^2 for roll and pitch, yaw noise^2 for yaw. ``serviceName``
(``<topicName>/calibrate``) resets the rate drift to zero; ``biasTopicName``
(``<topicName>/bias``) publishes the current biases as an Imu.

Magnetometer: the earth's field of ``magnitude`` (1.0), ``referenceHeading`` (0 deg, compass),
``declination`` (0 deg), ``inclination`` (60 deg) in the world (x north, y west, z up):
m (cos i cos(h - d), cos i sin(h - d), -sin i), rotated into the link frame, through the model
(no prefix); sensor_msgs/MagneticField with ``useMagneticFieldMsgs``, else
geometry_msgs/Vector3Stamped.
"""
import math

from modrob_sim.physics.transforms import quat_conj, quat_from_rpy, quat_mul, quat_normalize, quat_rotate

from .core import Rate, noise_rng
from .sdf import Params
from .sensor_model import SensorModel


def _link(model, p):
    """``<bodyName>`` or, as hector, the model's first (canonical) link."""
    name = p.string("bodyName")
    if not name:
        return model.canonical_link
    if name not in model.links:
        p.fail("bodyName", name, "is not a link of model '%s'" % model.name)
    return model.links[name]


class HectorImuReading(object):
    __slots__ = ("orientation", "angular_velocity", "linear_acceleration", "bias_orientation",
                 "rate_bias", "accel_bias")

    def __init__(self, *values):
        for k, v in zip(self.__slots__, values):
            setattr(self, k, v)


class HectorImu(object):
    FILENAME = "libhector_gazebo_ros_imu.so"

    def __init__(self, world, model, plugin_elem, where, seed=None):
        p = Params(plugin_elem, where)
        self.world, self.seed, self.where = world, seed, where
        self.link = _link(model, p)
        self.frame_id = p.string("frameId", self.link.name)
        self.topic = p.string("topicName", "imu")
        self.bias_topic = p.string("biasTopicName", self.topic + "/bias" if self.topic else "")
        self.service = p.string("serviceName", self.topic + "/calibrate")
        rng = noise_rng(world, seed)
        self.accel = SensorModel(p, "accel", rng)
        self.rate = SensorModel(p, "rate", rng)
        self.yaw = SensorModel(p, "yaw", rng, axes=1)
        noise = p.float("gaussianNoise", 0.0, nonneg=True)
        if noise != 0.0:
            self.accel.gaussian_noise = self.rate.gaussian_noise = (noise,) * 3
        p.floats("xyzOffset", 3, (0.0, 0.0, 0.0))        # read, unused (as hector)
        self.offset = quat_from_rpy(*p.floats("rpyOffset", 3, (0.0, 0.0, 0.0)))
        self.timer = Rate(p.float("updateRate", 0.0, nonneg=True))
        self.reset()

    def models(self):
        return (self.accel, self.rate, self.yaw)

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            rng = noise_rng(self.world, self.seed)
            for m in self.models():
                m.rng = rng
        for m in self.models():
            m.reset()
        self.timer.reset()
        self.last_t = None
        self.orientation = (0.0, 0.0, 0.0, 1.0)
        self.velocity = (0.0, 0.0, 0.0)
        self.lin_acc = (0.0, 0.0, 0.0)
        self.ang_rate = (0.0, 0.0, 0.0)

    def calibrate(self):
        """serviceName: the rate drift back to zero."""
        self.rate.reset((0.0, 0.0, 0.0))

    def step(self, t):
        """A HectorImuReading when an update is due at simulated time ``t``, else None."""
        if not self.timer.due(t):
            return None
        dt = t - self.last_t if self.last_t is not None and t > self.last_t else 0.0
        self.last_t = t
        (_p, q_link) = self.link.pose
        rot = quat_normalize(quat_mul(self.offset, q_link))
        g = self.world.gravity
        v = self.link.twist[0]
        if dt > 0.0:
            a = tuple((v[i] - self.velocity[i]) / dt - g[i] for i in range(3))
            self.lin_acc = quat_rotate(quat_conj(rot), a)
            d = quat_mul(quat_conj(self.orientation), rot)
            n = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            angle = 2.0 * math.acos(max(-1.0, min(1.0, d[3])))
            axis = (d[0] / n, d[1] / n, d[2] / n) if n > 0 else (0.0, 0.0, 0.0)
            self.ang_rate = quat_rotate(quat_conj(self.offset), tuple(angle * x / dt for x in axis))
        self.velocity = v
        self.orientation = rot
        accel = self.accel.apply(self.lin_acc, dt)
        rate = self.rate.apply(self.ang_rate, dt)
        self.yaw.update(dt)
        g_len = math.sqrt(sum(x * x for x in g))
        drift = quat_rotate(q_link, self.accel.bias)
        yaw_error = self.yaw.bias[0]
        tilt = (0.5 * drift[1] / g_len, 0.5 * -drift[0] / g_len, 0.0, 1.0) if g_len > 0 \
            else (0.0, 0.0, 0.0, 1.0)
        error = quat_normalize(quat_mul((0.0, 0.0, math.sin(yaw_error / 2), math.cos(yaw_error / 2)), tilt))
        return HectorImuReading(quat_mul(error, rot), rate, accel, error, self.rate.bias, self.accel.bias)

    def covariances(self):
        """(orientation, angular velocity, linear acceleration) 3x3 covariances, row-major."""
        g = math.sqrt(sum(x * x for x in self.world.gravity))
        an, rn, yn = self.accel.gaussian_noise, self.rate.gaussian_noise, self.yaw.gaussian_noise[0]
        orient = [0.0] * 9
        if g > 0:
            orient[0], orient[4] = (an[0] / g) ** 2, (an[1] / g) ** 2
        else:
            orient[0] = orient[4] = -1.0
        orient[8] = yn * yn
        return (orient, [rn[0] ** 2, 0, 0, 0, rn[1] ** 2, 0, 0, 0, rn[2] ** 2],
                [an[0] ** 2, 0, 0, 0, an[1] ** 2, 0, 0, 0, an[2] ** 2])


class HectorMagnetic(object):
    FILENAME = "libhector_gazebo_ros_magnetic.so"

    def __init__(self, world, model, plugin_elem, where, seed=None):
        p = Params(plugin_elem, where)
        self.world, self.seed, self.where = world, seed, where
        self.link = _link(model, p)
        self.frame_id = p.string("frameId", self.link.name)
        self.topic = p.string("topicName", "magnetic")
        magnitude = p.float("magnitude", 1.0)
        heading = math.radians(p.float("referenceHeading", 0.0))
        if p.bool("useWorldSphericalCoordinates", False):
            heading = 0.5 * math.pi    # the world's heading offset is 0 (no <spherical_coordinates> read)
        declination = math.radians(p.float("declination", 0.0))
        inclination = math.radians(p.float("inclination", 60.0))
        self.use_magnetic_field_msgs = p.bool("useMagneticFieldMsgs", False)
        self.field_world = (magnitude * math.cos(inclination) * math.cos(heading - declination),
                            magnitude * math.cos(inclination) * math.sin(heading - declination),
                            -magnitude * math.sin(inclination))
        self.model_error = SensorModel(p, "", noise_rng(world, seed))
        self.timer = Rate(p.float("updateRate", 0.0, nonneg=True))
        self.reset()

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            self.model_error.rng = noise_rng(self.world, self.seed)
        self.model_error.reset()
        self.timer.reset()
        self.last_t = None

    def step(self, t):
        """The field in the link frame when due, else None."""
        if not self.timer.due(t):
            return None
        dt = t - self.last_t if self.last_t is not None and t > self.last_t else 0.0
        self.last_t = t
        (_p, q) = self.link.pose
        return self.model_error.apply(quat_rotate(quat_conj(q), self.field_world), dt)
