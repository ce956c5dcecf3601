"""From a pixel to a floor position, and from several cameras to one.

One camera: the ray through the pixel (camera pose from the joint angles) meets the horizontal
plane z = h (h = the ball's radius: the centroid of a ball's image is, to first order, the image
of its centre). Its uncertainty: a pixel error sigma_px moves the point by J * sigma_px, J the
Jacobian of the floor point with respect to (u, v); the error is long along the viewing
direction when the camera looks flat. Several cameras: the information-weighted mean of their
floor points (each 2x2 covariance inverted and summed), so a camera looking steeply down counts
more than one looking across the field."""
from collections import namedtuple

import numpy as np

from ptrz_camera import pinhole

FloorEstimate = namedtuple("FloorEstimate", "xy cov")


def floor_point(pose, intr, u, v, height=0.0, max_range=50.0):
    """World (x, y, height) where the ray through (u, v) meets z = height, or None."""
    rot, t = pose
    d = rot.dot(pinhole.ray(intr, u, v))
    if d[2] >= -1e-9:
        return None                       # at or above the horizon
    s = (height - t[2]) / d[2]
    if s <= 0 or s > max_range:
        return None
    return t + s * d


def floor_estimate(pose, intr, u, v, height=0.0, sigma_px=1.0):
    """FloorEstimate(xy, 2x2 covariance) of one camera's detection, or None."""
    p = floor_point(pose, intr, u, v, height)
    if p is None:
        return None
    h = 0.5
    pu = floor_point(pose, intr, u + h, v, height)
    pv = floor_point(pose, intr, u, v + h, height)
    if pu is None or pv is None:
        return None
    jac = np.column_stack(((pu[:2] - p[:2]) / h, (pv[:2] - p[:2]) / h))
    cov = jac.dot(jac.T) * sigma_px ** 2 + np.eye(2) * 1e-8
    return FloorEstimate(p[:2], cov)


def fuse(estimates):
    """Information-weighted mean of FloorEstimates; None for none."""
    estimates = [e for e in estimates if e is not None]
    if not estimates:
        return None
    info = np.zeros((2, 2))
    vec = np.zeros(2)
    for e in estimates:
        w = np.linalg.inv(e.cov)
        info += w
        vec += w.dot(e.xy)
    cov = np.linalg.inv(info)
    return FloorEstimate(cov.dot(vec), cov)


def ray_residual(rays):
    """How far apart rays (origin, unit direction) pass: (point, residual), the point nearest to
    all of them in the least-squares sense and the largest distance of a ray from it (m); None
    for fewer than two rays or rays all parallel."""
    if len(rays) < 2:
        return None
    a = np.zeros((3, 3))
    b = np.zeros(3)
    projs = []
    for o, d in rays:
        d = np.asarray(d, dtype=float) / np.linalg.norm(d)
        m = np.eye(3) - np.outer(d, d)
        projs.append((np.asarray(o, dtype=float), m))
        a += m
        b += m.dot(o)
    if np.linalg.cond(a) > 1e8:
        return None
    p = np.linalg.solve(a, b)
    return p, max(float(np.linalg.norm(m.dot(p - o))) for o, m in projs)
