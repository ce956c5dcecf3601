"""The /gazebo node: Gazebo's ROS interface (gazebo_ros_api_plugin) on top of modrob_sim.physics.

This module is the wiring. One thread (:class:`~.sim_loop.SimulationLoop`) owns the World: it
steps it and runs, between steps, the jobs that ROS callbacks hand to it. The World's before-step
hook sets rospy's time, activates wrench jobs, runs the plugins' before_step (read -> controllers
-> write) and adds apply_joint_effort efforts; its after-step hook runs the plugins' after_step
and the node's publishers. The parts:

node_params.Params         ~parameters and gzserver's command line
force_jobs.ForceJobs       timed wrenches and efforts
plugin_host.PluginHost     loads plugins and calls their hooks (contract: plugin_base)
state_publishers           /clock, model/link states, guard events, markers, performance
services.*                 the service groups (models, properties, forces, physics)
"""
import math
import traceback

import rospy

from modrob_sim.errors import ModelError, ModrobError, SimulationError
from modrob_sim.gazebo_ros import native_pub, plugins
from modrob_sim.gazebo_ros.conversions import ros_time
from modrob_sim.gazebo_ros.force_jobs import ForceJobs
from modrob_sim.gazebo_ros import memory_debug
from modrob_sim.gazebo_ros.lookup import Lookup
from modrob_sim.gazebo_ros.node_params import Params, parse_server_args  # noqa: F401 (the node's API)
from modrob_sim.gazebo_ros.package_exports import PackageExports
from modrob_sim.gazebo_ros.physics_reconfigure import PhysicsReconfigure
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.publishing import PublishQueue, ros_advertiser
from modrob_sim.gazebo_ros.resources import ResourceResolver
from modrob_sim.gazebo_ros.rospy_setup import ensure_use_sim_time  # noqa: F401 (the node's API)
from modrob_sim.gazebo_ros.rospy_setup import forward_python_logging, take_over_sim_time
from modrob_sim.gazebo_ros.services.base import Sim
from modrob_sim.gazebo_ros.services.forces import ForceServices
from modrob_sim.gazebo_ros.services.models import ModelServices
from modrob_sim.gazebo_ros.services.physics import PhysicsServices
from modrob_sim.gazebo_ros.services.properties import PropertyServices
from modrob_sim.gazebo_ros.sim_loop import SimulationLoop
from modrob_sim.gazebo_ros.sim_timers import SimTimers
from modrob_sim.gazebo_ros.state_publishers import StatePublishers
from modrob_sim.gazebo_ros.world_file import find_world, world_physics


def set_rostime(stamp, _rt=rospy.rostime):
    """rospy.rostime._set_rostime(stamp) for a rospy.Time, at every step: the same assignment and
    wake-up of rospy.sleep's waiters, without its type checks and its Condition.notifyAll, which
    Python 3.10+ deprecates and so runs warnings.warn at every call (~5 us of a ~130 us step)."""
    _rt._rostime_current = stamp
    cond = _rt._rostime_cond
    with cond:
        cond.notify_all()


def default_world_factory(time_step, gravity, seed, resolver):
    from modrob_sim.physics import World
    return World(time_step=time_step, gravity=gravity, seed=seed, resource_resolver=resolver)


def report_physics_backend(world):
    """One line at start-up when the native physics loop is not in use, with how to get it."""
    from modrob_sim.physics import native
    if native.LIB is not None or not hasattr(world, "native") or world.native:
        return
    text = "physics: pure-Python path (slower; triangle meshes collide as their bounding boxes): %s" % (
        native.REASON or "the native loop is off")
    if native.DISABLED:
        rospy.loginfo(text)
    else:
        rospy.logwarn(text)


class WorldSettings(object):
    """time step, real-time factor and gravity: the ~parameters, else the world file's <physics>
    (else 0.001 s, 1.0, -9.81 z), as Gazebo takes them from the world."""

    def __init__(self, params, resolve):
        self.text, physics = None, {}
        if params.world_name:
            path = find_world(params.world_name, resolve)
            with open(path) as f:
                self.text = f.read()
            physics = world_physics(self.text)
            rospy.loginfo("world file %s" % path)
        self.time_step = params.time_step if params.time_step is not None else physics.get("time_step", 0.001)
        rtf = params.real_time_factor
        if rtf is None:
            rtf = physics.get("real_time_factor", 1.0)
            if physics.get("real_time_update_rate", 1.0) <= 0:
                rtf = 0.0   # Gazebo: update rate 0 = as fast as possible
        self.real_time_factor = rtf
        self.gravity = params.gravity or physics.get("gravity", (0.0, 0.0, -9.81))
        if not (self.time_step > 0 and math.isfinite(self.time_step)):
            raise ModelError("~time_step must be a positive number of seconds, got %r" % self.time_step)


class GazeboRosNode(object):
    """Gazebo's ROS API for a physics World. ``world_factory(time_step, gravity, seed, resolver)``
    builds the World (modrob_sim.physics.World by default)."""

    def __init__(self, params, world_factory=None, node_name=None):
        self.params = params
        self.node_name = node_name or rospy.get_name()
        self.exports = PackageExports()     # what packages export: plugins, model and media paths
        self.resolve = ResourceResolver(exports=self.exports)
        settings = WorldSettings(params, self.resolve)
        self.world = (world_factory or default_world_factory)(
            float(settings.time_step), tuple(settings.gravity), int(params.seed), self.resolve)
        forward_python_logging("modrob_sim")
        report_physics_backend(self.world)
        self._own_sim_time = take_over_sim_time()
        self._rostime_t = None      # the simulated time rospy's clock was last set to (_set_time)
        plugins.import_plugin_modules(plugins.PLUGIN_MODULES + list(params.plugin_modules),
                                      on_error=self._plugin_module_failed)

        if params.native_publishing and native_pub.start(self.node_name):
            rospy.loginfo("%s: publishing through roscpp (node %s_roscpp)" % (self.node_name, self.node_name))
        elif params.native_publishing:
            rospy.logwarn("%s: publishing through rospy (slower): %s" % (self.node_name, native_pub.reason()))
        self.outputs = StatePublishers(self.world, params)   # before any model: first states go out
        self.forces = ForceJobs(self.world)
        self.loop = SimulationLoop(self.world, real_time_factor=settings.real_time_factor,
                                   paused=params.paused, on_rtf=self._on_rtf, on_error=self._on_step_error,
                                   step=self._step)
        self._publish_queue = PublishQueue()
        # timers in simulated time for the node's own ROS helpers, when the node sets rospy's time
        self.timers = SimTimers(self._publish_queue) if self._own_sim_time else None
        self.plugins = PluginHost(self.world, self.node_name, self.resolve, call=self.loop.call,
                                  advertise=ros_advertiser(self._publish_queue), timers=self.timers,
                                  wake=self.world.wake,
                                  exports=self.exports)
        # the node's one step hook, with its due times: the World steps natively in between
        self._hook = self.world.add_step_hook(before=self._before_step, after=self._after_step,
                                              before_due=self._before_due, after_due=self._after_due)
        if settings.text is not None:
            self._load_world_file(settings)
        self.outputs.publish_markers(force=True)
        self.outputs.publish_clock()
        sim = Sim(self.world, self.loop, Lookup(self.world), self.forces, self.outputs, self.plugins)
        self._services = []
        self._physics_services = PhysicsServices(sim)
        self._physics_reconfigure = None
        if params.enable_ros_network:
            groups = (ModelServices(sim), PropertyServices(sim), ForceServices(sim), self._physics_services)
            for group in groups:
                self._services.extend(group.advertise())
        else:
            rospy.loginfo("%s: ~enable_ros_network is false: the /gazebo topics and services are not "
                          "offered (only /clock, and what plugins publish)" % self.node_name)
        debug = memory_debug.advertise(self.node_name)
        if debug is not None:
            self._services.append(debug)
        rtf = settings.real_time_factor
        rospy.loginfo("%s: time step %g s, real-time factor %s, %s, %d models" % (
            self.node_name, settings.time_step, "unlimited" if rtf <= 0 else "%g" % rtf,
            "paused" if params.paused else "running", len(self.world.models)))

    def _load_world_file(self, settings):
        try:
            for m in self.world.add_sdf(settings.text):
                self.plugins.load(m, "")
        except ModrobError as exc:
            raise ModelError("world file %s: %s" % (self.params.world_name, exc))
        # the core applies the world's <physics>; explicit ~time_step / gravity win over it
        self.world.time_step = float(settings.time_step)
        self.world.gravity = tuple(settings.gravity)

    # ---- life cycle ----------------------------------------------------------------------------
    def start(self):
        self.loop.start()
        if self.params.enable_ros_network:
            # /gazebo/set_parameters reads and sets the physics through the loop, so after it runs
            self._physics_reconfigure = PhysicsReconfigure(self._physics_services, self.node_name)

    def shutdown(self):
        """Plugins first, in the loop thread while it still runs (their services go away before
        the loop stops answering), then the loop, then the publishing thread."""
        self.loop.interrupt()       # a long step request ends now, not after its millions of steps
        if self._physics_reconfigure is not None:
            self._physics_reconfigure.shutdown()
        if self.loop.running:
            try:
                self.loop.call(self.plugins.shutdown, timeout=10.0)
            except SimulationError:     # the loop stopped meanwhile (or is stuck): done below
                pass
        if not self.loop.stop():
            # the loop thread is still inside a step: freeing ODE under it at exit would abort the
            # process; leave the memory to the OS instead
            rospy.logwarn("%s: the simulation loop did not stop within 5 s; exiting without freeing "
                          "the physics world" % self.node_name)
            self.world.abandon()
        self.plugins.shutdown()     # no-op when done above
        self._publish_queue.stop()

    # ---- the World's step hooks (loop thread) ----------------------------------------------------
    def _step(self, n):
        """One pass of the simulation loop: up to ``n`` steps of the World, natively up to the
        first stop for a hook (World.advance: the passes fall on the hooks' stops), then the
        states and markers due, what follows the wall clock (a throttled /clock, the scene) and
        rospy's time with the node's timers. Returns the steps made."""
        n = self.world.advance(n)
        if self._own_sim_time:
            self._set_time(self.world.time)
        self.outputs.after_pass()
        return n

    def _before_due(self):
        """The simulated time from which the before-hook has work: the plugins' (controllers)
        and, while force jobs run, every step."""
        if not self.forces.idle:
            return None
        return self.plugins.before_due()

    def _after_due(self):
        """The simulated time from which the after-hook has work: the plugins' (sensors) and the
        publishers' (states, markers; /clock at every step through rospy: every step)."""
        due = self.outputs.after_due()
        if due is None:
            return None
        return min(due, self.plugins.after_due())

    def _set_time(self, t):
        """Simulated time is ``t`` [s] (before a step, or after a batch of steps in C): rospy's
        time, then the timers due by then. rospy's time is set (and its sleepers woken) only when
        it changes: a pass of the loop ends at a stop, where the before-hook of the next pass's
        first step sets the same time again."""
        if t != self._rostime_t:
            self._rostime_t = t
            set_rostime(ros_time(t))
        self.timers.tick(t)

    def _before_step(self, t, dt):
        self.outputs.flush_clock()
        if self._own_sim_time:
            self._set_time(t)
        self.forces.activate_wrenches(t)
        self.plugins.before_step(t, dt)
        self.forces.apply_efforts(t)

    def _after_step(self, t, dt):
        self.outputs.flush_clock()
        self.plugins.after_step(t, dt)
        self.outputs.after_step()

    # ---- reports -------------------------------------------------------------------------------
    def _on_rtf(self, rtf, sim_time):
        self.outputs.publish_rtf(rtf, sim_time, self.loop.paused)

    def _on_step_error(self, exc):
        rospy.logerr("physics step failed, physics paused (call /gazebo/unpause_physics to go on): %s: %s\n%s"
                     % (type(exc).__name__, exc, traceback.format_exc()))

    @staticmethod
    def _plugin_module_failed(module, text):
        if text.startswith("ModuleNotFoundError") and ("'%s'" % module.rsplit(".", 1)[0]) in text or \
                ("'%s'" % module) in text:
            rospy.loginfo("plugin module %s is not available (%s): its plugins will be ignored"
                          % (module, text))
        else:
            rospy.logerr("plugin module %s failed to import, its plugins will be ignored: %s"
                         % (module, text))
