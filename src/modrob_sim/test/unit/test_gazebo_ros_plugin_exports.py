"""Tier 1: plugins found as Gazebo finds them, through what packages export.

A package makes a Python plugin module known by ``<export><modrob_sim filename="libX.so"
module="pkg.module"/>``; the node's plugin host imports that module when a model first names the
file (also from a package that is not built: its ``src/`` folder). ``<export><gazebo_ros
plugin_path gazebo_model_path gazebo_media_path/>`` are read with ``${prefix}`` as rospack does.
An unknown plugin is warned about once, naming the model, the file and where it was looked for.
Packages are real package trees in a temporary folder, read by a real rospkg.RosPack.
"""
import importlib.util
import logging
import os
import sys

import pytest
import rospkg

from modrob_sim.gazebo_ros import plugins
from modrob_sim.gazebo_ros.package_exports import PackageExports
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.physics import World

_FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
_spec = importlib.util.spec_from_file_location("package_trees", os.path.join(_FIXTURES, "package_trees.py"))
package_trees = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(package_trees)
make_package = package_trees.make_package

MODULE = '''
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin

LOADED = []


class Counter(ModelPlugin):
    def load(self, model, spec, context):
        self.steps = 0
        LOADED.append(self)

    def before_step(self, t, dt):
        self.steps += 1


register_plugin("{filename}", Counter)
'''


URDF = """<robot name="r"><link name="base"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <gazebo><plugin name="p" filename="%s"/></gazebo></robot>"""


@pytest.fixture
def tree(tmp_path, request):
    """Packages named after the test (so that modules never collide in sys.modules)."""
    tag = request.node.name.replace("[", "_").replace("]", "").replace("-", "_")[:40]
    root = str(tmp_path / "ws" / "src")
    os.makedirs(root)
    added = []
    yield root, tag, added
    for filename in added:
        plugins.unregister_plugin(filename)
    for mod in [m for m in sys.modules if m.startswith("pkg_" + tag)]:
        del sys.modules[mod]
    sys.path[:] = [p for p in sys.path if not p.startswith(str(tmp_path))]


def host_for(root):
    world = World(time_step=0.001)
    exports = PackageExports(rospkg.RosPack(ros_paths=[root]))
    host = PluginHost(world, "/gazebo", lambda uri: uri, exports=exports)
    world.add_step_hook(before=host.before_step, after=host.after_step)
    return world, host, exports


def test_exports_are_read_with_prefix_and_only_existing_folders(tree):
    root, tag, _ = tree
    pdir = make_package(root, "pkg_%s_a" % tag,
                        '<modrob_sim filename="liba_one.so" module="pkg_%s_a.one"/>'
                        '<modrob_sim plugin="a_two" module="pkg_%s_a.two"/>'   # the older spelling
                        '<gazebo_ros gazebo_model_path="${prefix}/models" plugin_path="${prefix}/lib"/>'
                        '<gazebo_ros gazebo_media_path="${prefix}"/>'
                        '<gazebo_ros gazebo_model_path="${prefix}/not_there"/>' % (tag, tag))
    os.makedirs(os.path.join(pdir, "models"))
    os.makedirs(os.path.join(pdir, "lib"))
    make_package(root, "pkg_%s_b" % tag, "")
    exports = PackageExports(rospkg.RosPack(ros_paths=[root]))
    assert exports.model_paths == [os.path.join(pdir, "models")]
    assert exports.plugin_paths == [os.path.join(pdir, "lib")]
    assert exports.media_paths == [pdir]
    assert exports.exported_plugins() == ["a_two", "liba_one.so"]
    # the file name is matched as Gazebo matches it: lib prefix and .so suffix optional
    assert [e.module for e in exports.plugin_exports("libone.so")] == []
    assert [e.module for e in exports.plugin_exports("a_one")] == ["pkg_%s_a.one" % tag]
    assert [e.module for e in exports.plugin_exports("liba_two.so")] == ["pkg_%s_a.two" % tag]
    assert exports.package_count == 2


def test_an_export_without_module_or_a_bad_package_xml_is_warned_about_naming_the_package(tree, caplog):
    root, tag, _ = tree
    make_package(root, "pkg_%s_c" % tag, '<modrob_sim filename="libc.so"/>')
    bad = make_package(root, "pkg_%s_c2" % tag, '<modrob_sim filename="libc2.so" module="x.y"/>')
    with open(os.path.join(bad, "package.xml")) as f:
        text = f.read()
    with open(os.path.join(bad, "package.xml"), "w") as f:
        f.write(text.replace("fixture@example.org", "not an address"))
    with caplog.at_level(logging.WARNING):
        assert PackageExports(rospkg.RosPack(ros_paths=[root])).exported_plugins() == []
    assert "package 'pkg_%s_c'" % tag in caplog.text and "needs both attributes" in caplog.text
    assert "package 'pkg_%s_c2': its package.xml cannot be read" % tag in caplog.text


def test_an_exported_plugin_of_an_unbuilt_package_is_imported_when_a_model_names_it(tree):
    root, tag, added = tree
    filename = "lib%s_counter.so" % tag
    added.append(filename)
    pkg = "pkg_%s_d" % tag
    make_package(root, pkg, '<modrob_sim filename="%s" module="%s.counter"/>' % (filename, pkg),
                 {"counter": MODULE.format(filename=filename)})
    world, host, _ = host_for(root)
    assert plugins.plugin_factory(filename) is None         # nothing imported before a model needs it
    loaded = host.load(world.add_urdf("r", URDF % filename))
    assert len(loaded) == 1 and type(loaded[0]).__name__ == "Counter"
    assert pkg + ".counter" in sys.modules
    world.step(5)
    assert loaded[0].steps == 5
    # a second model naming it does not import again, and gets its own instance
    loaded2 = host.load(world.add_urdf("r2", URDF % filename))
    assert len(loaded2) == 1 and loaded2[0] is not loaded[0]
    world.close()


def test_an_unknown_plugin_is_warned_once_naming_model_file_and_where_it_looked(tree, caplog):
    root, tag, _ = tree
    pdir = make_package(root, "pkg_%s_e" % tag,
                        '<gazebo_ros plugin_path="${prefix}/lib"/>'
                        '<modrob_sim filename="libsomething_else.so" module="pkg_%s_e.x"/>' % tag)
    os.makedirs(os.path.join(pdir, "lib"))
    open(os.path.join(pdir, "lib", "libgazebo_ros_cpp_only.so"), "w").close()
    world, host, _ = host_for(root)
    with caplog.at_level(logging.WARNING):
        assert host.load(world.add_urdf("r", URDF % "libnowhere.so")) == []
        assert host.load(world.add_urdf("r2", URDF % "libnowhere.so")) == []
        assert host.load(world.add_urdf("r3", URDF % "libgazebo_ros_cpp_only.so")) == []
    nowhere = [r.getMessage() for r in caplog.records if "libnowhere.so" in r.getMessage()]
    assert len(nowhere) == 1
    text = nowhere[0]
    assert "model 'r'" in text and "is not provided by this simulator" in text
    assert "1 packages on ROS_PACKAGE_PATH (libsomething_else.so)" in text
    assert os.path.join(pdir, "lib") in text                         # the plugin_path it looked in
    assert '<export><modrob_sim filename="libnowhere.so" module=' in text   # how to provide it
    cpp = [r.getMessage() for r in caplog.records if "libgazebo_ros_cpp_only.so (p)" in r.getMessage()]
    assert len(cpp) == 1 and "is a Gazebo C++ plugin, which this simulator cannot load" in cpp[0]
    world.close()


def test_an_export_whose_module_fails_or_registers_nothing_is_an_error_naming_it(tree, caplog):
    root, tag, _ = tree
    pkg = "pkg_%s_f" % tag
    make_package(root, pkg, '<modrob_sim filename="libbroken.so" module="%s.broken"/>'
                 '<modrob_sim filename="libsilent.so" module="%s.silent"/>' % (pkg, pkg),
                 {"broken": "import no_such_module_anywhere\n", "silent": "X = 1\n"})
    world, host, _ = host_for(root)
    with caplog.at_level(logging.WARNING):
        assert host.load(world.add_urdf("r", URDF % "libbroken.so")) == []
        assert host.load(world.add_urdf("r2", URDF % "libbroken.so")) == []
        assert host.load(world.add_urdf("r3", URDF % "libsilent.so")) == []
    broken = [r.getMessage() for r in caplog.records if "libbroken.so" in r.getMessage()]
    assert len(broken) == 1          # once: not retried, and no second "not provided" warning
    assert "package '%s'" % pkg in broken[0] and "no_such_module_anywhere" in broken[0]
    silent = [r.getMessage() for r in caplog.records if "libsilent.so" in r.getMessage()]
    assert len(silent) == 1 and "registered no plugin of that name" in silent[0]
    world.close()


def test_the_registry_wins_over_exports(tree, caplog):
    """A file name already registered (the simulator's own, ~plugin_modules) is never looked up in
    exports: a package exporting the same name from a missing module changes nothing."""
    root, tag, added = tree
    filename = "lib%s_local.so" % tag
    added.append(filename)
    make_package(root, "pkg_%s_g" % tag, '<modrob_sim filename="%s" module="nowhere_at_all.x"/>' % filename)
    namespace = {}
    exec(MODULE.format(filename=filename), namespace)
    world, host, _ = host_for(root)
    with caplog.at_level(logging.WARNING):
        loaded = host.load(world.add_urdf("r", URDF % filename))
    assert len(loaded) == 1 and isinstance(loaded[0], namespace["Counter"])
    assert "nowhere_at_all" not in caplog.text
    assert plugins.plugin_key("/opt/x/libgazebo_ros_control.so") == plugins.plugin_key("gazebo_ros_control")
    world.close()
