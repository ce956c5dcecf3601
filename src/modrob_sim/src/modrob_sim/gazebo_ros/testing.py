"""Test support for the node's batches of native steps without ROS (test_native_steps.py,
test_native_trajectory_steps.py): a World with one robot under ros_control and a stand-in for
gazebo_ros_control's plugin, stepped either in Python (World.step) or as the node steps it
(FastSteps: batches of the C loop), so that the two can be compared bit for bit."""
import types

from modrob_sim import physics
from modrob_sim.gazebo_ros.fast_steps import FastSteps
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.native_control import NativeControl
from modrob_sim.ros_control.transmissions import parse_transmissions


class ControlRig(object):
    """``xml`` (a URDF with transmissions) in a World of 1 ms steps, its RobotHWSim and
    ControllerManager, and the plugin stand-in whose before-step hook (:meth:`before`, added by
    :meth:`start`) runs as GazeboRosControlPlugin.before_step: the adapters' ``before_update``,
    the manager's update, the adapters' ``after_update``. Adapters are added in the plugin's order
    with :meth:`adapter`; a joint_state_controller's samples go to ``log`` as
    ("joint_states", t, sample)."""

    def __init__(self, xml, name="arm"):
        self.world = physics.World(time_step=0.001)
        self.model = self.world.add_urdf(name, xml)
        self.hw = RobotHWSim(self.model.joints, parse_transmissions(self.model.source_xml))
        self.mgr = ControllerManager(self.hw, "/" + name)
        self.plugin = types.SimpleNamespace(config=types.SimpleNamespace(control_period=None), hw=self.hw,
                                            manager=self.mgr, adapters={}, _last_update=None)
        self.log = []
        self.jsc = None
        self.fast = None

    def adapter(self, name, **hooks):
        """The adapter of controller ``name`` (NATIVE: the C loop may run its controller)."""
        a = types.SimpleNamespace(NATIVE=True, after_update=lambda t: None)
        a.__dict__.update(hooks)
        self.plugin.adapters[name] = a
        return a

    def joint_state_controller(self, publish_rate=50):
        """A joint_state_controller ("jsc") whose adapter logs its samples."""
        self.jsc = self.mgr.load("jsc", {"type": "joint_state_controller/JointStateController",
                                         "publish_rate": publish_rate})
        self.adapter("jsc", after_update=self._jsc_after_update)
        return self.jsc

    def _jsc_after_update(self, t):
        data, self.jsc.pending = self.jsc.pending, None
        if data is not None:
            self.log.append(("joint_states", t, data))

    def start(self, fast, batch_after_due=lambda: float("inf"), after=None, plugins=None):
        """The step hooks (``after``: the node's after-step work, e.g. its state messages) and, with
        ``fast``, the node's FastSteps with ``batch_after_due`` as its publishers' schedule and the
        due times of ``plugins`` (a PluginHost whose hooks ``after`` calls) as the node's."""
        self.world.add_step_hook(before=self.before, after=after)
        if fast:
            self.nc = NativeControl(self.plugin)
            never = lambda: float("inf")  # noqa: E731
            host = types.SimpleNamespace(native_controls=lambda: (self.nc,),
                                         before_due=plugins.before_due if plugins else never,
                                         after_due=plugins.after_due if plugins else never)
            outputs = types.SimpleNamespace(batch_after_due=batch_after_due, batch_clock=lambda: None,
                                            after_batch=lambda **_kw: None)
            self.fast = FastSteps(self.world, host, types.SimpleNamespace(idle=True), outputs)

    def before(self, t, dt):
        self.plugin._last_update = t
        adapters = list(self.plugin.adapters.values())
        for a in adapters:
            hook = getattr(a, "before_update", None)
            if hook is not None:
                hook(t)
        self.mgr.update(t, dt)
        for a in adapters:
            a.after_update(t)

    def step(self, n, whole=True):
        """``n`` steps, in Python or as the node makes them; returns the steps made (fewer with
        ``whole`` False when a pass ends early, as the node's loop lets it)."""
        if self.fast is None:
            self.world.step(n)
            return n
        return self.fast.step(n, whole=whole)
