"""Tier 1: the simulator runs the exported camera renderer only while a camera is subscribed.

The rule (Demand), the export (``<export><modrob_sim camera_renderer="..."/>`` read by a real
rospkg over package trees in a temporary folder) and the process manager with stand-ins for the
cameras' publishers (their subscriber counts) and a real child process (a Python script that waits
for its signal) in place of the renderer.
"""
import importlib.util
import logging
import os
import subprocess
import sys
import threading
import time

import pytest
import rospkg

from modrob_sim.camera.renderer_process import Demand, RendererProcess, check_display
from modrob_sim.gazebo_ros.package_exports import PackageExports

_FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
_spec = importlib.util.spec_from_file_location("package_trees", os.path.join(_FIXTURES, "package_trees.py"))
package_trees = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(package_trees)
make_package = package_trees.make_package


# ---- the rule ----------------------------------------------------------------------------------
def test_started_only_when_a_camera_is_subscribed():
    d = Demand(idle_stop=10.0)
    assert d.update(0.0, 1, False) is None          # a camera, nobody listens: nothing runs
    assert d.update(5.0, 0, True) is None           # no camera
    assert d.update(6.0, 1, True) == "start"
    assert d.update(6.5, 1, True) is None
    assert d.update(10.0, 1, False) is None         # unsubscribed, not idle long enough
    assert d.update(16.4, 1, False) is None
    assert d.update(16.5, 1, False) == "stop"       # 10 s after the last subscriber
    assert d.update(20.0, 1, True) == "start"
    assert d.update(20.5, 0, True) == "stop"        # the last camera deleted: at once


def test_idle_stop_zero_keeps_it_while_cameras_exist():
    d = Demand(idle_stop=0.0)
    assert d.update(0.0, 2, True) == "start"
    assert d.update(1000.0, 2, False) is None
    assert d.update(1001.0, 0, False) == "stop"


def test_a_renderer_that_ended_is_started_again_when_wanted():
    d = Demand()
    assert d.update(0.0, 1, True) == "start"
    d.exited()
    assert d.update(0.5, 1, True) == "start"


@pytest.mark.parametrize("value", ["", ":0", ":99.0", "localhost:10.0"])
def test_display_choices(value):
    assert check_display(value) == value


@pytest.mark.parametrize("value", ["own", "mine", "0"])
def test_bad_display_is_refused_by_name(value):
    with pytest.raises(ValueError, match=r"~render_display .*private Xvfb.*':0'"):
        check_display(value)


# ---- the export --------------------------------------------------------------------------------
def test_camera_renderer_export_is_read(tmp_path, caplog):
    root = str(tmp_path)
    make_package(root, "viz_a", '<modrob_sim camera_renderer="my_renderer"/>'
                                '<modrob_sim filename="libp.so" module="viz_a.p"/>')
    make_package(root, "viz_b", '<modrob_sim camera_renderer="a/b"/>')
    exports = PackageExports(rospkg.RosPack([root]))
    with caplog.at_level(logging.WARNING):
        found = exports.camera_renderers()
    assert [(e.package, e.executable) for e in found] == [("viz_a", "my_renderer")]
    assert [e.module for e in exports.plugin_exports("libp.so")] == ["viz_a.p"]
    assert "viz_b" in caplog.text and "needs the name of an executable" in caplog.text
    assert "needs both" not in caplog.text          # a renderer export is not a plugin export


# ---- the process manager -----------------------------------------------------------------------
class FakePublisher(object):
    """A camera output topic's publisher: ``subscribers`` is its connection count."""

    def __init__(self):
        self.subscribers = 0
        self.calls = 0

    def get_num_connections(self):
        self.calls += 1
        return self.subscribers


class FakeExports(object):
    def __init__(self, entries):
        self.entries = entries

    def camera_renderers(self):
        return self.entries


def _wait(cond, timeout=10.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        time.sleep(0.01)
    return cond()


@pytest.fixture
def renderer(tmp_path):
    """A RendererProcess whose 'renderer' is a Python child that writes its argv and waits."""
    script = tmp_path / "renderer.py"
    script.write_text("import sys, json, signal, time\n"
                      "signal.signal(signal.SIGINT, lambda *a: sys.exit(0))\n"
                      "open(sys.argv[1] + '.tmp', 'w').write(json.dumps(sys.argv[2:]))\n"
                      "import os; os.rename(sys.argv[1] + '.tmp', sys.argv[1])\n"
                      "while True: time.sleep(0.05)\n")
    out = tmp_path / "argv.json"
    started = []

    def popen(argv, env):
        # returns once the child has its SIGINT handler (a SIGINT before that would find it ignored
        # when the tests run in a background job): as a real renderer, it is up when it answers
        started.append((argv, env.get("ROS_NAMESPACE")))
        if out.exists():
            out.unlink()
        child = subprocess.Popen([sys.executable, str(script), str(out)] + argv[1:])
        _wait(lambda: out.exists() or child.poll() is not None, 60.0)
        return child

    from modrob_sim.gazebo_ros.package_exports import RendererExport
    pubs = [FakePublisher(), FakePublisher()]
    proc = RendererProcess("/sim/gazebo", FakeExports([RendererExport("camera_renderer", "viz")]),
                           lambda pkg, name: "/bin/%s" % name, idle_stop=0.3, popen=popen, poll=0.02)
    yield proc, pubs, started, out
    proc.shutdown()


def test_no_subscriber_no_process(renderer):
    proc, pubs, started, _out = renderer
    proc.register("m__cam", pubs)
    assert _wait(lambda: pubs[0].calls >= 5)
    assert started == [] and proc.child is None


def test_subscriber_starts_it_idle_stops_it(renderer):
    proc, pubs, started, out = renderer
    proc.register("m__cam", pubs)
    pubs[1].subscribers = 1
    assert _wait(lambda: proc.child is not None and out.exists())
    argv, ns = started[0]
    assert ns == "/sim"
    assert "__name:=gazebo_camera_renderer" in argv
    assert "_sensors_param:=/sim/gazebo/camera_sensors" in argv
    assert not any(a.startswith("_display:=") for a in argv)       # the renderer's private Xvfb
    child = proc.child
    pubs[1].subscribers = 0
    assert _wait(lambda: proc.child is None and child.poll() is not None)
    assert child.returncode == 0                    # ended by its SIGINT, in order
    pubs[0].subscribers = 2
    assert _wait(lambda: proc.child is not None)
    assert proc.starts == 2


def test_last_camera_deleted_stops_it(renderer):
    proc, pubs, _started, _out = renderer
    proc.register("m__cam", pubs[:1])
    pubs[0].subscribers = 1
    assert _wait(lambda: proc.child is not None)
    child = proc.child
    proc.unregister("m__cam")
    assert _wait(lambda: child.poll() is not None)


def test_shutdown_stops_it(renderer):
    proc, pubs, _started, _out = renderer
    proc.register("m__cam", pubs[:1])
    pubs[0].subscribers = 1
    assert _wait(lambda: proc.child is not None)
    child = proc.child
    proc.shutdown()
    assert child.poll() is not None
    assert not any(t.name == "camera_renderer_process" and t.is_alive() for t in threading.enumerate())


def test_no_exported_renderer_is_said_once(caplog):
    pub = FakePublisher()
    pub.subscribers = 1
    proc = RendererProcess("/gazebo", FakeExports([]), lambda pkg, name: None, poll=0.02)
    try:
        with caplog.at_level(logging.WARNING, logger="modrob_sim.camera"):
            proc.register("m__cam", [pub])
            assert _wait(lambda: pub.calls >= 5)
    finally:
        proc.shutdown()
    assert caplog.text.count("exports a camera renderer") == 1
    assert proc.child is None
