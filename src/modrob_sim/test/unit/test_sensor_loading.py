"""Tier 1: sensor plugins through the /gazebo plugin host (no ROS master): an unknown sensor plugin
file is warned about once naming model, link and file and the model still spawns; a malformed
sensor parameter is refused with a message naming the element and the value."""
import importlib.util
import logging
import os

import pytest

from modrob_sim.gazebo_ros import plugins
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.physics import World

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)

rospy = pytest.importorskip("rospy")


@pytest.fixture
def host():
    from modrob_sim.sensors import ros_plugins
    for name, cls in ros_plugins.PLUGINS.items():      # (other tests may have cleared the registry)
        plugins.register_plugin(name, cls)
    w = World(seed=1)
    return PluginHost(w, "/gazebo", lambda uri: uri)


def test_unknown_sensor_plugin_is_warned_once_with_model_link_and_file(host, caplog):
    caplog.set_level(logging.WARNING)
    xml = F.sensor_robot(F.laser_sensor(plugin="libgazebo_ros_fancy_laser.so", samples=10))
    m1 = host.world.add_urdf("bot", xml)
    assert host.load(m1) == []
    m2 = host.world.add_urdf("bot2", xml.replace('name="bot"', 'name="bot2"'))
    host.load(m2)
    lines = [r.getMessage() for r in caplog.records if "libgazebo_ros_fancy_laser.so" in r.getMessage()]
    assert len(lines) == 1
    assert "model 'bot'" in lines[0] and "link 'sensor_link'" in lines[0]
    assert "bot" in host.world.models and "bot2" in host.world.models


@pytest.mark.parametrize("bad, element, value", [
    ("<samples>abc</samples>", "samples", "abc"),
    ("<max>-5</max>", "range/max", "-5"),
])
def test_malformed_sensor_parameter_names_element_and_value(host, caplog, bad, element, value):
    caplog.set_level(logging.ERROR)
    xml = F.sensor_robot(F.laser_sensor(samples=10, rmax=10.0))
    old = "<samples>10</samples>" if "samples" in bad else "<max>10.0</max>"
    xml = xml.replace(old, bad)
    m = host.world.add_urdf("bot", xml)
    assert host.load(m) == []
    text = caplog.text
    assert element in text and value in text and "sensor_link" in text and "libgazebo_ros_laser.so" in text


class FakePub(object):
    """Stands in for context.advertise's PluginPublisher: records what is published."""

    def __init__(self, topic):
        self.name = topic
        self.has_subscribers = False
        self.sent = []

    def publish(self, msg):
        self.sent.append(msg)

    def publish_later(self, build):
        self.sent.append(build())

    def unregister(self):
        pass


def test_sensors_cost_nothing_without_subscribers_and_run_at_their_rate():
    pubs = {}

    def advertise(topic, msg_class, queue_size=1, latch=False):
        pubs[topic] = FakePub(topic)
        return pubs[topic]

    from modrob_sim.sensors import ros_plugins
    for name, cls in ros_plugins.PLUGINS.items():
        plugins.register_plugin(name, cls)
    w = World(seed=1)
    w.add_sdf(F.GROUND)
    host = PluginHost(w, "/gazebo", lambda uri: uri, advertise=advertise)
    w.add_step_hook(after=host.after_step)
    m = w.add_urdf("bot", F.sensor_robot(F.laser_sensor(topic="scan", samples=90, rate=20)))
    (laser,) = host.load(m)
    casts = []
    real_prepare = laser.ray.caster.prepare     # every scan's cast starts here (RaySensor.prepare_scan)
    laser.ray.caster.prepare = lambda *a, **k: casts.append(1) or real_prepare(*a, **k)
    w.step(500)                       # 0.5 s, nobody listening: no ray is cast
    assert casts == [] and pubs["/scan"].sent == []
    pubs["/scan"].has_subscribers = True
    w.step(500)                       # 0.5 s at 20 Hz: 10 scans
    assert len(casts) == 10 and len(pubs["/scan"].sent) == 10
    msg = pubs["/scan"].sent[-1]
    assert msg.header.frame_id == "sensor_link" and len(msg.ranges) == 90
