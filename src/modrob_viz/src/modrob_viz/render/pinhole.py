"""The pinhole camera a Gazebo camera sensor and RViz's Camera display share (pure).

Optical-frame convention (ROS REP 103, Gazebo's ``frameName`` images): z forward, x right,
y down. A point (x, y, z) in that frame lands on pixel u = fx x / z + cx, v = fy y / z + cy.
Gazebo's camera sensor derives its intrinsics from the horizontal field of view:
fx = fy = width / (2 tan(hfov / 2)), cx = (width + 1) / 2, cy = (height + 1) / 2
(gazebo_ros_camera_utils), so zooming is changing hfov.
"""
import collections
import math

from modrob_viz.errors import ConfigError

Intrinsics = collections.namedtuple("Intrinsics", "width height fx fy cx cy")

MIN_HFOV = 0.01         # rad
MAX_HFOV = 3.1          # rad (below pi: tan(hfov / 2) must stay finite)


def check_hfov(hfov, what="horizontal_fov"):
    """hfov in rad as float, or ConfigError naming ``what`` and the valid range."""
    try:
        value = float(hfov)
    except (TypeError, ValueError):
        raise ConfigError("%s must be a number in rad, got %r" % (what, hfov))
    if not math.isfinite(value) or not MIN_HFOV <= value <= MAX_HFOV:
        raise ConfigError("%s must be within [%.2f, %.2f] rad, got %r" % (what, MIN_HFOV, MAX_HFOV, hfov))
    return value


def check_size(width, height, what="image"):
    try:
        w, h = int(width), int(height)
    except (TypeError, ValueError):
        raise ConfigError("%s width/height must be integers, got %r x %r" % (what, width, height))
    if w <= 0 or h <= 0 or w > 8192 or h > 8192:
        raise ConfigError("%s size %d x %d is unusable: width and height must be 1..8192" % (what, w, h))
    return w, h


def gazebo_intrinsics(width, height, hfov):
    """Intrinsics of a Gazebo camera sensor with the given image size and horizontal fov [rad]."""
    w, h = check_size(width, height)
    hfov = check_hfov(hfov)
    f = w / (2.0 * math.tan(hfov / 2.0))
    return Intrinsics(w, h, f, f, (w + 1.0) / 2.0, (h + 1.0) / 2.0)


def hfov_from_focal(width, fx):
    """Horizontal field of view [rad] of an image ``width`` px wide with focal length ``fx`` px."""
    if not (fx > 0 and math.isfinite(fx)):
        raise ConfigError("focal length fx must be a positive number, got %r" % (fx,))
    return 2.0 * math.atan(width / (2.0 * fx))


def from_matrices(width, height, K=None, P=None):
    """Intrinsics from a CameraInfo's size and its P (preferred, RViz renders with P) or K matrix.
    ConfigError for a zero size or a non-positive focal length."""
    w, h = check_size(width, height, "CameraInfo")
    if P is not None and len(P) == 12 and P[0] > 0 and P[5] > 0:
        fx, fy, cx, cy = P[0], P[5], P[2], P[6]
    elif K is not None and len(K) == 9 and K[0] > 0 and K[4] > 0:
        fx, fy, cx, cy = K[0], K[4], K[2], K[5]
    else:
        raise ConfigError("CameraInfo has no usable focal length (P[0], P[5] and K[0], K[4] are 0): "
                          "fill K = [fx 0 cx 0 fy cy 0 0 1] and P")
    values = (fx, fy, cx, cy)
    if not all(math.isfinite(v) for v in values):
        raise ConfigError("CameraInfo intrinsics contain NaN or inf: %r" % (values,))
    return Intrinsics(w, h, float(fx), float(fy), float(cx), float(cy))


def rviz_intrinsics(i):
    """The intrinsics to give RViz's Camera display for an image with intrinsics ``i``: RViz puts
    the principal point at (cx, cy) in coordinates whose origin is the top-left pixel's corner,
    ROS (CameraInfo, image_geometry) at the top-left pixel's centre, half a pixel apart. Given
    (cx + 0.5, cy + 0.5), RViz draws a point where ``project(i, point)`` puts it."""
    return i._replace(cx=i.cx + 0.5, cy=i.cy + 0.5)


def k_matrix(i):
    return [i.fx, 0.0, i.cx, 0.0, i.fy, i.cy, 0.0, 0.0, 1.0]


def p_matrix(i, tx=0.0):
    """3x4 projection, row-major. ``tx`` = -fx * baseline (Gazebo's hackBaseline)."""
    return [i.fx, 0.0, i.cx, tx, 0.0, i.fy, i.cy, 0.0, 0.0, 0.0, 1.0, 0.0]


def project(i, point):
    """Pixel (u, v) of a point given in the optical frame, or None behind the camera."""
    x, y, z = point
    if z <= 1e-9:
        return None
    return (i.fx * x / z + i.cx, i.fy * y / z + i.cy)


def zoomed(i, hfov):
    """The same image size with a new horizontal fov (principal point kept, fy/fx ratio kept)."""
    hfov = check_hfov(hfov)
    fx = i.width / (2.0 * math.tan(hfov / 2.0))
    return Intrinsics(i.width, i.height, fx, fx * i.fy / i.fx, i.cx, i.cy)
