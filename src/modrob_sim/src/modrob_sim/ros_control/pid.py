"""control_toolbox::Pid with its exact semantics (ROS Noetic, control_toolbox 1.18):

* gains ``p`` (required), ``i``, ``d`` (default 0), ``i_clamp`` -> i_max = |i_clamp|,
  i_min = -|i_clamp|, overridden by ``i_clamp_min`` / ``i_clamp_max``; ``antiwindup`` (false).
* ``compute(error, dt)`` takes the error derivative by finite difference; ``compute(error, dt,
  error_dot)`` uses the given one.
* The integral ``i_error`` accumulates ``dt * error``. Without antiwindup the integral TERM is
  clamped to [i_min, i_max] -- so with no ``i_clamp`` given the integral term is zero, exactly as in
  ros_control. With antiwindup the integral STATE is clamped to [i_min/i, i_max/i].
* dt == 0 or a non-finite error returns 0.
"""
import math

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.params import Params


class PidGains(object):
    __slots__ = ("p", "i", "d", "i_max", "i_min", "antiwindup")

    def __init__(self, p, i=0.0, d=0.0, i_max=0.0, i_min=0.0, antiwindup=False):
        self.p, self.i, self.d = float(p), float(i), float(d)
        self.i_max, self.i_min = float(i_max), float(i_min)
        self.antiwindup = bool(antiwindup)

    @classmethod
    def from_params(cls, params):
        """Gains from a namespace (``Params``) as control_toolbox::Pid::init reads them; the
        error names the full path of a missing ``p``."""
        if not isinstance(params, Params):
            params = Params(params, "")
        if not params.has("p"):
            raise ControllerError("No p gain specified for pid: parameter %s is missing (ros_control "
                                  "needs at least p; i, d, i_clamp are optional)" % params.path("p"))
        p = params.get("p", kind=float)
        i = params.get("i", 0.0, kind=float)
        d = params.get("d", 0.0, kind=float)
        i_clamp = abs(params.get("i_clamp", 0.0, kind=float))
        i_max, i_min = i_clamp, -i_clamp
        if params.has("i_clamp_min"):
            i_min = -abs(params.get("i_clamp_min", kind=float))
        if params.has("i_clamp_max"):
            i_max = abs(params.get("i_clamp_max", kind=float))
        antiwindup = params.get("antiwindup", False, kind=bool)
        return cls(p, i, d, i_max, i_min, antiwindup)

    def as_dict(self):
        return {"p": self.p, "i": self.i, "d": self.d, "i_clamp_max": self.i_max,
                "i_clamp_min": self.i_min, "antiwindup": self.antiwindup}

    def __repr__(self):
        return "PidGains(p=%g, i=%g, d=%g, i_max=%g, i_min=%g, antiwindup=%s)" % (
            self.p, self.i, self.d, self.i_max, self.i_min, self.antiwindup)


class Pid(object):
    """One PID loop. ``gains`` may be replaced at any time (live tuning)."""

    def __init__(self, gains):
        self.gains = gains
        self.reset()

    def reset(self):
        self.p_error_last = 0.0
        self.p_error = 0.0
        self.i_error = 0.0
        self.d_error = 0.0
        self.cmd = 0.0
        self.terms = (0.0, 0.0, 0.0)

    def set_gains(self, gains):
        self.gains = gains

    def compute(self, error, dt, error_dot=None):
        if dt <= 0.0 or not math.isfinite(error):
            return 0.0
        if error_dot is None:
            error_dot = (error - self.p_error_last) / dt
            self.p_error_last = error
        if not math.isfinite(error_dot):
            return 0.0
        g = self.gains
        self.p_error = error
        self.d_error = error_dot
        p_term = g.p * error
        self.i_error += dt * error
        if g.antiwindup and g.i != 0.0:
            lo, hi = sorted((g.i_min / g.i, g.i_max / g.i))
            self.i_error = min(max(self.i_error, lo), hi)
        i_term = g.i * self.i_error
        if not g.antiwindup:
            i_term = min(max(i_term, g.i_min), g.i_max)
        d_term = g.d * error_dot
        self.terms = (p_term, i_term, d_term)
        self.cmd = p_term + i_term + d_term
        return self.cmd
