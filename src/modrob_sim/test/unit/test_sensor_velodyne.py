"""Tier 1: velodyne_simulator's PointCloud2 layout and a ring of cones seen by a 16-laser lidar."""
import importlib.util
import math
import os

import numpy as np

from modrob_sim.physics import World
from modrob_sim.sensors import velodyne
from modrob_sim.sensors.ray_sensor import RaySensor
from modrob_sim.sensors.sdf import Params

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "sensors")
_spec = importlib.util.spec_from_file_location("sensor_fixtures", os.path.join(_FIX, "sensor_fixtures.py"))
F = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(F)


def lidar_xml(samples=360, lasers=16, organize=False, noise=0.0):
    ray = F.ray_block(samples=samples, min_angle=-math.pi, max_angle=math.pi, rmin=0.3, rmax=20.0,
                      v_samples=lasers, v_min=-math.radians(15), v_max=math.radians(15))
    return ("<sensor type='ray' name='vlp'><update_rate>10</update_rate>%s<plugin name='l' "
            "filename='libgazebo_ros_velodyne_laser.so'><topicName>/points</topicName><frameName>sensor_link"
            "</frameName><organize_cloud>%s</organize_cloud><min_range>0.9</min_range><max_range>15.0"
            "</max_range><gaussianNoise>%g</gaussianNoise></plugin></sensor>"
            % (ray, "true" if organize else "false", noise))


def cones_world(xml, n=6, dist=5.0):
    w = World(seed=2)
    w.add_sdf(F.GROUND)
    az = [k * 2 * math.pi / n + 0.2 for k in range(n)]
    for k, a in enumerate(az):
        xyz = (dist * math.cos(a), dist * math.sin(a), 1.5)
        w.add_sdf(F.static_shape("cone%d" % k, F.cylinder(0.25, 3.0), xyz))
    m = w.add_urdf("bot", F.sensor_robot(xml), pose=((0, 0, 0.1), (0, 0, 0, 1)))
    link = m.links["sensor_link"]
    s = RaySensor(w, m, "sensor_link", link.sensors[0], "libgazebo_ros_velodyne_laser.so")
    cfg = velodyne.VelodyneConfig(Params(link.sensors[0].find("plugin"), "test"), s.spec)
    return w, s, cfg, az


def cloud(s, cfg):
    r, i = s.scan()
    data, width, height, row_step, dense = velodyne.pack_cloud(s.spec, cfg, r, i, rng=s.rng)
    return np.frombuffer(data, dtype=velodyne.POINT_DTYPE), width, height, row_step, dense


def test_layout_matches_velodyne():
    assert velodyne.POINT_DTYPE.itemsize == 22
    want = [("x", 0), ("y", 4), ("z", 8), ("intensity", 12), ("ring", 16), ("time", 18)]
    assert [(n, o) for n, o, _, _ in velodyne.FIELDS] == want
    assert [d for _, _, d, _ in velodyne.FIELDS] == [7, 7, 7, 7, 4, 7]


def test_ring_of_cones_at_the_right_azimuths_and_distances():
    w, s, cfg, az = cones_world(lidar_xml())
    pts, width, height, row_step, dense = cloud(s, cfg)
    assert height == 1 and width == len(pts) and row_step == 22 * width and dense
    sensor_z = 0.1 + 0.15
    above = pts["z"] > -sensor_z + 0.05
    hd = np.hypot(pts["x"], pts["y"])
    for a in az:
        cx, cy = 5 * math.cos(a), 5 * math.sin(a)
        d = np.hypot(pts["x"] - cx, pts["y"] - cy)
        near = (d < 0.5) & above
        assert near.sum() >= 16, "cone at %.0f deg not seen" % math.degrees(a)
        assert np.abs(d[near] - 0.25).max() < 1e-3
        # every laser that looks at a cone sees it: 8 rings (the upper half) at least
        assert len(set(pts["ring"][near])) >= 8
    # nothing else above the ground, and no point beyond max_range 15 or within min_range 0.9
    assert (hd[above] < 5.3).all()
    assert (np.sqrt(hd ** 2 + pts["z"] ** 2) > 0.9).all()
    # rings: 0 = lowest laser; its ground points are the nearest
    g0 = hd[(pts["ring"] == 0)]
    assert abs(np.median(g0) - sensor_z / math.tan(math.radians(15))) < 0.05
    # order: horizontal sample outer, laser inner (ring increases within a column)
    assert pts["time"].max() == 0.0


def test_organized_cloud():
    w, s, cfg, az = cones_world(lidar_xml(samples=90, organize=True))
    pts, width, height, row_step, dense = cloud(s, cfg)
    assert width == 16 and height == 90 and not dense and row_step == 16 * 22
    grid = pts.reshape(90, 16)
    assert (grid["ring"] == np.arange(16)[None, :]).all()
    assert np.isnan(grid["x"]).any() and np.isfinite(grid["x"]).any()


def test_noise():
    # organized clouds keep every beam in place: compare beam by beam
    w, s, cfg, _ = cones_world(lidar_xml(organize=True, noise=0.05))
    w0, s0, cfg0, _ = cones_world(lidar_xml(organize=True, noise=0.0))
    r, i = s.scan()
    noisy, *_ = velodyne.pack_cloud(s.spec, cfg, r, i, rng=np.random.default_rng(1))
    clean, *_ = velodyne.pack_cloud(s0.spec, cfg0, r, i, rng=None)
    a = np.frombuffer(noisy, dtype=velodyne.POINT_DTYPE)
    b = np.frombuffer(clean, dtype=velodyne.POINT_DTYPE)
    ra = np.sqrt(a["x"] ** 2 + a["y"] ** 2 + a["z"] ** 2)
    rb = np.sqrt(b["x"] ** 2 + b["y"] ** 2 + b["z"] ** 2)
    both = np.isfinite(ra) & np.isfinite(rb)
    assert both.sum() > 1000
    assert abs(np.std(ra[both] - rb[both]) - 0.05) < 0.005


def test_min_intensity_drops_points():
    xml = lidar_xml().replace("<gaussianNoise>", "<min_intensity>0.5</min_intensity><gaussianNoise>")
    w, s, cfg, _ = cones_world(xml)
    pts, *_ = cloud(s, cfg)
    assert len(pts) == 0       # nothing has a laserRetro here: every intensity is 0
