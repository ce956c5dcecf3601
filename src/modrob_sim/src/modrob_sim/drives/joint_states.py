"""gazebo_ros_joint_state_publisher (libgazebo_ros_joint_state_publisher.so) without ROS: the
positions and velocities of the joints named in ``<jointName>`` (comma-separated, spaces
ignored) at ``<updateRate>`` (100 Hz by default; 0 = every step)."""
from modrob_sim.errors import PluginError
from modrob_sim.gazebo_ros.plugin_base import RateGate


class JointStates(object):
    def __init__(self, plugin):
        names = [n for n in plugin.param("jointName").replace(" ", "").split(",") if n]
        missing = [n for n in names if n not in plugin.model.joints]
        if missing or not names:
            raise PluginError("%s: <jointName> %s (joints of the model: %s)"
                              % (plugin.name, "names no joint" if not names else
                                 "names joints the model does not have: %s" % ", ".join(missing),
                                 ", ".join(sorted(plugin.model.joints))))
        self.joints = [plugin.model.joints[n] for n in names]
        rate = plugin.param("updateRate", 100.0, float)
        if rate < 0:
            raise PluginError("%s: <updateRate> must not be negative, got %r" % (plugin.name, rate))
        self.gate = RateGate(rate)

    def reset(self):
        self.gate.reset()

    def update(self, t):
        """[(name, position, velocity)] when due at simulated time ``t``, else None."""
        if not self.gate.due(t):
            return None
        return [(j.name, j.position, j.velocity) for j in self.joints]
