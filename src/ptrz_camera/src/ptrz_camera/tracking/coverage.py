"""Which part of the floor the cameras have seen: a grid over a rectangle, each cell holding the
time it was last inside a camera's view. The view's footprint on the floor is the polygon where
the rays through the image border meet the floor (rays above the horizon are cut at max_range)."""
import numpy as np
import cv2

from ptrz_camera import pinhole


def footprint(pose, intr, max_range=12.0, samples=8):
    """Floor polygon (N x 2, world xy) seen by the camera, or None if it sees no floor."""
    rot, t = pose
    w, h = intr.width, intr.height
    steps = [i / float(samples) for i in range(samples)]
    border = ([(w * s, 0) for s in steps] + [(w, h * s) for s in steps]
              + [(w - w * s, h) for s in steps] + [(0, h - h * s) for s in steps])
    pts = []
    for u, v in border:
        d = rot.dot(pinhole.ray(intr, u, v))
        if d[2] < -1e-6:
            s = -t[2] / d[2]
            p = t + s * d
            off = p[:2] - t[:2]
            dist = np.linalg.norm(off)
            if dist > max_range:
                p = t[:2] + off * (max_range / dist)
            else:
                p = p[:2]
            pts.append(p)
        else:                                        # above the horizon: as far as max_range
            horiz = np.array([d[0], d[1]])
            n = np.linalg.norm(horiz)
            if n > 1e-9:
                pts.append(t[:2] + horiz / n * max_range)
    if len(pts) < 3:
        return None
    return np.array(pts)


class CoverageGrid(object):
    def __init__(self, x0, y0, width, height, resolution=0.1, stale_time=20.0):
        self.x0, self.y0, self.resolution = x0, y0, resolution
        self.nx = int(round(width / resolution))
        self.ny = int(round(height / resolution))
        self.stale_time = stale_time
        self.last_seen = np.full((self.ny, self.nx), -np.inf)

    def mark(self, polygon, t):
        cells = np.round((polygon - [self.x0, self.y0]) / self.resolution).astype(np.int32)
        mask = np.zeros((self.ny, self.nx), np.uint8)
        cv2.fillPoly(mask, [cells.reshape(-1, 1, 2)], 1)
        self.last_seen[mask.astype(bool)] = t

    def values(self, t):
        """OccupancyGrid data (row-major from (x0, y0)): -1 never seen, 0 seen now, rising to 100
        after stale_time seconds unseen."""
        age = t - self.last_seen
        out = np.where(np.isinf(age), -1, np.clip(np.round(100.0 * age / self.stale_time), 0, 100))
        return out.astype(np.int8)

    def fraction_seen(self, t, within=None):
        age = t - self.last_seen
        within = self.stale_time if within is None else within
        return float(np.mean(age <= within))
