"""hector_gazebo_ros_gps: position and velocity of a link as WGS84 fix, with hector's error model.

Flat earth around the reference point (hector's conversion): with a = 6378137 m, flattening
f = 1/298.257223563, e^2 = 2f - f^2, lat0 the reference latitude:
    N = a / sqrt(1 - e^2 sin^2 lat0)          (prime vertical radius)
    radius_north = N (1 - e^2) / (1 - e^2 sin^2 lat0),   radius_east = N cos lat0
    lat = lat0 + ( cos(h) x + sin(h) y) / radius_north   (degrees)
    lon = lon0 - (-sin(h) x + cos(h) y) / radius_east
    alt = alt0 + z
(x north, y west at heading h = 0). Velocity: (cos h vx + sin h vy, -sin h vx + cos h vy, vz).
Error per axis: hector's SensorModel (sensor_model.py), added to position and velocity.
position_covariance = drift^2 + noise^2
(diagonal, type DIAGONAL_KNOWN).
"""
import math

from .core import Rate, noise_rng
from .errors import SensorConfigError
from .sdf import Params
from .sensor_model import SensorModel

EQUATORIAL_RADIUS = 6378137.0
FLATTENING = 1.0 / 298.257223563
EXCENTRICITY2 = 2 * FLATTENING - FLATTENING * FLATTENING


class GpsFix(object):
    __slots__ = ("latitude", "longitude", "altitude", "velocity", "covariance")

    def __init__(self, latitude, longitude, altitude, velocity, covariance):
        self.latitude, self.longitude, self.altitude = latitude, longitude, altitude
        self.velocity = velocity
        self.covariance = covariance


class HectorGps(object):
    FILENAME = "libhector_gazebo_ros_gps.so"

    def __init__(self, world, model, plugin_elem, where, seed=None):
        p = Params(plugin_elem, where)
        body = p.string("bodyName")
        if not body:
            raise SensorConfigError("%s: <bodyName> is required (the link the GPS is on)" % where)
        if body not in model.links:
            p.fail("bodyName", body, "is not a link of model '%s'" % model.name)
        self.link = model.links[body]
        self.frame_id = p.string("frameId", "/world")
        self.topic = p.string("topicName", "fix")
        self.velocity_topic = p.string("velocityTopicName", "fix_velocity")
        self.reference_latitude = p.float("referenceLatitude", 49.9)
        self.reference_longitude = p.float("referenceLongitude", 8.9)
        self.reference_heading = math.radians(p.float("referenceHeading", 0.0))
        self.reference_altitude = p.float("referenceAltitude", 0.0)
        if not -90.0 <= self.reference_latitude <= 90.0:
            p.fail("referenceLatitude", self.reference_latitude, "must be within [-90, 90] degrees")
        self.status = p.int("status", 0)
        self.service = p.int("service", 0)
        self.rate = Rate(p.float("updateRate", 4.0, nonneg=True))
        self.world, self.seed = world, seed
        rng = noise_rng(world, seed)
        self.position_error = SensorModel(p, "", rng)
        self.velocity_error = SensorModel(p, "velocity", rng)
        s = math.sin(math.radians(self.reference_latitude))
        temp = 1.0 / (1.0 - EXCENTRICITY2 * s * s)
        prime_vertical = EQUATORIAL_RADIUS * math.sqrt(temp)
        self.radius_north = prime_vertical * (1 - EXCENTRICITY2) * temp
        self.radius_east = prime_vertical * math.cos(math.radians(self.reference_latitude))
        pe = self.position_error
        self.covariance = [pe.drift[0] ** 2 + pe.gaussian_noise[0] ** 2, 0.0, 0.0,
                           0.0, pe.drift[1] ** 2 + pe.gaussian_noise[1] ** 2, 0.0,
                           0.0, 0.0, pe.drift[2] ** 2 + pe.gaussian_noise[2] ** 2]
        self._last_t = None

    def reset(self, reseed=True):
        if reseed and self.seed is not None:
            rng = noise_rng(self.world, self.seed)
            self.position_error.rng = self.velocity_error.rng = rng
        self.rate.reset()
        self.position_error.reset()
        self.velocity_error.reset()
        self._last_t = None

    def to_geodetic(self, x, y, z):
        h = self.reference_heading
        north = math.cos(h) * x + math.sin(h) * y
        west = -math.sin(h) * x + math.cos(h) * y
        lat = self.reference_latitude + math.degrees(north / self.radius_north)
        lon = self.reference_longitude - math.degrees(west / self.radius_east)
        return lat, lon, self.reference_altitude + z

    def step(self, t):
        if not self.rate.due(t):
            return None
        dt = t - self._last_t if self._last_t is not None and t > self._last_t else 0.0
        self._last_t = t
        pos = self.link.pose[0]
        vel = self.link.twist[0]
        e = self.position_error.update(dt)
        ev = self.velocity_error.update(dt)
        x, y, z = pos[0] + e[0], pos[1] + e[1], pos[2] + e[2]
        vx, vy, vz = vel[0] + ev[0], vel[1] + ev[1], vel[2] + ev[2]
        lat, lon, alt = self.to_geodetic(x, y, z)
        h = self.reference_heading
        v = (math.cos(h) * vx + math.sin(h) * vy, -math.sin(h) * vx + math.cos(h) * vy, vz)
        return GpsFix(lat, lon, alt, v, list(self.covariance))
