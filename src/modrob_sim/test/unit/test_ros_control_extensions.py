"""Tier 1: hardware (robotSimType) and controller types that other packages add to the ros_control
emulation, found through ``<export><modrob_sim robot_sim_type=... / controller_type=...
module=.../>`` as Gazebo finds pluginlib classes (here: a package tree that is not built, read by
a real rospkg.RosPack)."""
import sys
import textwrap

import pytest
import rospkg

from modrob_sim.errors import ControllerError
from modrob_sim.gazebo_ros.package_exports import PackageExports
from modrob_sim.ros_control import extensions
from modrob_sim.ros_control.manager import ControllerManager

MODULE = '''
from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.extensions import register_controller_type, register_robot_sim_type


class Probe(Controller):
    TYPE = "ext_fixture/Probe"

    def update(self, t, dt):
        self.pending = t


def make_hw(plugin, model, transmissions, pid_gains, warn):
    return "hardware for %s" % model


register_controller_type(Probe, adapter=lambda plugin, controller: "adapter")
register_robot_sim_type("ext_fixture/ProbeHWSim", make_hw)
'''


@pytest.fixture
def package(tmp_path):
    pdir = tmp_path / "src" / "ext_fixture"
    (pdir / "src" / "ext_fixture").mkdir(parents=True)
    (pdir / "package.xml").write_text(textwrap.dedent("""\
        <?xml version="1.0"?>
        <package format="2"><name>ext_fixture</name><version>0.0.1</version><description>f</description>
          <maintainer email="f@example.org">a</maintainer><license>BSD</license>
          <buildtool_depend>catkin</buildtool_depend>
          <export>
            <modrob_sim robot_sim_type="ext_fixture/ProbeHWSim" module="ext_fixture.types"/>
            <modrob_sim controller_type="ext_fixture/Probe" module="ext_fixture.types"/>
            <modrob_sim controller_type="ext_fixture/Nothing"/>
          </export>
        </package>
        """))
    (pdir / "src" / "ext_fixture" / "__init__.py").write_text("")
    (pdir / "src" / "ext_fixture" / "types.py").write_text(MODULE)
    exports = PackageExports(rospkg.RosPack(ros_paths=[str(tmp_path / "src")]))
    extensions.set_package_exports(exports)
    yield exports
    extensions.set_package_exports(None)
    for m in [m for m in sys.modules if m.startswith("ext_fixture")]:
        del sys.modules[m]
    sys.path[:] = [p for p in sys.path if not p.startswith(str(tmp_path))]
    with extensions._lock:
        extensions._controller_types.pop("ext_fixture/Probe", None)
        extensions._adapters.pop("ext_fixture/Probe", None)
        extensions._sim_types.pop("ext_fixture/ProbeHWSim", None)


def test_type_exports_are_read(package):
    assert [e.module for e in package.type_exports("robot_sim_type", "ext_fixture/ProbeHWSim")] == \
        ["ext_fixture.types"]
    assert package.type_exports("controller_type", "ext_fixture/Nothing") == []   # no module: ignored


def test_robot_sim_type_imported_from_the_export(package):
    factory, why = extensions.robot_sim_type("ext_fixture/ProbeHWSim")
    assert why == "" and factory(None, "m", [], None, None) == "hardware for m"
    factory, why = extensions.robot_sim_type("ext_fixture/Unknown")
    assert factory is None and 'robot_sim_type="ext_fixture/Unknown"' in why


class _HW(object):
    joints, order = {}, []

    def read(self):
        pass

    def write(self, dt):
        pass

    def do_switch(self, start, stop):
        pass


def test_controller_type_loads_through_the_manager(package):
    mgr = ControllerManager(_HW(), "/")
    c = mgr.load("probe", {"type": "ext_fixture/Probe"})
    assert type(c).__name__ == "Probe" and "ext_fixture/Probe" in mgr.list_types()
    assert extensions.adapter_factory("ext_fixture/Probe")(None, c) == "adapter"
    with pytest.raises(ControllerError, match="ext_fixture/Nope.*does not exist"):
        mgr.load("nope", {"type": "ext_fixture/Nope"})
