"""Zoom of the PTRZ camera: its horizontal field of view (seed 002 section 2.3: "enlarging this
number gives that the camera will zoom out"), limited to the physical range of the camera model.

Units: the ``<ns>/zoom`` topic carries the horizontal field of view in radians
(``std_msgs/Float64``). The zoom factor of a field of view is the focal-length ratio to the
nominal field of view, ``tan(nominal/2) / tan(fov/2)`` (1 at the nominal 1.3962634 rad)."""
import math

from ptrz_camera.errors import ZoomRangeError

NOMINAL_FOV = 1.3962634          # seed 002 section 2.3 (80 deg)
WIDE_FOV = 2.7925268             # seed 002 figure 2.6 / appendix B.1 (160 deg): the widest setting
MAX_ZOOM = 20.0                  # a 20x optical zoom lens at the nominal field of view
TELE_FOV = 2.0 * math.atan(math.tan(NOMINAL_FOV / 2.0) / MAX_ZOOM)   # 0.0839 rad (4.8 deg)


def zoom_factor(fov, nominal=NOMINAL_FOV):
    return math.tan(nominal / 2.0) / math.tan(fov / 2.0)


def fov_for_zoom(factor, nominal=NOMINAL_FOV):
    return 2.0 * math.atan(math.tan(nominal / 2.0) / factor)


def focal_length_px(fov, width):
    """Gazebo's camera intrinsics: f = width / (2 tan(hfov / 2)) pixels, square pixels."""
    return width / (2.0 * math.tan(fov / 2.0))


def check_fov(fov, fov_min=TELE_FOV, fov_max=WIDE_FOV):
    """``fov`` as float if it is inside [fov_min, fov_max], else ZoomRangeError saying why."""
    try:
        fov = float(fov)
    except (TypeError, ValueError):
        raise ZoomRangeError("zoom: %r is not a number (send the horizontal field of view in rad)" % (fov,))
    if not math.isfinite(fov):
        raise ZoomRangeError("zoom: field of view %r is not finite" % fov)
    if fov < fov_min or fov > fov_max:
        raise ZoomRangeError("zoom: field of view %.4f rad is outside the camera's range [%.4f, %.4f] rad "
                             "(zoom %.2fx..%.2fx); send a value inside it"
                             % (fov, fov_min, fov_max, zoom_factor(fov_max), zoom_factor(fov_min)))
    return fov
