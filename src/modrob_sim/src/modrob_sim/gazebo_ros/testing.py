"""Test support for the node's steps without ROS (test_native_steps.py,
test_native_trajectory_steps.py, test_due_times.py): a World with one robot under ros_control,
its update as gazebo_ros_control's plugin runs it (ros_control.control_loop, with stand-in
adapters), stepped either in Python at every step (World.step, every hook called) or as the node
steps it (FastSteps: batches of the C loop between the due times), so that the two can be
compared bit for bit."""
import types

from modrob_sim import physics
from modrob_sim.gazebo_ros.fast_steps import FastSteps
from modrob_sim.ros_control.control_loop import ControlLoop
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.transmissions import parse_transmissions

INF = float("inf")


def _earliest(*fns):
    due = INF
    for f in fns:
        d = f()
        if d is None:
            return -INF
        due = min(due, d)
    return due


class ControlRig(object):
    """``xml`` (a URDF with transmissions) in a World of 1 ms steps (the pure-Python backend with
    ``native`` False), its RobotHWSim and ControllerManager on the World's actuators, and the
    ControlLoop of gazebo_ros_control's plugin. Adapters are added in the plugin's order with
    :meth:`adapter`; a joint_state_controller's samples go to ``log`` as ("joint_states", t,
    sample)."""

    def __init__(self, xml, name="arm", native=None):
        self.world = physics.World(time_step=0.001, native=native)
        self.model = self.world.add_urdf(name, xml)
        self.hw = RobotHWSim(self.model.joints, parse_transmissions(self.model.source_xml), world=self.world)
        self.mgr = ControllerManager(self.hw, "/" + name)
        self.adapters = {}
        self.loop = ControlLoop(self.hw, self.mgr, self.adapters, self.world)
        self.log = []
        self.jsc = None
        self.fast = None

    def adapter(self, name, **hooks):
        """The stand-in adapter of controller ``name``."""
        a = types.SimpleNamespace(before_update=lambda t: None, after_update=lambda t: None,
                                  waiting=lambda: False)
        a.__dict__.update(hooks)
        self.adapters[name] = a
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

    def start(self, fast, batch_after_due=lambda: INF, after=None, plugins=None):
        """The step hooks (``after``: the node's after-step work, e.g. its state messages, and
        the control loop's) and, with ``fast``, the node's FastSteps with ``batch_after_due`` as
        its publishers' schedule and the due times of ``plugins`` (a PluginHost whose hooks
        ``after`` calls) and of the control loop as the node's."""
        loop = self.loop

        def after_hook(t, dt):
            loop.after_step(t, dt)
            if after is not None:
                after(t, dt)
        self.world.add_step_hook(before=loop.before_step, after=after_hook)
        if fast:
            never = lambda: INF  # noqa: E731
            pb, pa = (plugins.before_due, plugins.after_due) if plugins is not None else (never, never)
            host = types.SimpleNamespace(before_due=lambda: _earliest(pb, loop.before_due),
                                         after_due=lambda: _earliest(pa, loop.after_due))
            outputs = types.SimpleNamespace(batch_after_due=batch_after_due, batch_clock=lambda: None,
                                            after_batch=lambda **_kw: None)
            self.fast = FastSteps(self.world, host, types.SimpleNamespace(idle=True), outputs)

    def step(self, n, whole=True):
        """``n`` steps, in Python or as the node makes them; returns the steps made (fewer with
        ``whole`` False when a pass ends early, as the node's loop lets it)."""
        if self.fast is None:
            self.world.step(n)
            return n
        return self.fast.step(n, whole=whole)
