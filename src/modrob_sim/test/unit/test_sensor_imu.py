"""Tier 1: the IMU cores (Gazebo's ImuSensor with gazebo_ros_imu_sensor's parameters, and the
gazebo_ros_imu model plugin): gravity at rest, rates when spinning, orientation when tilted,
offsets, noise and its covariance."""
import importlib.util
import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from modrob_sim.physics import World
from modrob_sim.physics.transforms import quat_from_rpy, quat_mul, rpy_from_quat
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.imu import ImuModelPlugin, ImuSensor

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)


def imu_xml(rate=100, hz=100.0, noise=0.0, rpy="0 0 0", initial=None, pose="0 0 0 0 0 0"):
    tag = "initialOrientationAsReference"
    ref = "" if initial is None else "<%s>%s</%s>" % (tag, initial, tag)
    return ("<sensor name='imu_sensor' type='imu'><always_on>true</always_on><update_rate>%g</update_rate>"
            "<pose>%s</pose><plugin filename='libgazebo_ros_imu_sensor.so' name='imu_plugin'>"
            "<topicName>imu</topicName><bodyName>sensor_link</bodyName><updateRateHZ>%g</updateRateHZ>"
            "<gaussianNoise>%g</gaussianNoise><xyzOffset>0 0 0</xyzOffset><rpyOffset>%s</rpyOffset>"
            "<frameName>sensor_link</frameName>%s</plugin></sensor>" % (rate, pose, hz, noise, rpy, ref))


def make(sensor_xml, static=False, pose=((0, 0, 0.1), (0, 0, 0, 1)), ground=True):
    w = World(seed=5)
    if ground:
        w.add_sdf(F.GROUND)
    m = w.add_urdf("bot", F.sensor_robot(sensor_xml, static=static), pose=pose)
    link = m.links["sensor_link"]
    plug = link.sensors[0].find("plugin")
    return w, m, ImuSensor(w, m, "sensor_link", link.sensors[0], plug)


def run(w, imu, seconds):
    out = []
    for _ in range(int(round(seconds / w.time_step))):
        w.step()
        r = imu.step(w.time)
        if r is not None:
            out.append(r)
    return out


def test_at_rest_reads_gravity_up_and_zero_rates():
    w, m, imu = make(imu_xml())
    rs = run(w, imu, 1.5)
    r = rs[-1]
    assert abs(r.linear_acceleration[2] - 9.81) < 0.01
    assert abs(r.linear_acceleration[0]) < 0.01 and abs(r.linear_acceleration[1]) < 0.01
    assert max(abs(x) for x in r.angular_velocity) < 1e-3
    assert len(rs) == pytest.approx(150, abs=2)          # updateRateHZ 100 over 1.5 s


def test_publish_rate_follows_update_rate_hz():
    w, m, imu = make(imu_xml(rate=100, hz=10.0))
    assert len(run(w, imu, 1.0)) == pytest.approx(10, abs=1)


def test_spinning_reads_the_commanded_rate():
    w, m, imu = make(imu_xml(), ground=False, pose=((0, 0, 5.0), (0, 0, 0, 1)))
    for ln in m.links.values():
        ln.gravity_enabled = False
    m.links["base_link"].set_twist(((0, 0, 0), (0, 0, 1.7)))
    r = run(w, imu, 0.5)[-1]
    assert abs(r.angular_velocity[2] - 1.7) < 0.017
    # on the spin axis: no centripetal acceleration; the body does not fall (its gravity is off)
    # so, like Gazebo's, the IMU reads the world's gravity as support: +9.81 up
    assert max(abs(a) for a in r.linear_acceleration[:2]) < 0.05
    assert abs(r.linear_acceleration[2] - 9.81) < 0.05


def test_spinning_about_x_in_the_sensor_frame():
    w, m, imu = make(imu_xml(), ground=False, pose=((0, 0, 5.0), quat_from_rpy(0, 0, math.pi / 2)))
    for ln in m.links.values():
        ln.gravity_enabled = False
    m.links["base_link"].set_twist(((0, 0, 0), (0.0, 0.9, 0.0)))   # world y = body x after the yaw
    r = run(w, imu, 0.2)[-1]
    assert abs(r.angular_velocity[0] - 0.9) < 0.009
    assert abs(r.angular_velocity[1]) < 0.009


@pytest.mark.parametrize("initial", [None, "false", "true"])     # None: the default, world (REP 145)
def test_orientation_follows_a_commanded_tilt(initial):
    start = quat_from_rpy(0, 0, 0.4)
    w, m, imu = make(imu_xml(initial=initial), static=True, pose=((0, 0, 1.0), start))
    run(w, imu, 0.05)
    tilt = quat_from_rpy(0.3, -0.2, 0.4)
    m.set_pose(((0, 0, 1.0), tilt))
    r = run(w, imu, 0.05)[-1]
    got = rpy_from_quat(r.orientation)
    undo_start = (0, 0, -math.sin(0.2), math.cos(0.2))
    want = (0.3, -0.2, 0.4) if initial != "true" else rpy_from_quat(quat_mul(undo_start, tilt))
    assert np.allclose(got, want, atol=1e-6)
    # gravity in the tilted sensor frame (static model: no motion)
    g = np.array(r.linear_acceleration)
    assert abs(np.linalg.norm(g) - 9.81) < 0.01 and g[2] < 9.81 - 0.1


def test_rpy_offset_rotates_the_orientation():
    w, m, imu = make(imu_xml(rpy="0 0 0.5", initial="false"), static=True)
    r = run(w, imu, 0.05)[-1]
    assert abs(rpy_from_quat(r.orientation)[2] - 0.5) < 1e-9


def test_noise_and_covariance():
    w, m, imu = make(imu_xml(noise=0.05), static=True)
    rs = run(w, imu, 2.0)
    az = np.array([r.linear_acceleration[2] for r in rs])
    assert abs(az.std() - 0.05) < 0.005 and abs(az.mean() - 9.81) < 0.01
    from modrob_sim.sensors.imu import covariance
    assert covariance(0.05)[0] == pytest.approx(0.0025) and covariance(0.05)[1] == 0.0


def test_model_plugin_reads_the_same():
    w, m, _ = make(imu_xml())
    elem = ET.fromstring("<plugin name='imu' filename='libgazebo_ros_imu.so'><bodyName>base_link</bodyName>"
                         "<topicName>imu_data</topicName><serviceName>imu_service</serviceName>"
                         "<gaussianNoise>0.0</gaussianNoise><updateRate>50.0</updateRate></plugin>")
    p = ImuModelPlugin(w, m, elem, "model 'bot' plugin libgazebo_ros_imu.so")
    rs = []
    for _ in range(1000):
        w.step()
        r = p.step(w.time)
        if r is not None:
            rs.append(r)
    assert len(rs) == pytest.approx(50, abs=1)
    assert abs(rs[-1].linear_acceleration[2] - 9.81) < 0.01
    assert p.topic == "imu_data" and p.service == "imu_service" and p.frame == "base_link"


def test_model_plugin_errors_name_the_element():
    w, m, _ = make(imu_xml())
    with pytest.raises(SensorConfigError) as e:
        ImuModelPlugin(w, m, ET.fromstring("<plugin><bodyName>nope</bodyName></plugin>"),
                       "model 'bot' plugin x")
    assert "bodyName" in str(e.value) and "nope" in str(e.value)
    with pytest.raises(SensorConfigError) as e:
        ImuModelPlugin(w, m, ET.fromstring("<plugin><bodyName>base_link</bodyName>"
                                           "<updateRate>fast</updateRate>"
                                           "</plugin>"), "model 'bot' plugin x")
    assert "updateRate" in str(e.value) and "fast" in str(e.value)
