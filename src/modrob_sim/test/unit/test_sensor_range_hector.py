"""Tier 1: the range finders (gazebo_ros_range, hector's sonar, gazebo_ros_block_laser) on the ray
sensor core, and hector's IMU and magnetometer with their error model, on a bare World."""
import importlib.util
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from modrob_sim.physics import World
from modrob_sim.physics.transforms import quat_from_rpy
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.hector import HectorImu, HectorMagnetic
from modrob_sim.sensors.range_sensor import BlockLaser, GazeboRange, HectorSonar
from modrob_sim.sensors.ray_sensor import RaySensor

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)


def cone(samples=5, span=0.2, rmin=0.05, rmax=4.0, v_samples=5):
    """A sonar-like cone of samples x v_samples rays, ``span`` rad wide both ways."""
    return F.ray_block(samples=samples, min_angle=-span / 2, max_angle=span / 2, rmin=rmin, rmax=rmax,
                       v_samples=v_samples, v_min=-span / 2, v_max=span / 2)


def ray_world(plugin_xml, ray_xml, box_at=None, retro=None):
    """A static robot with a ray sensor 0.25 m up looking along x; a 0.4 m cube at ``box_at``."""
    w = World(seed=5)
    w.add_sdf(F.GROUND)
    if box_at is not None:
        w.add_sdf(F.static_shape("target", F.box((0.4, 0.4, 0.4)), (box_at, 0.0, 0.25)))
        if retro is not None:
            w.models["target"].links["link"].extra["laserRetro"] = ET.fromstring(
                "<laserRetro>%r</laserRetro>" % retro)
    sensor = ("<sensor type='ray' name='ranger'><update_rate>10</update_rate>%s%s</sensor>"
              % (ray_xml, plugin_xml))
    m = w.add_urdf("bot", F.sensor_robot(sensor), pose=((0, 0, 0.1), (0, 0, 0, 1)))
    link = m.links["sensor_link"]
    spec = link.sensors[0]
    plugin = spec.find("plugin")
    ray = RaySensor(w, m, "sensor_link", spec, plugin.get("filename"), seed=7)
    return w, ray, plugin


def test_gazebo_range_reads_the_nearest_ray_and_the_maximum_when_nothing_is_hit():
    xml = ("<plugin name='r' filename='libgazebo_ros_range.so'><topicName>sonar_front</topicName>"
           "<frameName>sonar_link</frameName><radiation>infrared</radiation><fov>0.2</fov></plugin>")
    w, ray, plugin = ray_world(xml, cone(), box_at=1.5)
    r = GazeboRange(ray, plugin, "test")
    assert (r.topic, r.frame, r.radiation, r.fov) == ("sonar_front", "sonar_link", "infrared", 0.2)
    assert r.read() == pytest.approx(1.3, abs=0.005)      # the cube's face, the centre ray nearest
    w2, ray2, plugin2 = ray_world(xml, cone(rmax=2.0))       # the lowest rays meet the ground at 2.5 m
    assert GazeboRange(ray2, plugin2, "test").read() == 2.0


def test_gazebo_range_noise_stays_at_most_the_maximum():
    xml = "<plugin name='r' filename='libgazebo_ros_range.so'><gaussianNoise>0.05</gaussianNoise></plugin>"
    w, ray, plugin = ray_world(xml, cone(rmax=1.32), box_at=1.5)
    r = GazeboRange(ray, plugin, "test")
    readings = [r.read() for _ in range(200)]
    assert max(readings) <= 1.32 and min(readings) < 1.25 and (r.topic, r.frame) == ("/range", "/world")


def test_hector_sonar_applies_its_error_model_and_clamps():
    xml = ("<plugin name='s' filename='libhector_gazebo_ros_sonar.so'><topicName>sonar</topicName>"
           "<frameId>sonar_link</frameId><offset>0.1</offset></plugin>")
    w, ray, plugin = ray_world(xml, cone(span=0.3), box_at=1.5)
    s = HectorSonar(ray, plugin, "test")
    assert s.fov == pytest.approx(0.3) and s.rate.period == pytest.approx(0.1)   # 10 Hz default
    assert s.read(0.1) == pytest.approx(1.3 + 0.1, abs=0.01)
    w2, ray2, plugin2 = ray_world(xml, cone(rmax=2.0))
    assert HectorSonar(ray2, plugin2, "test").read(0.1) == 2.0     # nothing hit: max, no offset


def test_block_laser_points_land_on_the_face_and_carry_the_retro_intensity():
    xml = "<plugin name='b' filename='libgazebo_ros_block_laser.so'><topicName>cloud</topicName></plugin>"
    ray_xml = F.ray_block(samples=11, min_angle=-0.5, max_angle=0.5, rmin=0.05, rmax=4.0, v_samples=3,
                          v_min=-0.05, v_max=0.05)
    w, ray, plugin = ray_world(xml, ray_xml, box_at=1.5, retro=200.0)
    points, intensities = BlockLaser(ray, plugin, "test").read()
    assert points.shape == (33, 3) and intensities.shape == (33,)
    on_face = np.abs(points[:, 1]) < 0.15
    assert np.allclose(points[on_face, 0], 1.3, atol=0.005)
    assert np.allclose(intensities[on_face], 200.0)
    far = ~(np.abs(points[:, 1]) < 0.25)
    assert np.allclose(np.linalg.norm(points[far], axis=1), 4.0, atol=1e-5)    # the maximum


def hector_world(plugin_xml, pose=((0, 0, 0.5), (0, 0, 0, 1))):
    w = World(seed=11)
    w.add_sdf(F.GROUND)
    m = w.add_urdf("bot", F.sensor_robot("", static=False), pose=pose)
    return w, m, ET.fromstring(plugin_xml)


def test_hector_imu_at_rest_reads_gravity_up_and_no_rate():
    xml = ("<plugin name='imu' filename='libhector_gazebo_ros_imu.so'><bodyName>base_link</bodyName>"
           "<topicName>imu/data</topicName><updateRate>50</updateRate></plugin>")
    w, m, elem = hector_world(xml, pose=((0, 0, 0.1), (0, 0, 0, 1)))
    imu = HectorImu(w, m, elem, "test", seed=1)
    assert (imu.topic, imu.bias_topic, imu.service, imu.frame_id) == \
        ("imu/data", "imu/data/bias", "imu/data/calibrate", "base_link")
    readings = []
    for _ in range(500):
        w.step(1)
        r = imu.step(w.time)
        if r is not None:
            readings.append(r)
    assert len(readings) == pytest.approx(25, abs=1)          # 50 Hz for 0.5 s
    last = readings[-1]
    assert last.linear_acceleration[2] == pytest.approx(9.81, abs=0.05)
    assert max(abs(x) for x in last.angular_velocity) < 1e-3
    assert last.orientation[3] == pytest.approx(1.0, abs=1e-4)


def test_hector_imu_rate_follows_a_turn_and_the_offsets_bias_it():
    xml = ("<plugin name='imu' filename='libhector_gazebo_ros_imu.so'><rateOffset>0.01 0 0</rateOffset>"
           "<accelOffset>0 0.2 0</accelOffset><yawOffset>0.1</yawOffset></plugin>")
    w, m, elem = hector_world(xml)
    w.gravity = (0.0, 0.0, 0.0)
    imu = HectorImu(w, m, elem, "test", seed=1)
    m.set_twist(((0, 0, 0), (0, 0, 0.5)))
    for _ in range(100):
        w.step(1)
        r = imu.step(w.time)
    assert r.angular_velocity[2] == pytest.approx(0.5, abs=1e-3)
    assert r.angular_velocity[0] == pytest.approx(0.01, abs=1e-6)     # rateOffset
    assert r.accel_bias == pytest.approx((0.0, 0.2, 0.0))
    imu.calibrate()                    # the drift goes; the offset stays
    assert imu.rate.current_drift == [0.0, 0.0, 0.0] and imu.rate.bias == pytest.approx((0.01, 0.0, 0.0))


def test_hector_imu_drift_wanders_and_is_seeded():
    xml = "<plugin name='imu' filename='libhector_gazebo_ros_imu.so'><rateDrift>0.1</rateDrift></plugin>"
    biases = []
    for _ in range(2):
        w, m, elem = hector_world(xml)
        imu = HectorImu(w, m, elem, "test", seed=4)
        for _ in range(200):
            w.step(1)
            imu.step(w.time)
        biases.append(imu.rate.bias)
    assert biases[0] == biases[1] and any(abs(b) > 1e-4 for b in biases[0])


def test_hector_magnetic_field_in_the_world_and_turned_into_the_link():
    xml = ("<plugin name='m' filename='libhector_gazebo_ros_magnetic.so'><magnitude>5e-5</magnitude>"
           "<inclination>60</inclination><useMagneticFieldMsgs>true</useMagneticFieldMsgs></plugin>")
    w, m, elem = hector_world(xml)
    mag = HectorMagnetic(w, m, elem, "test", seed=1)
    assert mag.use_magnetic_field_msgs and mag.topic == "magnetic"
    f = mag.step(0.0)
    assert f == pytest.approx((5e-5 * 0.5, 0.0, -5e-5 * math.sqrt(3) / 2))
    w2, m2, elem2 = hector_world(xml, pose=((0, 0, 0.5), quat_from_rpy(0, 0, math.pi / 2)))
    f2 = HectorMagnetic(w2, m2, elem2, "test", seed=1).step(0.0)
    assert f2 == pytest.approx((0.0, -5e-5 * 0.5, -5e-5 * math.sqrt(3) / 2), abs=1e-12)


def test_hector_plugins_name_a_missing_body():
    xml = "<plugin name='m' filename='libhector_gazebo_ros_magnetic.so'><bodyName>nope</bodyName></plugin>"
    w, m, elem = hector_world(xml)
    with pytest.raises(SensorConfigError, match="nope"):
        HectorMagnetic(w, m, elem, "model 'bot' plugin libhector_gazebo_ros_magnetic.so")
