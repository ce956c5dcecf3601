"""The ``<plugin filename="libgazebo_ros_control.so">`` element, read as gazebo_ros_control
(Noetic 2.9) reads it.

* ``robotNamespace``: the controller manager's namespace (default: the model name).
* ``robotSimType``: only ``gazebo_ros_control/DefaultRobotHWSim`` exists here.
* ``legacyModeNS``: Gazebo looks the per-joint gains up at ``/gazebo_ros_control/pid_gains/<joint>``
  when true or absent, at ``<ns>/gazebo_ros_control/pid_gains/<joint>`` when false. We look at
  the Gazebo place first and then at the other, so a YAML that worked in Gazebo works unchanged.
* ``controlPeriod``: controllers update every controlPeriod seconds (default: every step).
"""
from modrob_sim.errors import ModelError

DEFAULT_SIM_TYPE = "gazebo_ros_control/DefaultRobotHWSim"


def _norm_ns(ns):
    ns = (ns or "").strip()
    if not ns or ns == "/":
        return "/"
    return "/" + ns.strip("/")


class PluginConfig(object):
    def __init__(self, robot_namespace, legacy_mode_ns, legacy_mode_given, sim_type, control_period):
        self.robot_namespace = robot_namespace
        self.legacy_mode_ns = legacy_mode_ns
        self.legacy_mode_given = legacy_mode_given
        self.sim_type = sim_type
        self.control_period = control_period

    @classmethod
    def from_element(cls, element, model_name, default_namespace=None):
        """``element``: the <plugin> xml.etree Element (or None). ``default_namespace``: the spawn
        robot_namespace when the plugin has no <robotNamespace> (else the model name)."""
        def text(tag):
            if element is None:
                return None
            child = element.find(tag)
            return child.text.strip() if child is not None and child.text is not None else None

        ns = text("robotNamespace")
        if ns is None:
            ns = default_namespace or model_name
        legacy_text = text("legacyModeNS")
        if legacy_text is None:
            legacy = True
        elif legacy_text.lower() in ("true", "1"):
            legacy = True
        elif legacy_text.lower() in ("false", "0"):
            legacy = False
        else:
            raise ModelError("gazebo_ros_control plugin of model '%s': <legacyModeNS> must be true or false, "
                             "got %r" % (model_name, legacy_text))
        sim_type = text("robotSimType") or DEFAULT_SIM_TYPE
        period_text = text("controlPeriod")
        period = None
        if period_text:
            try:
                period = float(period_text)
            except ValueError:
                raise ModelError("gazebo_ros_control plugin of model '%s': <controlPeriod> %r is not a number"
                                 % (model_name, period_text))
            if not period > 0.0:
                raise ModelError("gazebo_ros_control plugin of model '%s': <controlPeriod> must be > 0"
                                 % model_name)
        return cls(_norm_ns(ns), legacy, legacy_text is not None, sim_type, period)

    def pid_gains_namespaces(self):
        """Where to look for ``gazebo_ros_control/pid_gains``, first match wins."""
        own = (self.robot_namespace.rstrip("/") + "/gazebo_ros_control/pid_gains")
        legacy = "/gazebo_ros_control/pid_gains"
        if own == legacy:
            return [legacy]
        return [legacy, own] if self.legacy_mode_ns else [own, legacy]
