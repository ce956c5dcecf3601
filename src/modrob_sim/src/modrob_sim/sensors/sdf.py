"""Reading sensor and plugin parameters from SDF/URDF <sensor>/<plugin> Elements with messages
that name the element and the value (SensorConfigError)."""
import math

from modrob_sim.physics.transforms import quat_from_rpy

from .errors import SensorConfigError

TRUE = ("1", "true", "yes", "on")
FALSE = ("0", "false", "no", "off")


class Params(object):
    """Typed access to the children of one Element. ``where`` names it in messages, e.g.
    "model 'bot' link 'laser' plugin libgazebo_ros_laser.so"."""

    def __init__(self, elem, where):
        self.elem = elem
        self.where = where

    def has(self, tag):
        return self.find(tag) is not None

    def find(self, path):
        if self.elem is None:
            return None
        e = self.elem
        for part in path.split("/"):
            nxt = None
            for c in e:
                if isinstance(c.tag, str) and c.tag.split("}")[-1] == part:
                    nxt = c
                    break
            if nxt is None:
                return None
            e = nxt
        return e

    def text(self, path, default=None):
        e = self.find(path)
        if e is None:
            return default
        return (e.text or "").strip()

    def fail(self, path, value, why):
        raise SensorConfigError("%s: <%s> %r %s" % (self.where, path, value, why))

    def string(self, path, default=None):
        t = self.text(path)
        return default if t is None else t

    def float(self, path, default=None, positive=False, nonneg=False):
        t = self.text(path)
        if t is None:
            return default
        try:
            v = float(t)
        except ValueError:
            self.fail(path, t, "is not a number")
        if not math.isfinite(v) and not (math.isinf(v) and v > 0 and not positive):
            self.fail(path, t, "must be finite")
        if positive and not v > 0:
            self.fail(path, t, "must be positive")
        if nonneg and v < 0:
            self.fail(path, t, "must not be negative")
        return v

    def int(self, path, default=None, minimum=None):
        t = self.text(path)
        if t is None:
            return default
        try:
            v = int(float(t))
            if float(t) != v:
                raise ValueError
        except ValueError:
            self.fail(path, t, "is not an integer")
        if minimum is not None and v < minimum:
            self.fail(path, t, "must be at least %d" % minimum)
        return v

    def bool(self, path, default=None):
        t = self.text(path)
        if t is None:
            return default
        if t.lower() in TRUE:
            return True
        if t.lower() in FALSE:
            return False
        self.fail(path, t, "is not a boolean (true/false/1/0)")

    def floats(self, path, n, default=None):
        t = self.text(path)
        if t is None:
            return default
        parts = t.replace(",", " ").split()
        try:
            vals = [float(p) for p in parts]
        except ValueError:
            self.fail(path, t, "is not a list of %d numbers" % n)
        if len(vals) == 1 and n > 1:
            vals = vals * n          # hector and gazebo_ros accept one number for all axes
        if len(vals) != n or not all(math.isfinite(v) for v in vals):
            self.fail(path, t, "must be %d finite numbers" % n)
        return tuple(vals)

    def pose(self, path="pose", default=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))):
        v = self.floats(path, 6)
        if v is None:
            return default
        return (tuple(v[:3]), tuple(quat_from_rpy(*v[3:])))


def sensor_update_rate(p):
    """<update_rate> of a <sensor> (0 or absent: every physics step)."""
    r = p.float("update_rate", 0.0, nonneg=True)
    return r


def tf_resolve(prefix, frame):
    """tf::resolve of ROS Noetic: a leading '/' is stripped; otherwise the tf prefix is
    prepended."""
    if frame.startswith("/"):
        return frame.lstrip("/")
    if prefix:
        return prefix.strip("/") + "/" + frame if prefix.strip("/") else frame
    return frame


def join_ns(ns, name):
    """A topic name as ros::NodeHandle(ns) resolves it under the /gazebo node: absolute names
    stay, relative ones go under the namespace (root if empty)."""
    if name.startswith("/"):
        return name
    ns = (ns or "").strip("/")
    return "/" + (ns + "/" if ns else "") + name
