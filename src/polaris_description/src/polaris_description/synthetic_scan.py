"""An analytic HDL-32E for tests and benchmarks that run without the simulator's lidar plugin:
32 rings from -30.67 to +10.67 deg, ``samples`` azimuths, rays against the ground plane and
vertical cylinders (the street cones' radius at each height is approximated by their widest
part below the hit). Points come back in the lidar frame, as /velodyne_points2 gives them."""
import math

import numpy as np

from polaris_description import parking_lot
from polaris_description.obstacle import LIDAR_OFFSET

RINGS = np.radians(np.linspace(-30.67, 10.67, 32))


def cone_cylinders(cones):
    """(x, y, radius, z_top) per cone stack part."""
    out = []
    for (x, y) in cones:
        for r, z0, z1 in parking_lot.CONE_STACK:
            out.append((x, y, r, z0, z1))
    return out


def scan(pose, cones, samples=220, max_range=70.0):
    """Points (N x 3, lidar frame) seen from a vehicle at pose (x, y, yaw) on flat ground."""
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    ox = x + c * LIDAR_OFFSET[0] - s * LIDAR_OFFSET[1]
    oy = y + s * LIDAR_OFFSET[0] + c * LIDAR_OFFSET[1]
    oz = 0.32 + LIDAR_OFFSET[2]
    az = np.linspace(-math.pi, math.pi, samples, endpoint=False)
    el, a = np.meshgrid(RINGS, az, indexing="ij")
    d = np.stack([np.cos(el) * np.cos(a + yaw), np.cos(el) * np.sin(a + yaw), np.sin(el)],
                 axis=-1).reshape(-1, 3)
    t = np.full(len(d), np.inf)
    down = d[:, 2] < -1e-6
    t[down] = -oz / d[down, 2]
    for (cx, cy, r, z0, z1) in cone_cylinders(cones):
        # ray vs infinite vertical cylinder, then clip to [z0, z1]
        px, py = ox - cx, oy - cy
        a2 = d[:, 0] ** 2 + d[:, 1] ** 2
        b = 2 * (px * d[:, 0] + py * d[:, 1])
        cc = px * px + py * py - r * r
        disc = b * b - 4 * a2 * cc
        ok = (disc >= 0) & (a2 > 1e-12)
        th = np.full(len(d), np.inf)
        th[ok] = (-b[ok] - np.sqrt(disc[ok])) / (2 * a2[ok])
        z = oz + th * d[:, 2]
        hit = ok & (th > 0) & (z >= z0) & (z <= z1)
        t = np.where(hit & (th < t), th, t)
    keep = t < max_range
    tk, dk = t[keep], d[keep]
    pts_world = np.stack([ox + tk * dk[:, 0], oy + tk * dk[:, 1], oz + tk * dk[:, 2]], axis=1)
    # into the lidar frame (yaw only: flat ground)
    rx, ry = pts_world[:, 0] - ox, pts_world[:, 1] - oy
    return np.stack([c * rx + s * ry, -s * rx + c * ry, pts_world[:, 2] - oz], axis=1)
