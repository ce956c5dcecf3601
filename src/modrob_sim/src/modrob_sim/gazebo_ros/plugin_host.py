"""The plugin host of the /gazebo node: loads the plugins of each spawned model, calls their hooks
from the World's step hooks, resets and shuts them down (the contract: plugin_base, docs/plugins.md).

Pure (no rospy; messages go through the ``modrob_sim`` Python logger, which the node forwards to
rosout). Every method runs in the simulation loop thread, or before it starts / after it stopped.
"""
import collections
import logging
import traceback

from modrob_sim.errors import ModrobError
from modrob_sim.gazebo_ros import plugins
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.physics.world import earliest_due

LOG = logging.getLogger("modrob_sim.gazebo_ros.plugins")

_Loaded = collections.namedtuple("_Loaded", "model_name spec plugin context")


def _overrides(plugin, hook):
    """True when the plugin's class overrides the base's no-op ``hook`` (only those are called,
    so a plugin pays nothing for the hooks it does not use)."""
    return getattr(type(plugin), hook) is not getattr(ModelPlugin, hook)


class PluginHost(object):
    """``call``/``advertise``/``timers`` are handed to every PluginContext (see plugins.PluginContext).
    ``exports`` (a package_exports.PackageExports, or None) finds the plugins that packages export:
    a file name the registry does not know is looked up there and its module imported."""

    def __init__(self, world, node_name, resolve, call=None, advertise=None, timers=None, exports=None,
                 wake=None):
        self.world = world
        self.exports = exports
        self.node_name = node_name
        self.resolve = resolve
        self._call = call
        self._advertise = advertise
        self._timers = timers
        self._wake = wake
        self._loaded = collections.OrderedDict()    # model name -> [_Loaded]
        self._warned = set()
        self._import_failed = set()
        self._before = ()
        self._after = ()
        self._before_due = ()
        self._after_due = ()

    # ---- loading -----------------------------------------------------------------------------
    def load(self, model, spawn_namespace=""):
        """Load every registered plugin of ``model``; an unknown file name is warned about once,
        a plugin that fails to load is logged and skipped (never fatal). Returns the plugins."""
        loaded = []
        for index, spec in enumerate(model.plugins):
            factory = plugins.plugin_factory(spec.filename) or self._exported_factory(model, spec)
            if factory is None:
                if spec.filename not in self._warned:
                    self._warned.add(spec.filename)
                    where = " link '%s'" % spec.link if spec.link else ""
                    LOG.warning("model '%s'%s: plugin %s (%s) is not provided by this simulator; ignored. %s",
                                model.name, where, spec.filename, spec.name, self._searched(spec.filename))
                continue
            ns = spec.robot_namespace or spawn_namespace or ""
            if ns != spec.robot_namespace:
                spec = spec._replace(robot_namespace=ns)
            ctx = plugins.PluginContext(self.world, self.node_name, self.resolve, model.name, ns,
                                        seed=plugins.plugin_seed(self.world.seed, model.name, index, spec),
                                        call=self._call, advertise=self._advertise, timers=self._timers,
                                        wake=self._wake)
            plugin = self._construct(factory, model, spec, ctx)
            if plugin is not None:
                loaded.append(_Loaded(model.name, spec, plugin, ctx))
        self._loaded[model.name] = loaded
        self._rebuild()
        return [item.plugin for item in loaded]

    def _exported_factory(self, model, spec):
        """Import the modules that packages export for this plugin file (once), then ask the
        registry again; None when no package provides it."""
        if self.exports is None:
            return None
        for export in self.exports.plugin_exports(spec.filename):
            if (export.package, export.module) in self._import_failed:
                continue
            error = self.exports.import_module(export)
            if error is not None:
                self._import_failed.add((export.package, export.module))
                self._warned.add(spec.filename)     # said here; no second "not provided" warning
                LOG.error("model '%s': plugin %s not loaded: %s", model.name, spec.filename, error)
                continue
            factory = plugins.plugin_factory(spec.filename)
            if factory is not None:
                return factory
            self._import_failed.add((export.package, export.module))
            self._warned.add(spec.filename)
            LOG.error("model '%s': plugin %s not loaded: package '%s' exports it from module %s, but "
                      "importing that module registered no plugin of that name (it should call "
                      "modrob_sim.gazebo_ros.plugins.register_plugin(\"%s\", <ModelPlugin class>))",
                      model.name, spec.filename, export.package, export.module, export.filename)
        return None

    def _searched(self, filename):
        """Where a plugin file was looked for, and how to provide it (the unknown-plugin warning)."""
        own = ", ".join(plugins.registered_plugins()) or "none"
        text = "Looked among the simulator's plugins (%s)" % own
        if self.exports is None:
            return text + "."
        exported = ", ".join(self.exports.exported_plugins()) or "none"
        text += (" and the <export><modrob_sim filename=... module=.../> of the %d packages on "
                 "ROS_PACKAGE_PATH (%s)" % (self.exports.package_count, exported))
        files = self.exports.plugin_files(filename)
        if files:
            text += ("; %s in an exported plugin_path is a Gazebo C++ plugin, which this simulator "
                     "cannot load" % ", ".join(files))
        elif self.exports.plugin_paths:
            text += " and the exported plugin_path folders (%s)" % ", ".join(self.exports.plugin_paths)
        return text + (". To provide it, write a ModelPlugin in Python (docs/plugins.md) and export it "
                       "from its package.xml: <export><modrob_sim filename=\"%s\" module=\"<pkg>.<module>\"/>"
                       "</export>" % filename)

    def _construct(self, factory, model, spec, ctx):
        what = "model '%s': plugin %s" % (model.name, spec.filename)
        try:
            plugin = factory(model, spec, ctx)
            if not isinstance(plugin, ModelPlugin):
                LOG.error("%s not loaded: its factory returned %s, which is not a "
                          "modrob_sim.gazebo_ros.plugin_base.ModelPlugin (derive the plugin class from "
                          "ModelPlugin or SensorPlugin; docs/plugins.md)", what, type(plugin).__name__)
                return None
            plugin.load(model, spec, ctx)
            return plugin
        except ModrobError as exc:
            LOG.error("%s not loaded: %s", what, exc)
        except Exception as exc:  # noqa: B902 - a faulty plugin must not take the simulator down
            LOG.error("%s raised while loading (a bug in the plugin): %s: %s\n%s", what,
                      type(exc).__name__, exc, traceback.format_exc())
        return None

    def _rebuild(self):
        before, after = [], []
        before_due, after_due = [], []
        for items in self._loaded.values():
            for item in items:
                p = item.plugin
                for hook, hooks, dues in (("before_step", before, before_due),
                                          ("after_step", after, after_due)):
                    if _overrides(p, hook):
                        hooks.append((item, getattr(p, hook)))
                        # its due time (docs/plugins.md, "Due times"); None: every step
                        dues.append(getattr(p, hook.replace("_step", "_due")))
        self._before, self._after = tuple(before), tuple(after)
        self._before_due, self._after_due = tuple(before_due), tuple(after_due)

    def before_due(self):
        """The earliest simulated time from which a plugin's before_step has work (-inf: now;
        a plugin that declares no due time is due at every step)."""
        return earliest_due(self._before_due)

    def after_due(self):
        """The same for after_step."""
        return earliest_due(self._after_due)

    def plugins_of(self, model_name):
        return [item.plugin for item in self._loaded.get(model_name, [])]

    # ---- the World's step hooks ---------------------------------------------------------------
    def before_step(self, t, dt):
        for item, hook in self._before:
            try:
                hook(t, dt)
            except Exception as exc:  # noqa: B902 - disable the plugin, keep simulating
                self._disable(item, "before_step", exc)

    def after_step(self, t, dt):
        for item, hook in self._after:
            try:
                hook(t, dt)
            except Exception as exc:  # noqa: B902 - disable the plugin, keep simulating
                self._disable(item, "after_step", exc)

    def _disable(self, item, hook, exc):
        LOG.error("model '%s': plugin %s failed in %s and is disabled: %s: %s\n%s", item.model_name,
                  item.spec.filename, hook, type(exc).__name__, exc, traceback.format_exc())
        items = self._loaded.get(item.model_name, [])
        self._loaded[item.model_name] = [i for i in items if i is not item]
        self._rebuild()
        self._shutdown_one(item)

    # ---- reset / shutdown ---------------------------------------------------------------------
    def reset(self, reseed):
        """reset_simulation (``reseed`` True: every plugin's rng back to its start) or
        reset_world (False)."""
        for items in self._loaded.values():
            for item in items:
                if reseed:
                    item.context.reseed()
                try:
                    item.plugin.reset()
                except Exception as exc:  # noqa: B902 - the other plugins still reset
                    LOG.error("model '%s': plugin %s failed to reset: %s: %s", item.model_name,
                              item.spec.filename, type(exc).__name__, exc)

    def unload(self, model_name):
        """Shut down the plugins of a model (before it leaves the World)."""
        items = self._loaded.pop(model_name, [])
        self._rebuild()
        for item in items:
            self._shutdown_one(item)

    def shutdown(self):
        for name in list(self._loaded):
            self.unload(name)

    @staticmethod
    def _shutdown_one(item):
        try:
            item.plugin.shutdown()
        except Exception as exc:  # noqa: B902 - the other plugins still shut down
            LOG.error("model '%s': plugin %s failed to shut down: %s: %s", item.model_name,
                      item.spec.filename, type(exc).__name__, exc)
