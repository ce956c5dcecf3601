"""Tier 1: hector_gazebo_ros_gps: hector's flat-earth WGS84 conversion and its drift process."""
import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from modrob_sim.physics import World
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.gps import EXCENTRICITY2, HectorGps

BOT = """<robot name="bot"><link name="base_link"><inertial><mass value="1"/>
<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
<collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
<gazebo><static>true</static></gazebo></robot>"""


def gps(params, seed=1):
    w = World(seed=seed)
    m = w.add_urdf("bot", BOT)
    elem = ET.fromstring("<plugin filename='libhector_gazebo_ros_gps.so'>"
                         "<bodyName>base_link</bodyName>%s</plugin>" % params)
    return w, m, HectorGps(w, m, elem, "model 'bot' plugin libhector_gazebo_ros_gps.so", seed=seed)


def radii(lat0):
    a = 6378137.0
    s = math.sin(math.radians(lat0))
    n = a / math.sqrt(1 - EXCENTRICITY2 * s * s)
    return n * (1 - EXCENTRICITY2) / (1 - EXCENTRICITY2 * s * s), n * math.cos(math.radians(lat0))


def fix_at(w, m, g, x, y, z=0.0):
    m.set_pose(((x, y, z), (0, 0, 0, 1)))
    w.step()
    g.rate.reset()
    return g.step(w.time)


def test_defaults_are_hectors():
    w, m, g = gps("")
    assert (g.reference_latitude, g.reference_longitude, g.reference_heading, g.reference_altitude) == \
        (49.9, 8.9, 0.0, 0.0)
    assert g.topic == "fix" and g.velocity_topic == "fix_velocity" and g.frame_id == "/world"
    assert g.rate.period == pytest.approx(0.25)
    f = fix_at(w, m, g, 0.0, 0.0)
    assert f.latitude == 49.9 and f.longitude == 8.9 and f.altitude == 0.0


def test_100m_north_and_west_without_noise():
    w, m, g = gps("")
    rn, re = radii(49.9)
    f = fix_at(w, m, g, 100.0, 0.0)
    assert abs(f.latitude - (49.9 + math.degrees(100.0 / rn))) < 1e-7
    assert abs(f.longitude - 8.9) < 1e-7
    assert abs((f.latitude - 49.9) - 0.000899) < 2e-6          # ~ 1/111.2 km per degree
    f = fix_at(w, m, g, 0.0, 100.0, 2.5)
    assert abs(f.longitude - (8.9 - math.degrees(100.0 / re))) < 1e-7   # +y is west
    assert abs(f.latitude - 49.9) < 1e-7
    assert f.altitude == pytest.approx(2.5)


def test_reference_heading_rotates_the_axes():
    w, m, g = gps("<referenceHeading>90</referenceHeading><referenceLatitude>10</referenceLatitude>"
                  "<referenceLongitude>20</referenceLongitude><referenceAltitude>100</referenceAltitude>")
    rn, re = radii(10.0)
    f = fix_at(w, m, g, 50.0, 0.0, 1.0)
    # heading 90: +x is east -> longitude grows
    assert abs(f.longitude - (20 + math.degrees(50.0 / re))) < 1e-7
    assert abs(f.latitude - 10.0) < 1e-7 and f.altitude == pytest.approx(101.0)


def test_noise_stddev_and_covariance():
    w, m, g = gps("<gaussianNoise>0.5 0.5 0.5</gaussianNoise><updateRate>0</updateRate>")
    rn, _ = radii(49.9)
    xs = []
    for _ in range(3000):
        w.step()
        f = g.step(w.time)
        xs.append(math.radians(f.latitude - 49.9) * rn)
    assert abs(np.std(xs) - 0.5) < 0.05 and abs(np.mean(xs)) < 0.05
    assert g.covariance == [0.25, 0, 0, 0, 0.25, 0, 0, 0, 0.25]


def test_drift_statistics_follow_hectors_process():
    # drift_k = exp(-dt f) drift_{k-1} + dt N(0, sqrt(2f) d): stationary variance
    # dt^2 2 f d^2 / (1 - exp(-2 dt f)); lag-1 autocorrelation exp(-dt f)
    d, f, dt = 2.0, 0.5, 0.1
    w, m, g = gps("<drift>%g %g %g</drift><driftFrequency>%g %g %g</driftFrequency>"
                  "<updateRate>10</updateRate>" % (d, d, d, f, f, f))
    assert g.covariance[0] == pytest.approx(d * d)
    errs = []
    for _ in range(60000):
        errs.append(g.position_error.update(dt))
    e = np.array(errs)[2000:]
    var = dt * dt * 2 * f * d * d / (1 - math.exp(-2 * dt * f))
    for k in range(3):
        assert abs(e[:, k].var() / var - 1) < 0.25
        c = np.corrcoef(e[:-1, k], e[1:, k])[0, 1]
        assert abs(c - math.exp(-dt * f)) < 0.02


def test_offset_is_added():
    w, m, g = gps("<offset>10 0 -1</offset>")
    rn, _ = radii(49.9)
    f = fix_at(w, m, g, 0.0, 0.0)
    assert abs(f.latitude - (49.9 + math.degrees(10.0 / rn))) < 1e-9 and f.altitude == pytest.approx(-1.0)


def test_velocity_is_north_west_up():
    w = World(seed=2)
    m = w.add_urdf("bot", BOT.replace("<gazebo><static>true</static></gazebo>", ""),
                   pose=((0, 0, 10), (0, 0, 0, 1)))
    elem = ET.fromstring("<plugin><bodyName>base_link</bodyName>"
                         "<referenceHeading>90</referenceHeading></plugin>")
    g = HectorGps(w, m, elem, "model 'bot' plugin x", seed=2)
    m.set_twist(((1.0, 2.0, 0.0), (0, 0, 0)))
    w.step(500)
    g.rate.reset()
    f = g.step(w.time)
    # heading 90 deg: north = +y, west = -x; falling for 0.5 s
    assert f.velocity[0] == pytest.approx(2.0, abs=1e-6)
    assert f.velocity[1] == pytest.approx(-1.0, abs=1e-6)
    assert f.velocity[2] == pytest.approx(-9.81 * 0.5, abs=0.02)


@pytest.mark.parametrize("params, tag", [("<drift>a b c</drift>", "drift"),
                                         ("<referenceLatitude>95</referenceLatitude>", "referenceLatitude"),
                                         ("<gaussianNoise>-1</gaussianNoise>", "gaussianNoise")])
def test_bad_parameters_name_the_element(params, tag):
    with pytest.raises(SensorConfigError) as e:
        gps(params)
    assert tag in str(e.value) and "bot" in str(e.value)
