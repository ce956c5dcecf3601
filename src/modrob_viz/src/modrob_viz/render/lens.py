"""Lens distortion drawn into a rendered image (Gazebo's ``<camera><distortion>``).

Brown's model as ROS's CameraInfo ``plumb_bob`` D = (k1, k2, p1, p2, k3) and OpenCV describe it: a
point at normalised pinhole coordinates (x, y) (relative to the distortion centre, in focal
lengths) appears in the image at

    r2 = x^2 + y^2,  s = 1 + k1 r2 + k2 r2^2 + k3 r2^3
    x_d = x s + 2 p1 x y + p2 (r2 + 2 x^2),   y_d = y s + p1 (r2 + 2 y^2) + 2 p2 x y

The centre is SDF's ``<center>`` in fractions of the image; 0.5 0.5 is the principal point of the
CameraInfo (cx, cy), so with the default centre a consumer undistorting with the published D and K
(image_proc, ``cv2.undistort``) gets the pinhole image back. Each output pixel takes the colour of
the pinhole render where its undistorted point lies (bilinear); pixels whose point lies outside the
render are black, as Gazebo's uncropped distortion (``borderCrop`` false) leaves them. (Pure.)
"""
import numpy as np

ITERATIONS = 20         # fixed-point steps inverting the model (|error| < 1e-6 px for usual lenses)


def centre(intr, lens):
    """The distortion centre in pixels: the principal point moved by (center - 0.5) image sizes."""
    return (intr.cx + (lens[5] - 0.5) * intr.width, intr.cy + (lens[6] - 0.5) * intr.height)


def distort_normalised(x, y, lens):
    """Where normalised pinhole coordinates (x, y) land with the lens (arrays or floats)."""
    k1, k2, k3, p1, p2 = lens[:5]
    r2 = x * x + y * y
    s = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
    return (x * s + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
            y * s + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y)


def source_maps(intr, lens):
    """(map_x, map_y) float32 (h, w): for each pixel of the distorted image, the pinhole render's
    pixel that it shows (the model inverted by fixed-point iteration)."""
    uc, vc = centre(intr, lens)
    u, v = np.meshgrid(np.arange(intr.width, dtype=np.float64), np.arange(intr.height, dtype=np.float64))
    # pixel (column u, row v) is at u, v: the renderer draws a point where the CameraInfo projects it
    xd, yd = (u - uc) / intr.fx, (v - vc) / intr.fy
    x, y = xd.copy(), yd.copy()
    with np.errstate(all="ignore"):
        for _ in range(ITERATIONS):
            fx_, fy_ = distort_normalised(x, y, lens)
            x, y = x + (xd - fx_), y + (yd - fy_)
        # where the model folds back (a strong barrel far out) no point lands: black there
        fx_, fy_ = distort_normalised(x, y, lens)
        lost = ~(np.abs(fx_ - xd) * intr.fx < 0.01) | ~(np.abs(fy_ - yd) * intr.fy < 0.01)
    x[lost] = y[lost] = -1e4
    return (x * intr.fx + uc).astype(np.float32), (y * intr.fy + vc).astype(np.float32)


def apply(img, maps):
    """The distorted image: img (h, w[, c]) sampled at maps (bilinear), black outside."""
    import cv2
    return cv2.remap(img, maps[0], maps[1], cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
