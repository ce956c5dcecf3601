"""Polyline geometry for trajectories (pure numpy): distance of a point to a polyline,
Douglas-Peucker reduction, path length and the divergence between two paths."""
import math

import numpy as np

from modrob_viz.errors import TrajectoryError


def as_points(points, what="points"):
    """An (N, 3) float array; raises :class:`TrajectoryError` for a wrong shape or NaN."""
    arr = np.asarray(points, dtype=float)
    if arr.ndim == 1 and arr.size == 0:
        arr = arr.reshape(0, 3)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise TrajectoryError("%s must be a list of (x, y, z), got shape %s" % (what, arr.shape))
    if not np.all(np.isfinite(arr)):
        bad = int(np.argmax(~np.all(np.isfinite(arr), axis=1)))
        raise TrajectoryError("%s: point %d is not finite (%s)" % (what, bad, arr[bad].tolist()))
    return arr


def point_segment_distance(p, a, b):
    """(distance, t): distance from p to segment a-b and the parameter t in [0, 1] of the
    closest point a + t (b - a)."""
    p, a, b = (np.asarray(v, dtype=float) for v in (p, a, b))
    ab = b - a
    denom = float(ab.dot(ab))
    t = 0.0 if denom == 0.0 else min(1.0, max(0.0, float((p - a).dot(ab)) / denom))
    return float(np.linalg.norm(p - (a + t * ab))), t


class PolylineDistance(object):
    """Distance queries against one polyline (segments precomputed; vectorised over segments)."""

    def __init__(self, points):
        pts = as_points(points, "polyline")
        if len(pts) == 0:
            raise TrajectoryError("polyline has no points")
        self.points = pts
        if len(pts) == 1:
            self.a = pts
            self.ab = np.zeros((1, 3))
        else:
            self.a = pts[:-1]
            self.ab = pts[1:] - pts[:-1]
        self.len2 = np.einsum("ij,ij->i", self.ab, self.ab)

    def query(self, p):
        """(distance, segment index, closest point) for point p."""
        p = np.asarray(p, dtype=float)
        ap = p - self.a
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.where(self.len2 > 0, np.einsum("ij,ij->i", ap, self.ab) / self.len2, 0.0)
        t = np.clip(t, 0.0, 1.0)
        closest = self.a + t[:, None] * self.ab
        d = np.linalg.norm(closest - p, axis=1)
        i = int(np.argmin(d))
        return float(d[i]), i, closest[i]

    def distance(self, p):
        return self.query(p)[0]

    def distances(self, points):
        return np.array([self.distance(p) for p in as_points(points)])


def polyline_distance(p, points):
    """Distance from point p to the polyline through ``points`` [same unit as the input]."""
    return PolylineDistance(points).distance(p)


def douglas_peucker(points, tolerance):
    """Indices of the points kept by the Douglas-Peucker reduction with ``tolerance``.

    The first and the last point are always kept; every removed point lies within
    ``tolerance`` of the reduced polyline. Iterative (no recursion limit for long paths).
    """
    pts = as_points(points)
    if not (tolerance >= 0.0 and math.isfinite(tolerance)):
        raise TrajectoryError("Douglas-Peucker tolerance must be a finite number >= 0, got %r" % (tolerance,))
    n = len(pts)
    if n <= 2:
        return list(range(n))
    keep = np.zeros(n, dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, n - 1)]
    while stack:
        first, last = stack.pop()
        if last - first < 2:
            continue
        a, b = pts[first], pts[last]
        inner = pts[first + 1:last]
        ab = b - a
        denom = float(ab.dot(ab))
        if denom == 0.0:
            d = np.linalg.norm(inner - a, axis=1)
        else:
            t = np.clip((inner - a).dot(ab) / denom, 0.0, 1.0)
            d = np.linalg.norm(inner - (a + t[:, None] * ab), axis=1)
        i = int(np.argmax(d))
        if d[i] > tolerance:
            split = first + 1 + i
            keep[split] = True
            stack.append((first, split))
            stack.append((split, last))
    return [int(i) for i in np.nonzero(keep)[0]]


def path_length(points):
    pts = as_points(points)
    if len(pts) < 2:
        return 0.0
    return float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))


class Divergence(object):
    """How far a travelled path strays from a desired one [m].

    ``max`` and ``rms`` are over the travelled samples' distances to the desired polyline;
    ``final`` is the distance between the two paths' last points; ``n`` the number of samples.
    """

    def __init__(self, distances, final):
        self.distances = np.asarray(distances, dtype=float)
        self.n = int(self.distances.size)
        self.max = float(self.distances.max()) if self.n else float("nan")
        self.rms = float(math.sqrt(np.mean(self.distances ** 2))) if self.n else float("nan")
        self.final = float(final)

    def __str__(self):
        return ("max %.4f m, RMS %.4f m, final %.4f m over %d samples"
                % (self.max, self.rms, self.final, self.n))


def divergence(desired, travelled):
    """:class:`Divergence` of the ``travelled`` points from the ``desired`` polyline."""
    poly = PolylineDistance(desired)
    trav = as_points(travelled, "travelled path")
    if len(trav) == 0:
        raise TrajectoryError("the travelled path has no samples: is the end-effector frame in tf?")
    d = poly.distances(trav)
    final = float(np.linalg.norm(trav[-1] - poly.points[-1]))
    return Divergence(d, final)
