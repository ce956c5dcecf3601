"""The plugin registry of the /gazebo node (docs/design/sim_core_api.md, "Plugins").

A plugin module registers a factory for a Gazebo plugin file name::

    from modrob_sim.gazebo_ros.plugins import register_plugin
    register_plugin("libgazebo_ros_control.so", factory)

and the node calls ``factory(model, spec, context)`` for every ``<plugin filename=...>`` of every
spawned model, then the plugin's ``load(model, spec, context)``; the plugin is a
:class:`~modrob_sim.gazebo_ros.plugin_base.ModelPlugin` (the contract: docs/plugins.md). The
node imports the registering modules listed in :data:`PLUGIN_MODULES` (and in its
``~plugin_modules`` parameter). This module is pure: no rospy, so plugins and tests can import
it anywhere.
"""
import hashlib
import importlib
import logging
import random
import threading

from modrob_sim.errors import PluginError

#: Modules imported by the node so that they register their plugin factories. A module that fails
#: to import is logged with its error and skipped.
PLUGIN_MODULES = [
    "modrob_sim.ros_control.plugin",
    "modrob_sim.camera.plugin",
    "modrob_sim.sensors.ros_plugins",
    "modrob_sim.drives.ros_plugins",
    "modrob_sim.arm_plugins.mimic_joint",
    "modrob_sim.arm_plugins.grasp_fix",
]

_log = logging.getLogger(__name__)
_registry = {}
_registry_lock = threading.Lock()


def register_plugin(filename, factory):
    """Register ``factory(model, spec, context) -> plugin`` for a plugin file name such as
    ``libgazebo_ros_control.so``; the plugin must be a
    :class:`~modrob_sim.gazebo_ros.plugin_base.ModelPlugin` (a ModelPlugin subclass is itself
    such a factory). Registering the same name again replaces the factory."""
    if not filename or not isinstance(filename, str):
        raise PluginError("register_plugin: filename must be a non-empty string, got %r" % (filename,))
    if not callable(factory):
        raise PluginError("register_plugin(%r): factory must be callable" % filename)
    with _registry_lock:
        _registry[filename] = factory


def unregister_plugin(filename):
    """Forget a factory (tests)."""
    with _registry_lock:
        _registry.pop(filename, None)


def plugin_key(filename):
    """The name a plugin file is known by: ``libfoo.so``, ``foo.so``, ``libfoo`` and ``foo`` (with
    or without a folder) are the same plugin, as Gazebo finds ``libfoo.so`` for each of them."""
    base = (filename or "").replace("\\", "/").rsplit("/", 1)[-1]
    if base.startswith("lib"):
        base = base[3:]
    if base.endswith(".so"):
        base = base[:-3]
    return base


def plugin_factory(filename):
    """The factory registered for ``filename``, or None (names compared by :func:`plugin_key`, so
    ``gazebo_ros_control`` finds ``libgazebo_ros_control.so``)."""
    key = plugin_key(filename)
    with _registry_lock:
        if filename in _registry:
            return _registry[filename]
        for name, factory in _registry.items():
            if plugin_key(name) == key:
                return factory
    return None


def registered_plugins():
    """Sorted list of registered file names."""
    with _registry_lock:
        return sorted(_registry)


def import_plugin_modules(modules=None, on_error=None):
    """Import each module (default :data:`PLUGIN_MODULES`); returns ``(imported, failed)`` where
    failed is a list of ``(module, error_text)``. ``on_error(module, text)`` is called per failure."""
    imported, failed = [], []
    for name in (PLUGIN_MODULES if modules is None else modules):
        try:
            importlib.import_module(name)
        except Exception as exc:  # noqa: B902 - any import failure of a plugin module is reported, not fatal
            text = "%s: %s" % (type(exc).__name__, exc)
            failed.append((name, text))
            if on_error is not None:
                on_error(name, text)
            else:
                _log.warning("plugin module %s not loaded (%s)", name, text)
        else:
            imported.append(name)
    return imported, failed


def plugin_seed(world_seed, model_name, index, spec):
    """The seed of one plugin's random generator: a stable hash (not Python's salted hash()) of
    the world's seed, the model name, the plugin's position among the model's plugins, its file
    name, its name and its sensor's name. Same world seed and model -> same numbers in every run;
    two plugins never share a stream."""
    sensor = spec.sensor.get("name", "") if getattr(spec, "sensor", None) is not None else ""
    key = "%d/%s/%d/%s/%s/%s" % (int(world_seed), model_name, index, spec.filename, spec.name, sensor)
    return int.from_bytes(hashlib.sha256(key.encode("utf-8")).digest()[:8], "little")


class PluginContext(object):
    """What a plugin gets besides its model and spec (see plugin_base and docs/plugins.md).

    world            the physics World: use it only in the plugin's hooks (the loop thread)
    node_name        "/gazebo" (or the gazebo namespace)
    resolve(uri)     absolute path of a package://, file://, model:// or plain path
    model_name       the name of the model the plugin belongs to
    robot_namespace  the plugin's <robotNamespace>, else the namespace the model was spawned with
    seed, rng        this plugin's seed (int) and random.Random(seed); see :func:`plugin_seed`.
                     Make a numpy generator with ``numpy.random.default_rng(context.seed)`` (and
                     again in reset()) if you need arrays of noise
    call(fn, timeout=30.0)   run fn() in the simulation loop thread between two steps and return
                     its result (re-raising its exception); from a ROS callback this is how a
                     plugin reads or changes simulation state. Inside a hook it runs fn at once.
    advertise(topic, msg_class, queue_size=1, latch=False)   a rospy publisher wrapped in a
                     :class:`~modrob_sim.gazebo_ros.publishing.PluginPublisher`: publish(msg) in
                     the hook for small messages; publish_later(build) hands the building and
                     serialisation of a big one to the node's publishing thread. The plugin owns
                     them: unregister them in its shutdown().
    wake()           any thread: a ROS callback stored work for one of the plugin's hooks; the
                     node asks the plugins' due times again after the step in progress, so the
                     hook runs at the next step instead of at its declared due time
    every(period, callback, name)   ``callback(rospy.TimerEvent)`` every ``period`` seconds of
                     simulated time, in the node's publishing thread (a rospy.Timer in simulated
                     time without waking at every step; see sim_timers). Returns a handle with
                     shutdown(), or None when the node does not run on simulated time: then use
                     rospy.Timer.
    """

    def __init__(self, world, node_name, resolve, model_name="", robot_namespace="", seed=0, call=None,
                 advertise=None, timers=None, wake=None):
        self.world = world
        self.node_name = node_name
        self.resolve = resolve
        self.model_name = model_name
        self.robot_namespace = robot_namespace
        self.seed = int(seed)
        self.rng = random.Random(self.seed)
        self._call = call
        self._advertise = advertise
        self._timers = timers
        self._wake = wake

    def wake(self):
        if self._wake is not None:
            self._wake()

    def call(self, fn, timeout=30.0):
        if self._call is None:      # no loop (a unit test drives the plugin itself)
            return fn()
        return self._call(fn, timeout)

    def advertise(self, topic, msg_class, queue_size=1, latch=False):
        if self._advertise is None:
            raise PluginError("model '%s': no ROS publishing in this context (advertise %s)"
                              % (self.model_name, topic))
        return self._advertise(topic, msg_class, queue_size=queue_size, latch=latch)

    def every(self, period, callback, name="timer"):
        if self._timers is None:
            return None
        return self._timers.add(period, callback, name)

    def reseed(self):
        """Back to the start of this plugin's random stream (reset_simulation)."""
        self.rng.seed(self.seed)
