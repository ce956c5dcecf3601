"""The pinhole camera of a Gazebo camera sensor, in the camera LINK frame (x forward, y left,
z up), as gazebo_ros_camera publishes it: f = width / (2 tan(hfov / 2)) for both axes, principal
point (cx, cy) from the CameraInfo. Pixel u grows to the right (-y), v downwards (-z)."""
import math
from collections import namedtuple

import numpy as np

Intrinsics = namedtuple("Intrinsics", "width height fx fy cx cy")


def intrinsics_from_fov(width, height, hfov):
    """Gazebo's intrinsics for an image size and horizontal field of view (rad)."""
    f = width / (2.0 * math.tan(hfov / 2.0))
    return Intrinsics(int(width), int(height), f, f, (width + 1.0) / 2.0, (height + 1.0) / 2.0)


def intrinsics_from_camera_info(msg):
    k = msg.K
    return Intrinsics(int(msg.width), int(msg.height), k[0], k[4], k[2], k[5])


def hfov(intr):
    return 2.0 * math.atan(intr.width / (2.0 * intr.fx))


def project(intr, p_cam):
    """Pixel (u, v) of a point in the camera link frame, or None behind the camera."""
    x, y, z = p_cam
    if x <= 1e-9:
        return None
    return intr.cx - intr.fx * y / x, intr.cy - intr.fy * z / x


def ray(intr, u, v):
    """Unit direction (camera link frame) of the ray through pixel (u, v)."""
    d = np.array([1.0, -(u - intr.cx) / intr.fx, -(v - intr.cy) / intr.fy])
    return d / np.linalg.norm(d)


def to_camera(pose, p_world):
    """Point in the camera frame; pose = (R 3x3, t 3) of the camera link in the world."""
    rot, t = pose
    return rot.T.dot(np.asarray(p_world, dtype=float) - t)
