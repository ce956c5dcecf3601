"""control_toolbox::Pid with its exact semantics (ROS Noetic, control_toolbox 1.18): the physics
core's (modrob_sim.physics.actuators, where the World's actuators use it), with ros_control's
parameter reading:

* gains ``p`` (required), ``i``, ``d`` (default 0), ``i_clamp`` -> i_max = |i_clamp|,
  i_min = -|i_clamp|, overridden by ``i_clamp_min`` / ``i_clamp_max``; ``antiwindup`` (false).
"""
from modrob_sim.errors import ControllerError
from modrob_sim.physics import actuators
from modrob_sim.physics.actuators import Pid  # noqa: F401 (the contract's name)
from modrob_sim.ros_control.params import Params


class PidGains(actuators.PidGains):
    __slots__ = ()

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
