"""Obstacles on the vehicle's way from a point cloud (pure; numpy, no rospy).

Points are taken into base_link_polaris (the lidar's mounting offset; the HDL-32E sits at
(0.95, 0, 1.84) with no rotation), the ground and the vehicle's own body are dropped, and what
remains inside the swept corridor of the current arc (curvature kappa) counts. ``distance`` is
the arc length from the front bumper to the nearest such point (inf when none).
"""
import math

import numpy as np

LIDAR_OFFSET = (0.95, 0.0, 1.84)
GROUND_Z = -0.32                 # ground in base_link_polaris on flat ground
BODY_X = (-0.7, 2.3)             # the vehicle itself, base_link_polaris frame
BODY_Y = 0.8
FRONT_X = 2.25                   # front bumper / wheels


class ObstacleDetector(object):
    def __init__(self, half_width=1.1, min_height=0.15, max_height=2.5, lidar_offset=LIDAR_OFFSET,
                 min_points=2):
        self.half_width = float(half_width)
        self.min_height = float(min_height)
        self.max_height = float(max_height)
        self.offset = np.asarray(lidar_offset, dtype=float)
        self.min_points = int(min_points)

    def distance(self, points, kappa=0.0):
        """Arc length (m) from the front bumper to the nearest obstacle point in the corridor."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        p = p[np.all(np.isfinite(p), axis=1)] + self.offset
        h = p[:, 2] - GROUND_Z
        keep = (h > self.min_height) & (h < self.max_height)
        body = (p[:, 0] > BODY_X[0]) & (p[:, 0] < BODY_X[1]) & (np.abs(p[:, 1]) < BODY_Y)
        p = p[keep & ~body]
        if len(p) == 0:
            return math.inf
        x, y = p[:, 0], p[:, 1]
        if abs(kappa) < 1e-4:
            lateral, s = np.abs(y), x
        else:
            r = 1.0 / kappa
            d = np.hypot(x, y - r)
            lateral = np.abs(d - abs(r))
            ang = np.arctan2(x, np.sign(r) * (r - y))        # angle travelled from the rear axle
            s = np.abs(r) * ang
        ahead = (lateral < self.half_width) & (s > FRONT_X - 0.3)
        if np.count_nonzero(ahead) < self.min_points:
            return math.inf
        return float(np.sort(s[ahead])[self.min_points - 1] - FRONT_X)


class StopGuard(object):
    """Latches a stop when an obstacle is nearer than ``stop_distance`` (m from the bumper)."""

    def __init__(self, stop_distance=4.0):
        self.stop_distance = float(stop_distance)
        self.stopped = False
        self.obstacle_distance = math.inf

    def update(self, distance):
        self.obstacle_distance = distance
        if distance < self.stop_distance:
            self.stopped = True
        return self.stopped
