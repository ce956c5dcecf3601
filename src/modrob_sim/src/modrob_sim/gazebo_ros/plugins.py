"""The plugin registry of the /gazebo node (docs/design/sim_core_api.md, "Plugins").

A plugin module registers a factory for a Gazebo plugin file name::

    from modrob_sim.gazebo_ros.plugins import register_plugin
    register_plugin("libgazebo_ros_control.so", factory)

and the node calls ``factory(model, spec, context)`` for every ``<plugin filename=...>`` of every
spawned model. The node imports the registering modules listed in :data:`PLUGIN_MODULES` (and in
its ``~plugin_modules`` parameter). This module is pure: no rospy, so plugins and tests can import
it anywhere.
"""
import importlib
import logging
import threading

#: Modules imported by the node so that they register their plugin factories. A module that fails
#: to import is logged with its error and skipped.
PLUGIN_MODULES = [
    "modrob_sim.ros_control.plugin",
]

_log = logging.getLogger(__name__)
_registry = {}
_registry_lock = threading.Lock()


def register_plugin(filename, factory):
    """Register ``factory(model, spec, context) -> plugin`` for a plugin file name such as
    ``libgazebo_ros_control.so``. Registering the same name again replaces the factory."""
    if not filename or not isinstance(filename, str):
        raise ValueError("register_plugin: filename must be a non-empty string, got %r" % (filename,))
    if not callable(factory):
        raise ValueError("register_plugin(%r): factory must be callable" % filename)
    with _registry_lock:
        _registry[filename] = factory


def unregister_plugin(filename):
    """Forget a factory (tests)."""
    with _registry_lock:
        _registry.pop(filename, None)


def plugin_factory(filename):
    """The factory registered for ``filename``, or None. Also matches without a ``lib`` prefix or
    ``.so`` suffix so that ``gazebo_ros_control`` finds ``libgazebo_ros_control.so``."""
    with _registry_lock:
        if filename in _registry:
            return _registry[filename]
        base = filename
        if base.startswith("lib"):
            base = base[3:]
        if base.endswith(".so"):
            base = base[:-3]
        for name, factory in _registry.items():
            other = name[3:] if name.startswith("lib") else name
            other = other[:-3] if other.endswith(".so") else other
            if other == base:
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


class PluginContext(object):
    """What a plugin factory gets besides the model and its spec.

    world        the physics World (use it only from update()/after_step(), in the loop thread)
    node_name    "/gazebo" (or the gazebo namespace)
    resolve      callable(uri) -> absolute path (package://, file://, model:// and plain paths)
    model_name   the name of the model the plugin belongs to
    robot_namespace  the namespace the plugin should use (its <robotNamespace>, else the spawn one)
    """

    def __init__(self, world, node_name, resolve, model_name="", robot_namespace=""):
        self.world = world
        self.node_name = node_name
        self.resolve = resolve
        self.model_name = model_name
        self.robot_namespace = robot_namespace
