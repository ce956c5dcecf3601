"""What the ROS packages on ROS_PACKAGE_PATH export for Gazebo and for this simulator.

Gazebo's ROS paths plugin asks every package for ``<export><gazebo_ros .../></export>`` and adds
``plugin_path`` to Gazebo's plugin path, ``gazebo_model_path`` to its model path (``model://``) and
``gazebo_media_path`` to its resource path (``worlds/...``, ``file://media/...``), each with
``${prefix}`` replaced by the package's folder. This module reads the same exports, plus the
simulator's own registry of Python plugin modules, and of the ros_control hardware
(``robotSimType``) and controller types that packages add (modrob_sim.ros_control.extensions)::

    <export>
      <modrob_sim filename="libmy_gripper.so" module="my_pkg.gripper_plugin"/>
      <modrob_sim robot_sim_type="my_pkg/MyRobotHWSim" module="my_pkg.hw_sim"/>
      <modrob_sim controller_type="my_pkg/MyController" module="my_pkg.my_controller"/>
      <modrob_sim camera_renderer="my_renderer"/>
      <gazebo_ros gazebo_model_path="${prefix}/models" plugin_path="${prefix}/lib"/>
    </export>

``camera_renderer`` names an executable of the package that renders the camera sensors
(modrob_sim.camera.renderer_process).

Gazebo only asks packages that depend on ``gazebo_ros``; here every package is asked (a Gazebo
project's package.xml still names gazebo_ros, which this machine does not have).

Pure apart from rospkg (no master, no rospy). The packages are read once, when first needed.
"""
import collections
import importlib
import logging
import os
import sys
import threading

import rospkg

from modrob_sim.gazebo_ros.plugins import plugin_key

LOG = logging.getLogger("modrob_sim.gazebo_ros.plugins")

#: the kinds of ros_control types a ``<modrob_sim>`` export may name instead of a plugin file
TYPE_KINDS = ("robot_sim_type", "controller_type")

#: one ``<export><modrob_sim filename=... module=.../>`` entry (filename: or the type's name)
PluginExport = collections.namedtuple("PluginExport", "filename module package package_dir")
#: one ``<export><modrob_sim camera_renderer=.../>`` entry: an executable of ``package``
RendererExport = collections.namedtuple("RendererExport", "executable package")


class PackageExports(object):
    """The exports of every package ``rospack`` finds (``rospack`` injectable for tests).

    plugin_exports(filename)   the PluginExport entries naming that plugin file
    type_exports(kind, name)   the same for a 'robot_sim_type' or 'controller_type' name
    plugin_paths, model_paths, media_paths   folders, in ROS_PACKAGE_PATH order, existing ones only
    exported_plugins()         sorted plugin file names exported by some package
    camera_renderers()         the RendererExport entries, in package name order
    """

    def __init__(self, rospack=None):
        self._rospack = rospack
        self._lock = threading.Lock()
        self._scanned = False
        self._plugins = {}
        self._types = {}        # (kind, type name) -> [PluginExport]
        self._renderers = []
        self._paths = {"plugin_path": [], "gazebo_model_path": [], "gazebo_media_path": []}
        self.package_count = 0

    def _scan(self):
        with self._lock:
            if self._scanned:
                return
            rp = self._rospack or rospkg.RosPack()
            names = rp.list()
            for pkg in sorted(names):
                try:
                    manifest = rp.get_manifest(pkg)
                    pkg_dir = rp.get_path(pkg)
                except Exception as exc:  # noqa: B902 - rospkg or catkin_pkg: one bad package.xml is skipped
                    LOG.warning("package '%s': its package.xml cannot be read, its exports are ignored: %s",
                                pkg, exc)
                    continue
                for exp in manifest.exports:
                    if exp.tag == "modrob_sim" and "camera_renderer" in exp.attrs:
                        self._read_renderer_export(pkg, exp.attrs)
                    elif exp.tag == "modrob_sim":
                        self._read_plugin_export(pkg, pkg_dir, exp.attrs)
                    elif exp.tag == "gazebo_ros":
                        for attr, value in exp.attrs.items():
                            if attr in self._paths:
                                self._add_path(pkg, attr, value.replace("${prefix}", pkg_dir))
            self.package_count = len(names)
            self._scanned = True

    def _read_plugin_export(self, pkg, pkg_dir, attrs):
        for kind in TYPE_KINDS:
            if attrs.get(kind):
                module = attrs.get("module", "").strip()
                if not module:
                    LOG.warning("package '%s': <export><modrob_sim %s=\"%s\"/> needs "
                                "module=\"<pkg>.<module>\" (the Python module that registers it); ignored",
                                pkg, kind, attrs[kind])
                else:
                    self._types.setdefault((kind, attrs[kind].strip()), []).append(
                        PluginExport(attrs[kind].strip(), module, pkg, pkg_dir))
                return
        # "filename" as in <plugin filename=...>; "plugin" is read too, but catkin_lint takes an
        # export with a plugin attribute for a pluginlib description file and refuses it
        filename = (attrs.get("filename") or attrs.get("plugin") or "").strip()
        module = attrs.get("module", "").strip()
        if not filename or not module:
            LOG.warning("package '%s': <export><modrob_sim filename=\"%s\" module=\"%s\"/> needs both "
                        "attributes (filename = the Gazebo plugin file such as libmy_plugin.so, module = "
                        "the Python module that registers it, such as my_pkg.my_plugin); ignored",
                        pkg, filename, module)
            return
        self._plugins.setdefault(plugin_key(filename), []).append(
            PluginExport(filename, module, pkg, pkg_dir))

    def _read_renderer_export(self, pkg, attrs):
        executable = attrs.get("camera_renderer", "").strip()
        if not executable or "/" in executable:
            LOG.warning("package '%s': <export><modrob_sim camera_renderer=\"%s\"/> needs the name of an "
                        "executable of the package (such as camera_renderer); ignored", pkg, executable)
            return
        self._renderers.append(RendererExport(executable, pkg))

    def _add_path(self, pkg, attr, value):
        for entry in value.split(os.pathsep):
            entry = entry.strip()
            if not entry:
                continue
            if not os.path.isdir(entry):
                LOG.debug("package '%s' exports %s %s, which is not a folder; skipped", pkg, attr, entry)
                continue
            if entry not in self._paths[attr]:
                self._paths[attr].append(entry)

    def plugin_exports(self, filename):
        self._scan()
        return list(self._plugins.get(plugin_key(filename), ()))

    def type_exports(self, kind, name):
        self._scan()
        return list(self._types.get((kind, name), ()))

    def exported_plugins(self):
        self._scan()
        return sorted(e.filename for entries in self._plugins.values() for e in entries)

    def camera_renderers(self):
        self._scan()
        return list(self._renderers)

    def import_module(self, export):
        """Import the module of a PluginExport; None, or the error's text (see
        :func:`import_exported_module`)."""
        return import_exported_module(export)

    def plugin_files(self, filename):
        """The files named like plugin ``filename`` in the exported plugin paths (Gazebo's C++
        plugins, which this simulator cannot load)."""
        key = plugin_key(filename)
        found = []
        for d in self.plugin_paths:
            for name in sorted(os.listdir(d)):
                if name.endswith(".so") and plugin_key(name) == key:
                    found.append(os.path.join(d, name))
        return found

    @property
    def plugin_paths(self):
        self._scan()
        return list(self._paths["plugin_path"])

    @property
    def model_paths(self):
        self._scan()
        return list(self._paths["gazebo_model_path"])

    @property
    def media_paths(self):
        self._scan()
        return list(self._paths["gazebo_media_path"])


def import_exported_module(export):
    """Import the module of a PluginExport. A package that is not built yet has its module in
    ``<package>/src`` (catkin's layout): that folder is put on the Python path and the import
    retried. Returns None, or the text of the error (naming the package and what to do)."""
    try:
        importlib.import_module(export.module)
        return None
    except ModuleNotFoundError as exc:
        top = export.module.split(".", 1)[0]
        src = os.path.join(export.package_dir, "src")
        missing_itself = exc.name and (export.module == exc.name or export.module.startswith(exc.name + "."))
        if not missing_itself or not os.path.isdir(os.path.join(src, top)) or src in sys.path:
            return _import_error(export, exc)
        sys.path.append(src)
        try:
            importlib.import_module(export.module)
            return None
        except Exception as exc2:  # noqa: B902 - a faulty plugin module must not stop the simulator
            return _import_error(export, exc2)
    except Exception as exc:  # noqa: B902 - a faulty plugin module must not stop the simulator
        return _import_error(export, exc)


def _import_error(export, exc):
    return ("package '%s' exports %s from Python module %s, which cannot be imported (%s: %s); build "
            "the workspace (catkin_make) or fix the module"
            % (export.package, export.filename, export.module, type(exc).__name__, exc))
