"""Synthetic camera images from the pinhole model (for tests and for checking the tracking core
without a renderer): a green floor with white lines, a magenta ball, grey sky."""
import numpy as np

from ptrz_camera import pinhole

SKY = (170, 190, 210)
FLOOR = (46, 140, 56)
BALL = (230, 0, 190)


def render(pose, intr, ball_centre, ball_radius, noise=0.0, rng=None):
    """RGB uint8 image (height x width x 3) of the ball on the floor seen from ``pose``."""
    rot, t = pose
    us, vs = np.meshgrid(np.arange(intr.width), np.arange(intr.height))     # pixel centres (ROS)
    d_cam = np.stack([np.ones_like(us), -(us - intr.cx) / intr.fx, -(vs - intr.cy) / intr.fy], axis=-1)
    d = d_cam.dot(rot.T)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    img = np.empty((intr.height, intr.width, 3), np.float64)
    img[:] = SKY
    down = d[..., 2] < 0
    s_floor = np.where(down, -t[2] / np.where(down, d[..., 2], -1), np.inf)
    img[down] = FLOOR
    p = t + s_floor[..., None] * d
    on_x = np.abs(np.mod(p[..., 0], 1.0) - 0.5) < 0.02
    lines = down & (on_x | (np.abs(np.mod(p[..., 1], 1.0) - 0.5) < 0.02))
    img[lines] = (240, 240, 240)
    oc = t - np.asarray(ball_centre, dtype=float)
    b = d.dot(oc)
    c = oc.dot(oc) - ball_radius ** 2
    disc = b * b - c
    hit = (disc >= 0) & (-b - np.sqrt(np.maximum(disc, 0)) > 0)
    shade = 0.75 + 0.25 * np.clip(-d[..., 2], 0, 1)
    img[hit] = np.outer(shade[hit], BALL)
    if noise:
        rng = rng or np.random.default_rng(0)
        img += rng.normal(0.0, noise * 255.0, img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def project_point(pose, intr, p_world):
    return pinhole.project(intr, pinhole.to_camera(pose, p_world))
