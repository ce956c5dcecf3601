"""A depth camera's outputs from one render's depth and colour (pure numpy).

``depth`` is what the ClipCamera plugin reads from the depth buffer: metres along the optical axis
(z in the optical frame, as Gazebo's depth camera gives), ``inf`` where nothing was drawn.

- depth image: Gazebo's ``libgazebo_ros_openni_kinect.so`` keeps a value when
  ``pointCloudCutoff < depth < pointCloudCutoffMax`` and writes NaN otherwise (``32FC1``, metres)
  or 0 (``16UC1``, millimetres, with ``useDepth16UC1Format``); ``libgazebo_ros_depth_camera.so``
  has no upper cutoff (``cutoff_max`` inf).
- point cloud: ``sensor_msgs/PointCloud2`` with fields x y z (float32 at 0, 4, 8) and rgb (packed
  at 16), 32 bytes a point, one point per pixel (height x width, row by row), NaN outside the
  cutoffs (then ``is_dense`` false). A pixel (u, v) at depth z is the optical-frame point
  ((u - cx) z / fx, (v - cy) z / fy, z) with the camera's CameraInfo intrinsics (pixel centres at
  whole numbers, as ROS's image_geometry has them), so depth_image_proc makes the same cloud from
  the depth image and the CameraInfo; a pixel that saw nothing is a NaN point. The colour of
  each point is the rgb image's pixel, packed as PCL and RViz read it (0x00RRGGBB in a
  little-endian uint32; Gazebo's plugins put red in the low byte, which RViz shows as blue).
"""
import numpy as np

POINT_STEP = 32
POINT_DTYPE = np.dtype({"names": ["x", "y", "z", "rgb"], "formats": ["<f4", "<f4", "<f4", "<u4"],
                        "offsets": [0, 4, 8, 16], "itemsize": POINT_STEP})
DEPTH_FORMATS = ("32FC1", "16UC1")


def masked(depth, cutoff, cutoff_max=float("inf")):
    """float32 copy of ``depth`` with NaN where it is not above ``cutoff`` and, when
    ``cutoff_max`` is finite, below it (with no upper cutoff a pixel that sees nothing stays inf,
    as with Gazebo's depth_camera plugin)."""
    d = np.asarray(depth, dtype=np.float32)
    with np.errstate(invalid="ignore"):
        keep = d > cutoff
        if np.isfinite(cutoff_max):
            keep &= d < cutoff_max
    return np.where(keep, d, np.float32(np.nan)).astype(np.float32)


def depth_image(depth_masked, fmt="32FC1"):
    """(array, encoding, step) of the depth image: 32FC1 metres (NaN outside the cutoffs) or 16UC1
    millimetres (0 outside), little-endian."""
    h, w = depth_masked.shape
    if fmt == "16UC1":
        mm = np.nan_to_num(depth_masked * 1000.0, nan=0.0, posinf=0.0)
        arr = np.clip(mm, 0, 65535).astype("<u2")
        return arr, "16UC1", w * 2
    if fmt != "32FC1":
        raise ValueError("depth format %r: use 32FC1 or 16UC1" % (fmt,))
    return depth_masked.astype("<f4"), "32FC1", w * 4


def pixel_rays(width, height, fx, fy, cx, cy):
    """(x/z per column, y/z per row) of the rays through the pixel centres (u, v whole numbers)."""
    u = np.arange(width, dtype=np.float64)
    v = np.arange(height, dtype=np.float64)
    return ((u - cx) / fx).astype(np.float32), ((v - cy) / fy).astype(np.float32)


def pack_rgb(rgb):
    """(h, w, 3) uint8 -> (h, w) uint32 0x00RRGGBB; a mono (h, w) image gives grey."""
    rgb = np.asarray(rgb)
    if rgb.ndim == 2:
        rgb = np.repeat(rgb[:, :, None], 3, axis=2)
    c = rgb.astype(np.uint32)
    return (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]


def point_cloud(depth_masked, rgb, rays):
    """(points, dense): a structured array of height x width points (POINT_DTYPE) and whether it
    has no NaN point. ``rays`` from :func:`pixel_rays`; ``rgb`` (h, w, 3) uint8, or None (black)."""
    h, w = depth_masked.shape
    xs, ys = rays
    pts = np.empty((h, w), dtype=POINT_DTYPE)
    z = np.where(np.isfinite(depth_masked), depth_masked, np.float32(np.nan))
    pts["x"] = xs[None, :] * z
    pts["y"] = ys[:, None] * z
    pts["z"] = z
    pts["rgb"] = pack_rgb(rgb) if rgb is not None else 0
    return pts.reshape(-1), not bool(np.isnan(z).any())
