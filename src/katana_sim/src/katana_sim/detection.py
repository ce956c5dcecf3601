"""Objects from a laser scan (seed 001, section 4.4 A), pure.

The seed: every beam whose range lies between the scanner's minimum and maximum hits an object;
successive in-range beams belong to the same object, and objects are separated by at least one
beam outside the range. An object's aim point is its middle; its coordinates are

    pos.x = sin(angle) * distance;  pos.y = cos(angle) * distance;  pos.z = z

**Frame convention.** That formula measures the beam angle from the frame's *y* axis towards its
*x* axis: its y axis is the scanner's zero beam (straight ahead) and its x axis the direction of
positive beam angles. A ROS ``LaserScan`` measures angles counter-clockwise from the scanner's x
axis (forward) towards its y axis (left), so the seed's (x, y) is the laser frame's (y, x):
``seed_xy`` computes the seed's formula as written and ``laser_xy`` swaps it into
``katana_laser_link`` (x ahead, y left, z up). z = 0 there: the scan plane cuts the cans.

**Distance to the centre.** The seed averages the leftmost and rightmost ranges of the object;
for a round object that is the distance to its visible rim, not its centre. We take the range of
the middle beam (the point of the can facing the scanner) and add the object's radius (given,
or estimated from the angular width of the run); ``method="seed"`` gives the seed's average.
"""
import math

from katana_sim.errors import DetectionError


class Detection(object):
    """An object in the laser frame: centre (x, y, z), the middle beam's angle and the centre's
    distance, radius used, and the run of beams [first, last]."""
    __slots__ = ("x", "y", "z", "angle", "distance", "radius", "first", "last")

    def __init__(self, x, y, z, angle, distance, radius, first, last):
        self.x, self.y, self.z, self.angle, self.distance = x, y, z, angle, distance
        self.radius, self.first, self.last = radius, first, last

    @property
    def beams(self):
        return self.last - self.first + 1

    def __repr__(self):
        return "Detection(x=%.4f, y=%.4f, beams %d..%d, r=%.4f)" % (
            self.x, self.y, self.first, self.last, self.radius)


def in_range(r, range_min, range_max):
    return math.isfinite(r) and range_min <= r <= range_max


def split_runs(ranges, range_min, range_max, max_jump=None):
    """Runs [(first, last), ...] of successive in-range beams. ``max_jump`` (m): also split where
    neighbouring ranges differ by more (two objects behind each other in one run); None = the
    seed's rule only."""
    runs, start = [], None
    for i, r in enumerate(ranges):
        ok = in_range(r, range_min, range_max)
        if ok and start is not None and max_jump is not None and abs(r - ranges[i - 1]) > max_jump:
            runs.append((start, i - 1))
            start = i
        elif ok and start is None:
            start = i
        elif not ok and start is not None:
            runs.append((start, i - 1))
            start = None
    if start is not None:
        runs.append((start, len(ranges) - 1))
    return runs


def seed_xy(angle, distance):
    """The seed's formula as written: (sin(angle) * distance, cos(angle) * distance)."""
    return math.sin(angle) * distance, math.cos(angle) * distance


def laser_xy(angle, distance):
    """A point of the scan in the laser frame (x ahead, y left): the seed's (x, y) swapped."""
    sx, sy = seed_xy(angle, distance)
    return sy, sx


def estimate_radius(surface_distance, half_angle):
    """Radius of a circle whose tangent beams are +-half_angle apart around the middle beam that
    hits it at surface_distance: R = d sin(a) / (1 - sin(a))."""
    s = math.sin(min(max(half_angle, 0.0), 1.2))
    return surface_distance * s / (1.0 - s)


def detect(ranges, angle_min, angle_increment, range_min, range_max, radius=None, min_beams=2,
           max_jump=0.05, method="centre", z=0.0):
    """Objects in one scan. ``radius`` (m): the objects' radius if known (else estimated per run);
    ``min_beams``: shorter runs are noise. Raises DetectionError on malformed input."""
    if not all(math.isfinite(v) for v in (angle_min, angle_increment, range_min, range_max)):
        raise DetectionError("scan angles/limits must be finite (angle_min %r, angle_increment %r, "
                             "range_min %r, range_max %r)"
                             % (angle_min, angle_increment, range_min, range_max))
    if angle_increment == 0 or range_max <= range_min:
        raise DetectionError("scan with angle_increment %r and range [%r, %r] cannot be split into objects"
                             % (angle_increment, range_min, range_max))
    if method not in ("centre", "seed"):
        raise DetectionError("detection method must be 'centre' or 'seed', got %r" % method)
    out = []
    for first, last in split_runs(ranges, range_min, range_max, max_jump):
        if last - first + 1 < min_beams:
            continue
        mid = 0.5 * (first + last)
        angle = angle_min + angle_increment * mid
        lo, hi = int(math.floor(mid)), int(math.ceil(mid))
        surface = 0.5 * (ranges[lo] + ranges[hi])
        half = 0.5 * abs(angle_increment) * (last - first + 1)
        r = radius if radius is not None else estimate_radius(surface, half)
        if method == "seed":
            distance = 0.5 * (ranges[first] + ranges[last])
        else:
            distance = surface + r
        x, y = laser_xy(angle, distance)
        out.append(Detection(x, y, z, angle, distance, r, first, last))
    return out


def cast_circles(circles, angle_min, angle_increment, count, range_max, nan_value=float("inf")):
    """A synthetic scan (tests, figures): ranges from the laser origin to circles [(x, y, r)] in
    the laser frame; beams that hit nothing get ``nan_value`` (a Gazebo laser reports inf)."""
    ranges = []
    for i in range(count):
        a = angle_min + angle_increment * i
        dx, dy = math.cos(a), math.sin(a)
        best = nan_value
        for cx, cy, r in circles:
            b = dx * cx + dy * cy
            c = cx * cx + cy * cy - r * r
            disc = b * b - c
            if disc >= 0:
                t = b - math.sqrt(disc)
                if 0 < t <= range_max and (not math.isfinite(best) or t < best):
                    best = t
        ranges.append(best)
    return ranges
