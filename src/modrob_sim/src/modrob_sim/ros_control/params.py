"""Reading controller parameters from a nested dict (what ``rospy.get_param(ns)`` returns) with
errors that name the full parameter path and say what to do, as controller_manager does."""
import math

from modrob_sim.errors import ControllerError

_MISSING = object()


def join(ns, *names):
    """'/ptrz/pan_controller' + 'pid', 'p' -> '/ptrz/pan_controller/pid/p'."""
    out = ns.rstrip("/")
    for n in names:
        out += "/" + str(n).strip("/")
    return out or "/"


class Params(object):
    """A read-only view of one namespace of the parameter server."""

    def __init__(self, values, ns):
        if values is None:
            values = {}
        if not isinstance(values, dict):
            raise ControllerError("Parameter %s must be a dictionary (namespace), not %r"
                                  % (ns, values))
        self.values = values
        self.ns = ns

    def path(self, *names):
        return join(self.ns, *names)

    def has(self, name):
        return name in self.values

    def child(self, name, required=False):
        value = self.values.get(name, _MISSING)
        if value is _MISSING:
            if required:
                raise ControllerError("Parameter %s is missing: it must be a namespace (e.g. "
                                      "'%s: {p: 100.0, i: 0.01, d: 10.0}' in your controller YAML)"
                                      % (self.path(name), name))
            value = {}
        if not isinstance(value, dict):
            raise ControllerError("Parameter %s must be a namespace (dictionary), got %r"
                                  % (self.path(name), value))
        return Params(value, self.path(name))

    def get(self, name, default=_MISSING, kind=None):
        value = self.values.get(name, _MISSING)
        if value is _MISSING:
            if default is _MISSING:
                raise ControllerError("Parameter %s is missing; set it in the controller's YAML "
                                      "(loaded with rosparam) before loading the controller"
                                      % self.path(name))
            return default
        if kind is float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ControllerError("Parameter %s must be a number, got %r" % (self.path(name), value))
            value = float(value)
            if not math.isfinite(value):
                raise ControllerError("Parameter %s must be finite, got %r" % (self.path(name), value))
        elif kind is bool:
            if not isinstance(value, bool):
                raise ControllerError("Parameter %s must be true or false, got %r" % (self.path(name), value))
        elif kind is str:
            if not isinstance(value, str) or not value:
                raise ControllerError("Parameter %s must be a non-empty string, got %r"
                                      % (self.path(name), value))
        elif kind is list:
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise ControllerError("Parameter %s must be a list of joint names, got %r"
                                      % (self.path(name), value))
        return value


def nest_slash_keys(values):
    """What ``rosparam load`` does with keys containing '/': {'a/b': {'c': 1}} -> {'a': {'b': {'c': 1}}}."""
    if not isinstance(values, dict):
        return values
    out = {}
    for key, value in values.items():
        value = nest_slash_keys(value)
        parts = [p for p in str(key).split("/") if p]
        node = out
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        if parts:
            last = parts[-1]
            if isinstance(node.get(last), dict) and isinstance(value, dict):
                node[last].update(value)
            else:
                node[last] = value
    return out
