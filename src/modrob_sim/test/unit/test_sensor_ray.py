"""Tier 1: the ray sensor core (laser and lidar geometry, Gazebo's out-of-range reporting, noise)
and the two ray casters on every primitive shape."""
import importlib.util
import math
import os

import numpy as np
import pytest

from modrob_sim.physics import World
from modrob_sim.physics.transforms import quat_to_matrix
from modrob_sim.sensors import raycast
from modrob_sim.sensors.errors import SensorConfigError
from modrob_sim.sensors.ray_sensor import RaySensor

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)

CASTERS = ["ode", "numpy"] if raycast.NATIVE_AVAILABLE else ["numpy"]


def laser_world(sensor_xml, shapes=(), **kw):
    w = World(seed=3)
    w.add_sdf(F.GROUND)
    for i, (geom, xyz) in enumerate(shapes):
        w.add_sdf(F.static_shape("obj%d" % i, geom, xyz))
    m = w.add_urdf("bot", F.sensor_robot(sensor_xml, **kw), pose=((0, 0, 0.1), (0, 0, 0, 1)))
    return w, m


def sensor_of(w, m, caster=None):
    link = m.links["sensor_link"]
    return RaySensor(w, m, "sensor_link", link.sensors[0], "libgazebo_ros_laser.so", caster=caster)


def clutter(seed, count, near, far, height):
    """``count`` shapes (a box, a cylinder, a sphere in turn) at random bearings between ``near``
    and ``far`` m from the origin; ``height``: their z, or a (low, high) range drawn per shape."""
    rng = np.random.default_rng(seed)
    shapes = []
    for k in range(count):
        a, d = rng.uniform(0, 2 * math.pi), rng.uniform(near, far)
        g = [F.box((0.5, 0.7, 1.0)), F.cylinder(0.3, 1.2), F.sphere(0.4)][k % 3]
        z = rng.uniform(*height) if isinstance(height, tuple) else height
        shapes.append((g, (d * math.cos(a), d * math.sin(a), z)))
    return shapes


def assert_same_scan(a, b, hits_agree=1.0):
    """The two casters' ranges ``a`` and ``b``: the same beams hit something (all of them, or at
    least the fraction ``hits_agree``: a ray grazing an edge may go either way), and the beams
    both hit read the same range to 1 um."""
    hit_a, hit_b = np.isfinite(a), np.isfinite(b)
    agree = (hit_a == hit_b).mean()
    assert agree >= hits_agree, "the casters disagree on which beams hit: %d of %d" % (
        np.count_nonzero(hit_a != hit_b), a.size)
    both = hit_a & hit_b
    assert np.abs(a[both] - b[both]).max() < 1e-6


@pytest.mark.parametrize("caster", CASTERS)
def test_box_at_known_bearing_and_distance(caster):
    # sensor at (0, 0, 0.25); a 0.4 m cube centred 3 m away at bearing 30 degrees
    b = math.radians(30.0)
    c = (3.0 * math.cos(b), 3.0 * math.sin(b), 0.25)
    w, m = laser_world(F.laser_sensor(samples=721, rmax=10.0), [(F.box((0.4, 0.4, 0.4)), c)])
    s = sensor_of(w, m, caster)
    ranges, _ = s.scan()
    i = int(round((b - s.spec.h_min) / s.spec.angle_step))
    # the face nearest to the sensor is at x' = 3 - 0.2 along the bearing (cube axis-aligned)
    expected = (c[0] - 0.2) / math.cos(b)
    assert abs(ranges[i] - expected) < 0.01
    # beams that hit nothing read +inf (Gazebo masks ranges >= max as +inf, REP 117)
    behind = int(round((b + math.pi - s.spec.h_min) / s.spec.angle_step)) % s.spec.count
    assert math.isinf(ranges[behind]) and ranges[behind] > 0
    assert np.isinf(ranges).sum() > 600 and np.isfinite(ranges).sum() >= 5


@pytest.mark.parametrize("caster", CASTERS)
def test_sensor_does_not_see_its_own_link_but_sees_its_robot(caster):
    # rays start at range min 0.01 inside the sensor link's 5 cm box: not seen. The base box of
    # the same robot, below the sensor, is seen by a ray pitched down.
    xml = F.laser_sensor(samples=1, min_angle=0.0, max_angle=0.0, rmin=0.01, rmax=5.0,
                         v_samples=1, v_min=-math.pi / 2, v_max=-math.pi / 2)
    w, m = laser_world(xml)
    s = sensor_of(w, m, caster)
    r, _ = s.scan()
    # sensor link origin at 0.1 + 0.15 = 0.25, base box top at 0.1 + 0.1 = 0.2
    assert abs(r[0] - 0.05) < 1e-6


@pytest.mark.parametrize("caster", CASTERS)
def test_every_primitive_shape(caster):
    shapes = [(F.box((1, 1, 1)), (4, 0, 0.5)), (F.cylinder(0.5, 1.0), (0, 4, 0.5)),
              (F.sphere(0.5), (-4, 0, 0.25))]
    w, m = laser_world(F.laser_sensor(samples=4, min_angle=0.0, max_angle=1.5 * math.pi, rmax=20), shapes)
    r, _ = sensor_of(w, m, caster).scan()
    assert abs(r[0] - 3.5) < 1e-6                       # box face
    assert abs(r[1] - 3.5) < 1e-6                       # cylinder side
    # sphere centre (-4, 0, 0.25) = sensor height: the near point at x = -3.5
    assert abs(r[2] - 3.5) < 1e-6
    assert math.isinf(r[3])


def test_casters_agree_in_a_cluttered_world():
    if not raycast.NATIVE_AVAILABLE:
        pytest.skip("native caster unavailable")
    xml = F.laser_sensor(samples=300, rmax=15, v_samples=8, v_min=-0.3, v_max=0.2)
    w, m = laser_world(xml, clutter(seed=1, count=30, near=1.5, far=8, height=0.4))
    a, _ = sensor_of(w, m, "ode").scan()
    b, _ = sensor_of(w, m, "numpy").scan()
    assert_same_scan(a, b, hits_agree=0.999)


def test_casters_agree_for_a_turned_and_tilted_sensor():
    # the native caster culls by the angles of the rays in the sensor's frame: a sensor rolled,
    # pitched and turned must see what the numpy caster (no culling) sees, scan after scan, with
    # the rays' angles kept from the first scan and computed afresh (a writable copy) alike
    if not raycast.NATIVE_AVAILABLE:
        pytest.skip("native caster unavailable")
    shapes = clutter(seed=7, count=24, near=1.0, far=6, height=(-0.5, 1.5))
    xml = F.laser_sensor(samples=180, rmax=15, v_samples=16, v_min=-0.6, v_max=0.4)
    w = World(seed=3)
    for i, (geom, xyz) in enumerate(shapes):
        w.add_sdf(F.static_shape("obj%d" % i, geom, xyz))
    r, p, y = 0.4, -0.3, 2.0        # roll, pitch, yaw
    cr, sr, cp, sp, cy, sy = (math.cos(r / 2), math.sin(r / 2), math.cos(p / 2), math.sin(p / 2),
                              math.cos(y / 2), math.sin(y / 2))
    q = (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
         cr * cp * cy + sr * sp * sy)
    m = w.add_urdf("bot", F.sensor_robot(xml), pose=((0.2, -0.1, 0.6), q))
    ode_s, np_s = sensor_of(w, m, "ode"), sensor_of(w, m, "numpy")
    for _ in range(2):
        a, _ = ode_s.scan()
        b, _ = np_s.scan()
        assert np.isfinite(a).sum() > 100
        assert_same_scan(a, b)
    pos, rot = ode_s.pose()
    fresh = ode_s.caster.cast(pos, quat_to_matrix(rot), np.array(ode_s._dirs), ode_s.spec.range_min,
                              ode_s.spec.range_max)
    kept = ode_s.caster.cast(pos, quat_to_matrix(rot), ode_s._dirs, ode_s.spec.range_min,
                             ode_s.spec.range_max)
    assert np.array_equal(fresh, kept)


def test_noise_stddev_as_configured():
    # the fan looks down at the ground from 1.0 m: every one of the 1000 beams hits
    down = "0 0 0 0 1.5707963 0"
    xml_clean = F.laser_sensor(samples=1000, min_angle=-0.5, max_angle=0.5, rmax=10, pose=down)
    xml_noisy = F.laser_sensor(samples=1000, min_angle=-0.5, max_angle=0.5, rmax=10, pose=down, stddev=0.02)
    w, m = laser_world(xml_clean, sensor_xyz=(0, 0, 0.9))
    clean, _ = sensor_of(w, m).scan()
    w2, m2 = laser_world(xml_noisy, sensor_xyz=(0, 0, 0.9))
    noisy, _ = sensor_of(w2, m2).scan()
    assert np.isfinite(clean).all()
    d = noisy - clean
    assert abs(d.std() - 0.02) < 0.002
    assert abs(d.mean()) < 0.003


def test_noise_is_seeded():
    xml = F.laser_sensor(samples=50, min_angle=-0.5, max_angle=0.5, rmax=10, pose="0 0 0 0 1.5707963 0",
                         stddev=0.05)
    a = sensor_of(*laser_world(xml, sensor_xyz=(0, 0, 0.9))).scan()[0]
    b = sensor_of(*laser_world(xml, sensor_xyz=(0, 0, 0.9))).scan()[0]
    assert np.array_equal(a, b)


def test_range_clamps_and_minus_inf():
    # a wall 0.3-0.5 m away with range min 0.6: the ray starts beyond it -> nothing -> +inf; a wall
    # at 3 m with max 2 -> +inf
    xml = F.laser_sensor(samples=2, min_angle=0.0, max_angle=math.pi, rmin=0.6, rmax=2.0)
    w, m = laser_world(xml, [(F.box((0.2, 4, 2)), (0.4, 0, 1)), (F.box((0.2, 4, 2)), (-3.1, 0, 1))])
    r, _ = sensor_of(w, m).scan()
    assert math.isinf(r[0]) and r[0] > 0
    assert math.isinf(r[1]) and r[1] > 0


@pytest.mark.parametrize("bad, text", [
    ("<samples>abc</samples>", "samples"),
    ("<samples>0</samples>", "samples"),
])
def test_malformed_parameters_name_element_and_value(bad, text):
    xml = F.laser_sensor(samples=10).replace("<samples>10</samples>", bad)
    w, m = laser_world(xml)
    with pytest.raises(SensorConfigError) as e:
        sensor_of(w, m)
    assert text in str(e.value) and "sensor_link" in str(e.value) and "bot" in str(e.value)


def test_range_max_below_min_is_refused():
    xml = F.laser_sensor(samples=10, rmin=2.0, rmax=1.0)
    w, m = laser_world(xml)
    with pytest.raises(SensorConfigError) as e:
        sensor_of(w, m)
    assert "range/max" in str(e.value) and "1.0" in str(e.value)


def test_triangle_mesh_is_hit_where_the_physics_has_it():
    if not raycast.NATIVE_AVAILABLE:
        pytest.skip("native caster unavailable (meshes are boxes on the pure-Python path)")
    cube = os.path.join(os.path.dirname(_FIX), "physics", "cube.obj")       # 0.1 m cube
    mesh = "<mesh><uri>file://%s</uri><scale>10 10 10</scale></mesh>" % cube
    # a 1 m cube turned 30 degrees about z, centred 3 m ahead at the sensor's height: the ray along
    # +x enters the face turned 30 degrees at x = 3 - 0.5 / cos(30 deg); rays 0.15 rad aside hit too
    w = World(seed=3)
    w.add_sdf(F.GROUND)
    w.add_sdf(F.static_shape("meshcube", mesh, (3.0, 0.0, 0.75), (0, 0, math.radians(30))))
    m = w.add_urdf("bot", F.sensor_robot(F.laser_sensor(samples=3, min_angle=-0.15, max_angle=0.15, rmax=10)),
                   pose=((0, 0, 0.1), (0, 0, 0, 1)))
    r, _ = sensor_of(w, m, "ode").scan()
    assert abs(r[1] - (3.0 - 0.5 / math.cos(math.radians(30)))) < 1e-6
    assert np.isfinite(r).all()


def _falling(name, geometry, xyz):
    """A dynamic (not static) model of one shape: it falls while the World steps."""
    return F.static_shape(name, geometry, xyz).replace("<static>true</static>", "<static>false</static>")


@pytest.mark.parametrize("caster", CASTERS)
def test_a_prepared_scan_sees_the_instant_it_was_prepared(caster):
    # a box and a cylinder fall through the beams; a scan prepared now and cast in another thread
    # after the World stepped on reads what scan() read now, not what the beams see then
    import threading
    w, m = laser_world(F.laser_sensor(samples=181, rmax=10.0, v_samples=9, v_min=-0.4, v_max=0.4))
    w.add_sdf(_falling("falling_box", F.box((0.5, 0.5, 0.5)), (3.0, 0.0, 1.2)))
    w.add_sdf(_falling("falling_cyl", F.cylinder(0.3, 0.8), (0.0, 2.5, 1.4)))
    s = sensor_of(w, m, caster)
    now = s.scan()
    later = s.prepare_scan()
    w.step(150)
    out = {}
    t = threading.Thread(target=lambda: out.setdefault("scan", later()))
    t.start()
    w.step(50)                         # the World steps while the rays are cast
    t.join()
    assert np.array_equal(out["scan"][0], now[0]) and np.array_equal(out["scan"][1], now[1])
    assert np.isfinite(now[0]).sum() > 20
    after = s.scan()[0]
    assert not np.array_equal(after, now[0])            # the shapes did move meanwhile


def test_a_scan_with_a_mesh_in_reach_is_cast_when_prepared():
    # ODE's triangle-mesh collider keeps caches shared between threads: such a cast runs at once
    if not raycast.NATIVE_AVAILABLE:
        pytest.skip("native caster unavailable")
    cube = os.path.join(os.path.dirname(_FIX), "physics", "cube.obj")
    mesh = "<mesh><uri>file://%s</uri><scale>10 10 10</scale></mesh>" % cube
    w, m = laser_world(F.laser_sensor(samples=31, rmax=10.0), [(F.box((0.5, 0.5, 0.5)), (2.0, 1.0, 0.25))])
    s = sensor_of(w, m, "ode")
    d = s._dirs
    assert s.caster.prepare((0, 0, 0.25), np.eye(3), d, 0.1, 10.0).deferred
    w.add_sdf(F.static_shape("meshcube", mesh, (3.0, 0.0, 0.75)))
    assert not s.caster.prepare((0, 0, 0.25), np.eye(3), d, 0.1, 10.0).deferred
    # out of reach, the mesh does not hold the cast back
    assert s.caster.prepare((0, 0, 0.25), np.eye(3), d, 0.1, 1.0).deferred
