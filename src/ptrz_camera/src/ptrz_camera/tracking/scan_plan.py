"""The coordinated scan: the floor rectangle is cut into one strip per camera along its long side,
each strip goes to the camera that is nearest to it (the assignment with the least total distance),
and each camera sweeps its strip in a lawnmower of aim points."""
import itertools

import numpy as np


def strips(x0, y0, length, width, n):
    """n rectangles (x0, y0, length, width) cutting the floor along its long side."""
    if length >= width:
        return [(x0 + i * length / n, y0, length / n, width) for i in range(n)]
    return [(x0, y0 + i * width / n, length, width / n) for i in range(n)]


def assign(cameras_xy, rects):
    """For each camera (in order) the index of its strip: least total distance to strip centres."""
    centres = [np.array([x + lx / 2, y + ly / 2]) for x, y, lx, ly in rects]
    best, best_cost = None, None
    for perm in itertools.permutations(range(len(rects)), len(cameras_xy)):
        cost = sum(np.linalg.norm(np.asarray(c) - centres[i]) for c, i in zip(cameras_xy, perm))
        if best_cost is None or cost < best_cost:
            best, best_cost = perm, cost
    return list(best)


def lawnmower(rect, rows=2, cols=3, height=0.0):
    """Aim points covering a rectangle row by row, alternating direction."""
    x, y, lx, ly = rect
    pts = []
    for r in range(rows):
        yr = y + (r + 0.5) * ly / rows
        xs = [x + (c + 0.5) * lx / cols for c in range(cols)]
        if r % 2:
            xs = xs[::-1]
        pts += [(xc, yr, height) for xc in xs]
    if lx < ly:                       # sweep along the long side
        pts = [(x + (p[1] - y) * lx / ly, y + (p[0] - x) * ly / lx, height) for p in pts]
    return pts


class ScanPlan(object):
    """Per camera: its aim points and which one is next."""

    def __init__(self, cameras_xy, floor, dwell=1.5):
        x0, y0, length, width = floor
        rects = strips(x0, y0, length, width, len(cameras_xy))
        self.assignment = assign(cameras_xy, rects)
        self.rects = [rects[i] for i in self.assignment]
        self.points = [lawnmower(r) for r in self.rects]
        self.index = [0] * len(cameras_xy)
        self.settled_since = [None] * len(cameras_xy)
        self.dwell = dwell

    def target(self, cam, t, settled):
        """The aim point of camera ``cam`` at time t; it moves on once the camera has been settled
        on the current point for ``dwell`` seconds."""
        if not settled:
            self.settled_since[cam] = None
        elif self.settled_since[cam] is None:
            self.settled_since[cam] = t
        elif t - self.settled_since[cam] >= self.dwell:
            self.index[cam] = (self.index[cam] + 1) % len(self.points[cam])
            self.settled_since[cam] = None
        return self.points[cam][self.index[cam]]
