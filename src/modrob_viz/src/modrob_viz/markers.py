"""visualization_msgs markers for trajectories (message classes only, no rospy): line strips,
direction arrows, spheres, and per-vertex colours that dim or clip the passed part of a path."""
import math

import numpy as np
from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from modrob_viz.errors import VizError

NAMED_COLORS = {
    "red": (1.0, 0.0, 0.0, 1.0), "green": (0.0, 0.8, 0.0, 1.0), "blue": (0.0, 0.3, 1.0, 1.0),
    "yellow": (1.0, 0.9, 0.0, 1.0), "orange": (1.0, 0.5, 0.0, 1.0), "black": (0.0, 0.0, 0.0, 1.0),
    "white": (1.0, 1.0, 1.0, 1.0), "grey": (0.5, 0.5, 0.5, 1.0), "gray": (0.5, 0.5, 0.5, 1.0),
    "turquoise": (0.25, 0.88, 0.82, 1.0), "magenta": (1.0, 0.0, 1.0, 1.0), "cyan": (0.0, 1.0, 1.0, 1.0),
}


def parse_color(value):
    """(r, g, b, a) in [0, 1] from a name ('red'), a string 'r g b [a]' / 'r,g,b' or a list."""
    if isinstance(value, str):
        key = value.strip().lower()
        if key in NAMED_COLORS:
            return NAMED_COLORS[key]
        parts = key.replace(",", " ").split()
    else:
        parts = list(value) if isinstance(value, (list, tuple)) else [value]
    try:
        rgba = [float(v) for v in parts]
    except (TypeError, ValueError):
        rgba = []
    if len(rgba) == 3:
        rgba.append(1.0)
    if len(rgba) != 4 or not all(math.isfinite(v) and 0.0 <= v <= 1.0 for v in rgba):
        raise VizError("colour %r is not a name (%s) nor 3-4 numbers in [0, 1] like '1 0 0 1'"
                       % (value, ", ".join(sorted(NAMED_COLORS))))
    return tuple(rgba)


def rgba(color):
    if isinstance(color, ColorRGBA):
        return ColorRGBA(color.r, color.g, color.b, color.a)
    r, g, b, a = parse_color(color)
    return ColorRGBA(r, g, b, a)


def _marker(kind, frame_id, ns, marker_id, color):
    m = Marker()
    m.header.frame_id = frame_id
    m.ns = ns
    m.id = marker_id
    m.type = kind
    m.action = Marker.ADD
    m.pose.orientation.w = 1.0
    m.color = rgba(color)
    return m


def line_strip(points, frame_id, color="red", width=0.005, ns="trajectory", marker_id=0, colors=None):
    """A LINE_STRIP through ``points`` (scale.x = line width [m]); ``colors``: one per point."""
    m = _marker(Marker.LINE_STRIP, frame_id, ns, marker_id, color)
    m.scale.x = float(width)
    m.points = [Point(float(p[0]), float(p[1]), float(p[2])) for p in points]
    if colors is not None:
        m.colors = [rgba(c) for c in colors]
    return m


def sphere(center, frame_id, diameter=0.05, color="red", ns="goal", marker_id=0):
    m = _marker(Marker.SPHERE, frame_id, ns, marker_id, color)
    m.pose.position = Point(*[float(v) for v in center])
    m.scale.x = m.scale.y = m.scale.z = float(diameter)
    return m


def points_marker(points, frame_id, size=0.01, color="yellow", ns="milestones", marker_id=0):
    m = _marker(Marker.SPHERE_LIST, frame_id, ns, marker_id, color)
    m.scale.x = m.scale.y = m.scale.z = float(size)
    m.points = [Point(float(p[0]), float(p[1]), float(p[2])) for p in points]
    return m


def arrow_positions(points, spacing):
    """(start, end) pairs of arrows placed every ``spacing`` metres along the path, each pointing
    along the path over a length of min(spacing / 2, remaining path) metres."""
    pts = np.asarray(points, dtype=float)
    if len(pts) < 2 or spacing <= 0:
        return []
    seg = np.diff(pts, axis=0)
    seg_len = np.linalg.norm(seg, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg_len)])
    total = cum[-1]
    if total <= 0:
        return []

    def at(s):
        i = min(int(np.searchsorted(cum, s, side="right")) - 1, len(seg) - 1)
        while i > 0 and seg_len[i] == 0:
            i -= 1
        t = 0.0 if seg_len[i] == 0 else (s - cum[i]) / seg_len[i]
        return pts[i] + t * seg[i]

    out = []
    s = 0.5 * min(spacing, total)
    length = 0.5 * spacing
    while s < total:
        end_s = min(total, s + length)
        a, b = at(s), at(end_s)
        if np.linalg.norm(b - a) > 1e-9:
            out.append((a, b))
        s += spacing
    return out


def direction_arrows(points, frame_id, spacing=0.08, color="orange", shaft=0.008, ns="direction"):
    """A MarkerArray of ARROW markers (start/end points) along the path, every ``spacing`` m."""
    arr = MarkerArray()
    clear = Marker()
    clear.header.frame_id = frame_id
    clear.ns = ns
    clear.action = Marker.DELETEALL
    arr.markers.append(clear)
    for i, (a, b) in enumerate(arrow_positions(points, spacing)):
        m = _marker(Marker.ARROW, frame_id, ns, i, color)
        m.points = [Point(*a.tolist()), Point(*b.tolist())]
        m.scale.x = shaft            # shaft diameter
        m.scale.y = 2.5 * shaft      # head diameter
        m.scale.z = 0.4 * min(spacing, float(np.linalg.norm(b - a)) * 2)  # head length
        arr.markers.append(m)
    return arr


def progress_colors(n, passed, color, dim_alpha=0.35):
    """Per-vertex colours of a strip of ``n`` points where the first ``passed`` are dimmed (grey,
    translucent) and the rest keep ``color``."""
    r, g, b, a = parse_color(color)
    dim = (0.6, 0.6, 0.6, dim_alpha)
    return [dim if i < passed else (r, g, b, a) for i in range(n)]


def progress_strip(points, passed, frame_id, color="red", width=0.005, style="dim", ns="trajectory",
                   marker_id=0):
    """The desired path with the part already travelled dimmed (``style='dim'``), removed
    (``'clip'``) or left as is (``'none'``)."""
    if style == "dim":
        m = line_strip(points, frame_id, color, width, ns, marker_id,
                       colors=progress_colors(len(points), passed, color))
        m.color.a = min(m.color.a, 0.99)  # RViz blends per-vertex alpha only for a translucent marker
        return m
    if style == "clip":
        return line_strip(points[max(0, passed - 1):], frame_id, color, width, ns, marker_id)
    if style == "none":
        return line_strip(points, frame_id, color, width, ns, marker_id)
    raise VizError("passed_style '%s' is not one of dim, clip, none" % style)
