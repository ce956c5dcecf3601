"""The plugin contract of the /gazebo node, without ROS: the host loads registered ModelPlugin /
SensorPlugin classes for a real physics World, calls only the hooks a plugin overrides, disables a
plugin that raises, refuses factories that return something else, gives each plugin its own
deterministic random stream (re-seeded on reset_simulation), and plugin parameters and sensor
rates are read with errors that name the model, plugin and tag."""
import os

import pytest

from modrob_sim.errors import PluginError
from modrob_sim.gazebo_ros import plugins
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin, RateGate, SensorPlugin
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.publishing import PluginPublisher, PublishQueue
from modrob_sim.physics import World

HERE = os.path.dirname(os.path.abspath(__file__))

URDF = """<robot name="r">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
  </link>
  <gazebo><plugin name="a" filename="libtest_recorder.so"><topicName>/a</topicName><gain>2.5</gain>
    <bad>x1</bad></plugin></gazebo>
  <gazebo><plugin name="b" filename="libtest_recorder.so"/></gazebo>
  <gazebo><plugin name="c" filename="libtest_unknown.so"/></gazebo>
  <gazebo reference="base"><sensor type="ray" name="scan"><update_rate>100</update_rate>
    <pose>0 0 0.1 0 0 0</pose>
    <plugin name="s" filename="libtest_sensor.so"/></sensor></gazebo>
</robot>"""


class Recorder(ModelPlugin):
    fail_after = None

    def load(self, model, spec, context):
        self.calls = []
        self.draws = [self.rng.random() for _ in range(3)]

    def before_step(self, t, dt):
        self.calls.append(("before", round(t, 6)))
        if self.spec.name == "a" and self.fail_after is not None and len(self.calls) > self.fail_after:
            raise RuntimeError("plugin bug")

    def reset(self):
        self.calls.append(("reset",))
        self.draws = [self.rng.random() for _ in range(3)]

    def shutdown(self):
        self.calls.append(("shutdown",))


class Sensor(SensorPlugin):
    def load(self, model, spec, context):
        self.readings = []

    def sense(self, t):
        self.readings.append(round(t, 6))


@pytest.fixture
def host():
    plugins.register_plugin("libtest_recorder.so", Recorder)
    plugins.register_plugin("libtest_sensor.so", Sensor)
    world = World(time_step=0.001, seed=7)
    h = PluginHost(world, "/gazebo", lambda uri: uri)
    world.add_step_hook(before=h.before_step, after=h.after_step)
    yield h
    plugins.unregister_plugin("libtest_recorder.so")
    plugins.unregister_plugin("libtest_sensor.so")
    world.close()


def spawn(host, name="r", ns="/ns"):
    model = host.world.add_urdf(name, URDF, robot_namespace=ns)
    return host.load(model, ns)


def test_hooks_are_called_in_step_order_and_only_when_overridden(host):
    a, b, s = spawn(host)
    assert isinstance(s, Sensor) and s.link.name == "base" and s.update_rate == 100.0
    assert s.sensor_pose[0] == (0.0, 0.0, 0.1)
    host.world.step(20)
    assert a.calls[:2] == [("before", 0.0), ("before", 0.001)] and len(a.calls) == 20
    # the sensor (after_step at 100 Hz of simulated time) read at t = 0.001 and 0.011
    assert s.readings == [0.001, 0.011]
    assert [item for item, _ in host._before if item.plugin is s] == []
    assert a.context.robot_namespace == "/ns" and a.spec.robot_namespace == "/ns"


def test_a_plugin_that_raises_is_disabled_and_the_others_go_on(host):
    Recorder.fail_after = 3
    try:
        a, b, _ = spawn(host)
        host.world.step(10)
    finally:
        Recorder.fail_after = None
    assert a.calls[-1] == ("shutdown",) and len(a.calls) == 5
    assert host.plugins_of("r")[0] is b and len(host.plugins_of("r")) == 2 and len(b.calls) == 10


def test_random_streams_are_per_plugin_deterministic_and_reseeded(host):
    a, b, _ = spawn(host)
    assert a.draws != b.draws
    other = World(time_step=0.001, seed=7)
    try:
        h2 = PluginHost(other, "/gazebo", lambda uri: uri)
        a2, b2, _ = h2.load(other.add_urdf("r", URDF, robot_namespace="/ns"), "/ns")
        assert (a2.draws, b2.draws) == (a.draws, b.draws)
    finally:
        other.close()
    first = list(a.draws)
    host.reset(reseed=False)
    assert a.draws != first
    host.reset(reseed=True)
    assert a.draws == first and a.calls[-1] == ("reset",)


def test_unload_shuts_down(host):
    a, _, _ = spawn(host)
    host.unload("r")
    assert a.calls[-1] == ("shutdown",) and host.plugins_of("r") == []
    host.world.step(2)
    assert ("before", 0.0) not in a.calls


def test_a_factory_that_returns_no_model_plugin_is_refused(host, caplog):
    plugins.register_plugin("libtest_recorder.so", lambda model, spec, ctx: object())
    loaded = spawn(host)
    assert len(loaded) == 1 and isinstance(loaded[0], Sensor)
    assert "not a modrob_sim.gazebo_ros.plugin_base.ModelPlugin" in caplog.text
    assert "libtest_unknown.so" in caplog.text


def test_params_and_their_errors(host):
    a, b, _ = spawn(host)
    assert a.param("topicName") == "/a" and a.param("gain", cast=float) == 2.5
    assert b.param("topicName", "/default") == "/default"
    with pytest.raises(PluginError, match=r"model 'r': plugin libtest_recorder.so \(a\): <bad>: 'x1'"):
        a.param("bad", cast=float)
    with pytest.raises(PluginError, match="<frameName> is required"):
        b.param("frameName")


def test_a_sensor_plugin_outside_a_sensor_block_is_refused(host, caplog):
    plugins.register_plugin("libtest_recorder.so", Sensor)
    loaded = spawn(host)
    assert len(loaded) == 1
    assert "is a sensor plugin: put it inside a <sensor> block" in caplog.text


def test_rate_gate_keeps_the_period_without_bursts():
    g = RateGate(10.0)
    ticks = [t / 1000.0 for t in range(0, 1001) if g.due(t / 1000.0)]
    assert len(ticks) == 11 and ticks[:3] == [0.0, 0.1, 0.2]
    late = RateGate(10.0)
    assert late.due(0.0) and late.due(0.55) and not late.due(0.6) and late.due(0.65)
    with pytest.raises(PluginError):
        RateGate(float("nan"))


class FakePub(object):
    resolved_name = "/fake"

    def __init__(self):
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)

    def get_num_connections(self):
        return 0


def test_publish_later_builds_off_thread_latest_wins():
    import threading
    queue = PublishQueue()
    try:
        gate, started = threading.Event(), threading.Event()
        pub = PluginPublisher(FakePub(), queue)

        def first():
            started.set()
            gate.wait(5)
            return "first"
        pub.publish_later(first)
        assert started.wait(5)
        for k in range(5):
            pub.publish_later(lambda k=k: "msg%d" % k)
        gate.set()
        for _ in range(500):
            if pub.pub.sent[-1:] == ["msg4"]:
                break
            threading.Event().wait(0.01)
        assert pub.pub.sent[0] == "first" and pub.pub.sent[-1] == "msg4" and pub.dropped == 4
        assert not pub.has_subscribers
    finally:
        queue.stop()
