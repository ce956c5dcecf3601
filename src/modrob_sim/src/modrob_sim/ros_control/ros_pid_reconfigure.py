"""Live PID tuning through dynamic_reconfigure, as control_toolbox::Pid offers it (rqt_reconfigure
shows p, i, d, i_clamp_min, i_clamp_max, antiwindup under the PID's namespace, e.g.
``/ptrz/pan_position_controller/pid`` or ``/polaris/gazebo_ros_control/pid_gains/<joint>``).

Debian ships dynamic_reconfigure's Python server but no generated ``ParametersConfig``; the
config description the server needs is built here in Python (the same dict layout the cfg
generator writes)."""
from dynamic_reconfigure.server import Server

from modrob_sim.reconfigure_config import ConfigType, Param, shutdown_server
from modrob_sim.ros_control.pid import PidGains

_DESCR = (("p", "double", "Proportional gain."), ("i", "double", "Integral gain."),
          ("d", "double", "Derivative gain."),
          ("i_clamp_min", "double", "Min bounds for the integral windup"),
          ("i_clamp_max", "double", "Max bounds for the integral windup"),
          ("antiwindup", "bool", "Antiwindup."))


def PidConfigType(gains):
    """The Config type of a PID's dynamic_reconfigure server, ranges wide enough for its gains."""
    big = max(100000.0, 10.0 * max(abs(gains.p), abs(gains.i), abs(gains.d),
                                   abs(gains.i_max), abs(gains.i_min)))
    defaults = {"p": gains.p, "i": gains.i, "d": gains.d, "i_clamp_min": gains.i_min,
                "i_clamp_max": gains.i_max, "antiwindup": gains.antiwindup}
    low = {"p": -big, "i": -big, "d": -big, "i_clamp_min": -big, "i_clamp_max": 0.0, "antiwindup": False}
    high = {"p": big, "i": big, "d": big, "i_clamp_min": 0.0, "i_clamp_max": big, "antiwindup": True}
    return ConfigType([Param(name, kind, defaults[name], low[name], high[name], text)
                       for name, kind, text in _DESCR])


class PidReconfigure(object):
    """A dynamic_reconfigure server at ``namespace`` (absolute) driving ``pid``'s gains.
    ``on_change(gains)`` is called after each change (logging)."""

    def __init__(self, pid, namespace, on_change=None):
        self.pid = pid
        self.on_change = on_change
        ns = namespace if namespace.startswith("/") else "/" + namespace
        self.server = Server(PidConfigType(pid.gains), self._callback, namespace=ns)

    def _callback(self, config, level):
        gains = PidGains(config["p"], config["i"], config["d"], config["i_clamp_max"], config["i_clamp_min"],
                         config["antiwindup"])
        changed = gains.as_dict() != self.pid.gains.as_dict()
        self.pid.set_gains(gains)        # one reference swap: the loop reads either old or new gains
        if changed and self.on_change is not None:
            self.on_change(gains)
        return config

    def shutdown(self):
        shutdown_server(self.server)
