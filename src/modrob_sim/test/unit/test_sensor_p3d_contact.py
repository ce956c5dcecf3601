"""Tier 1: gazebo_ros_p3d ground truth and the contact sensor (gazebo_ros_bumper's data)."""
import importlib.util
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from modrob_sim.physics import World
from modrob_sim.physics.transforms import quat_from_rpy, quat_mul
from modrob_sim.sensors.contact import ContactSensor
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.p3d import P3d

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)


def p3d(params, pose=((1.0, -2.0, 3.0), (0, 0, 0, 1)), seed=1):
    w = World(seed=seed)
    m = w.add_urdf("bot", F.sensor_robot("", static=False), pose=pose)
    for ln in m.links.values():
        ln.gravity_enabled = False
    elem = ET.fromstring("<plugin><bodyName>base_link</bodyName><topicName>gt</topicName>%s</plugin>"
                         % params)
    return w, m, P3d(w, m, elem, "model 'bot' plugin libgazebo_ros_p3d.so", seed=seed)


def test_pose_and_twist_in_the_world():
    q = quat_from_rpy(0.1, 0.2, 0.3)
    w, m, p = p3d("", pose=((1.0, -2.0, 3.0), q))
    m.set_twist(((0.5, 0.0, 0.0), (0.0, 0.0, 0.2)))
    w.step()
    pos, rot, v, om = p.step(w.time)
    lp, lq = m.links["base_link"].pose
    assert np.allclose(pos, lp) and np.allclose(rot, lq)
    lv, lw = m.links["base_link"].twist
    assert np.allclose(v, lv) and np.allclose(om, lw)
    assert p.frame == "world" and p.body == "base_link"


def test_offsets():
    w, m, p = p3d("<xyzOffsets>0 0 1</xyzOffsets><rpyOffsets>0 0 0.5</rpyOffsets>")
    w.step()
    pos, rot, _, _ = p.step(w.time)
    lp, lq = m.links["base_link"].pose
    assert pos[2] == pytest.approx(lp[2] + 1.0)
    assert np.allclose(rot, quat_mul(quat_from_rpy(0, 0, 0.5), lq))


def test_relative_to_a_link():
    w, m, p = p3d("<frameName>sensor_link</frameName>")
    w.step()
    pos, rot, _, _ = p.step(w.time)
    assert np.allclose(pos, (0, 0, -0.15), atol=1e-9)   # base is 0.15 below the sensor link


def test_noise_on_the_twist_only():
    w, m, p = p3d("<gaussianNoise>0.1</gaussianNoise>")
    vx = []
    for _ in range(2000):
        w.step()
        pos, rot, v, _ = p.step(w.time)
        vx.append(v[0])
    assert abs(np.std(vx) - 0.1) < 0.01
    assert p.covariance()[0] == pytest.approx(0.01) and p.covariance()[35] == pytest.approx(0.01)


def test_p3d_errors():
    w = World()
    m = w.add_urdf("bot", F.sensor_robot(""))
    with pytest.raises(SensorConfigError) as e:
        P3d(w, m, ET.fromstring("<plugin><bodyName>base_link</bodyName></plugin>"), "model 'bot' plugin p3d")
    assert "topicName" in str(e.value)
    with pytest.raises(SensorConfigError) as e:
        P3d(w, m, ET.fromstring("<plugin><bodyName>chassis</bodyName><topicName>x</topicName></plugin>"),
            "model 'bot' plugin p3d")
    assert "bodyName" in str(e.value) and "chassis" in str(e.value)


CONTACT = ("<sensor name='plate' type='contact'><update_rate>100</update_rate><contact>"
           "<collision>sensor_link_collision</collision></contact>"
           "<plugin name='b' filename='libgazebo_ros_bumper.so'>"
           "<bumperTopicName>plate_bumper</bumperTopicName><frameName>%s</frameName></plugin></sensor>")


def contact_world(frame="world"):
    w = World(seed=1)
    w.add_sdf(F.GROUND)
    m = w.add_urdf("bot", F.sensor_robot(CONTACT % frame, static=True), pose=((0, 0, 0.1), (0, 0, 0, 1)))
    weight = F.static_shape("weight", F.box((0.1, 0.1, 0.1)), (0.01, 0, 0.33)).replace(
        "<static>true</static>", "").replace("<link name='link'>",
                                             "<link name='link'><inertial><mass>0.5</mass></inertial>")
    w.add_sdf(weight)
    link = m.links["sensor_link"]
    return w, m, ContactSensor(w, m, "sensor_link", link.sensors[0], link.sensors[0].find("plugin"))


def run(w, c, n):
    for _ in range(n):
        w.step()
        c.step(w.time)


def test_a_box_resting_on_the_sensor_link_is_reported():
    w, m, c = contact_world()
    run(w, c, 1500)     # long after the physics would have put the box to sleep
    pairs = c.contacts()
    keys = list(pairs)
    assert ("bot::sensor_link::sensor_link_collision", "weight::link::link_collision") in keys
    pair = pairs[("bot::sensor_link::sensor_link_collision", "weight::link::link_collision")]
    zs = [p[2] for p in pair.positions]
    assert all(abs(z - 0.275) < 0.01 for z in zs)
    # normals point from the weight into the sensor link (down), depths small and positive
    assert all(n[2] < -0.99 for n in pair.normals)
    assert all(0 <= d < 0.01 for d in pair.depths)
    assert c.topic == "plate_bumper" and c.frame == "world"


def test_nothing_reported_before_the_box_lands_and_in_a_link_frame():
    w, m, c = contact_world(frame="sensor_link")
    run(w, c, 1)
    assert not c.contacts()
    run(w, c, 1500)
    pair = list(c.contacts().values())[0]
    assert all(abs(p[2] - 0.025) < 0.01 for p in pair.positions)   # top face of the 5 cm cube
    assert math.isfinite(pair.depths[0])
