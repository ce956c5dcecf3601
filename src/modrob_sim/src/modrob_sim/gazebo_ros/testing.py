"""Test support for the node's steps without ROS (test_native_steps.py,
test_native_trajectory_steps.py, test_due_times.py): a World with one robot under ros_control,
its update as gazebo_ros_control's plugin runs it (ros_control.control_loop, with stand-in
adapters), stepped either with every hook called at every step or as the node steps it (the hooks
declare their due times: the World steps natively between them), so that the two can be compared
bit for bit."""
import types

from modrob_sim import physics
from modrob_sim.physics.world import earliest_due
from modrob_sim.ros_control.control_loop import ControlLoop
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.transmissions import parse_transmissions

INF = float("inf")


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
        """The node's step hook: the control loop's before- and after-hooks, ``after`` (the node's
        after-step work, e.g. its state messages) and the after-hooks of ``plugins`` (a
        PluginHost). With ``fast`` the hook declares its due times as the node's does (the control
        loop's, ``batch_after_due`` as its publishers' schedule, the plugins'): the World then
        steps natively between them; without, every hook runs at every step."""
        loop = self.loop

        def after_hook(t, dt):
            loop.after_step(t, dt)
            if plugins is not None:
                plugins.after_step(t, dt)
            if after is not None:
                after(t, dt)
        if not fast:
            loop.every_controller = True        # gazebo_ros_control: every controller, every step
            self.world.add_step_hook(before=loop.before_step, after=after_hook)
            return
        never = lambda: INF  # noqa: E731
        pb, pa = (plugins.before_due, plugins.after_due) if plugins is not None else (never, never)
        self.world.add_step_hook(before=loop.before_step, after=after_hook,
                                 before_due=lambda: earliest_due((pb, loop.before_due)),
                                 after_due=lambda: earliest_due((pa, loop.after_due, batch_after_due)))
        self.fast = True

    def step(self, n):
        """``n`` steps of the World (returns ``n``)."""
        self.world.step(n)
        return n
