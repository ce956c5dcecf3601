"""What every sensor core shares: the link it is mounted on, its pose on that link, its update
rate in simulated time, and the world's seeded noise."""
import numpy as np

from modrob_sim.physics.transforms import pose_mul

from .errors import SensorConfigError
from .sdf import Params, sensor_update_rate


def where(model, link=None, filename=None, sensor=None):
    """'model 'm' link 'l' sensor 's' plugin f' for messages."""
    parts = ["model '%s'" % model.name]
    if link:
        parts.append("link '%s'" % link)
    if sensor is not None and sensor.get("name"):
        parts.append("sensor '%s'" % sensor.get("name"))
    if filename:
        parts.append("plugin %s" % filename)
    return " ".join(parts)


def noise_rng(world, seed=None):
    """A numpy Generator for a sensor's noise: from ``seed`` (the plugin's seed, derived from the
    world's seed by the /gazebo node) or, without one, seeded from the World's seeded generator.
    Either way a seeded world gives the same noise every run and each sensor its own stream."""
    return np.random.default_rng(world.rng.getrandbits(64) if seed is None else seed)


class Rate(object):
    """Decimation to ``rate`` Hz of simulated time (0: every call). ``due(t)`` is true at most
    once per period; after a reset (time going back) it starts again."""

    def __init__(self, rate):
        self.period = 1.0 / rate if rate and rate > 0 else 0.0
        self.next = None
        self.last = None

    def due(self, t):
        if self.next is None or (self.last is not None and t < self.last):
            self.next = t
        if t + 1e-9 < self.next:
            return False
        self.last = t
        self.next = self.next + self.period if self.period else t
        if self.next <= t:       # fell behind (or rate above the physics rate): no burst
            self.next = t + self.period
        return True

    @property
    def next_time(self):
        """The simulated time from which :meth:`due` is true (-inf before the first call or
        with no rate): what a plugin declares as its hook's due time."""
        if self.next is None or not self.period:
            return -float("inf")
        return self.next

    def reset(self):
        self.next = None
        self.last = None


class MountedSensor(object):
    """A <sensor> on a link: ``pose()`` is its world pose (link pose composed with <pose>)."""

    def __init__(self, model, link_name, sensor_elem, filename=None):
        w = where(model, link_name, filename, sensor_elem)
        if link_name not in model.links:
            raise SensorConfigError("%s: no link named '%s'" % (w, link_name))
        self.model = model
        self.link = model.links[link_name]
        self.sensor_elem = sensor_elem
        self.where = w
        sp = Params(sensor_elem, w)
        self.sensor_params = sp
        self.name = sensor_elem.get("name", "") if sensor_elem is not None else ""
        self.type = sensor_elem.get("type", "") if sensor_elem is not None else ""
        self.offset = sp.pose("pose")
        self.update_rate = sensor_update_rate(sp) if sensor_elem is not None else 0.0
        self.always_on = sp.bool("always_on", False)
        sp.bool("visualize", False)   # accepted (nothing is drawn here)

    def pose(self):
        return pose_mul(self.link.pose, self.offset)
