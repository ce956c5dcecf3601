"""Validated camera definitions for the renderer (pure).

A camera is a dict (from the ``~cameras`` parameter, or from a simulator camera sensor under
``/gazebo/camera_sensors``) with these keys::

    name          unique id (also names the renderer's internal topics)
    image         output sensor_msgs/Image topic                                 (required)
    camera_info   input sensor_msgs/CameraInfo topic giving the pinhole (and, in its header,
                  the frame) - the seed's rviz_camera_stream interface
    width height fx [fy cx cy]   fixed intrinsics instead of a camera_info topic
    frame         tf frame to render from (optical convention: z forward, x right, y down);
                  default: the camera_info header's frame_id
    header_frame  frame_id written into the output (default: frame)
    camera_info_out  output CameraInfo topic, stamped like each image (default: none)
    rate          frames per second (default: the node's ~rate)
    format        rgb8 | bgr8 | mono8 | mono16 | rgb16 | bayer_rggb8 | bayer_bggr8 | bayer_gbrg8 |
                  bayer_grbg8, or Gazebo's R8G8B8 | B8G8R8 | L8 (default rgb8)
    noise_mean noise_stddev   Gazebo's gaussian image noise, in units of full scale (0..1)
    hack_baseline  Gazebo's hackBaseline [m]: P[3] = -fx * baseline
    clip_near clip_far  nothing nearer or farther (m) is drawn (0.01, 100)
    lens          Brown's lens distortion drawn into the image: {k1, k2, k3, p1, p2, center_x,
                  center_y} (centre in fractions of the image, 0.5 = the principal point; lens.py)
    trigger       a std_msgs/Empty topic: one frame per message instead of frames at ``rate``
                  (Gazebo's triggered camera)

A depth camera (Gazebo's depth sensor) has any of these output topics besides its image:

    depth_image        sensor_msgs/Image of the depth along the optical axis (depth.py)
    depth_camera_info  its CameraInfo, stamped like each depth image
    points             sensor_msgs/PointCloud2, xyz + rgb, in header_frame
    depth_format       32FC1 (metres, default) | 16UC1 (millimetres)
    point_cloud_cutoff point_cloud_cutoff_max   depths kept (m): cutoff < depth < max (0, inf)
"""
import math
import re

from modrob_viz.errors import ConfigError
from modrob_viz.render import depth, pinhole

FORMATS = {"rgb8": "rgb8", "bgr8": "bgr8", "mono8": "mono8", "mono16": "mono16", "rgb16": "rgb16",
           "bayer_rggb8": "bayer_rggb8", "bayer_bggr8": "bayer_bggr8", "bayer_gbrg8": "bayer_gbrg8",
           "bayer_grbg8": "bayer_grbg8",
           "R8G8B8": "rgb8", "B8G8R8": "bgr8", "L8": "mono8", "RGB_INT8": "rgb8", "BGR_INT8": "bgr8"}
LENS_KEYS = ("k1", "k2", "k3", "p1", "p2", "center_x", "center_y")


def internal_name(name):
    """A topic-safe id: 'ptrz/camera1' -> 'ptrz_camera1'."""
    return re.sub(r"[^A-Za-z0-9_]", "_", name.strip("/")) or "camera"


def _num(spec, key, default, where):
    value = spec.get(key, default)
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ConfigError("%s: %s must be a number, got %r" % (where, key, spec.get(key)))
    if not math.isfinite(value):
        raise ConfigError("%s: %s must be finite, got %r" % (where, key, value))
    return value


CLIP_NEAR, CLIP_FAR = 0.01, 100.0     # RViz's camera clip distances (m), for cameras that give none


def parse(spec, default_rate, where="camera"):
    """A normalised camera dict, or ConfigError naming the camera and the key."""
    if not isinstance(spec, dict):
        raise ConfigError("%s must be a dict with at least 'name' and 'image', got %r" % (where, spec))
    name = str(spec.get("name", "")).strip()
    if not name:
        raise ConfigError("%s has no 'name'" % where)
    where = "camera '%s'" % name
    image = str(spec.get("image", "")).strip()
    if not image:
        raise ConfigError("%s has no 'image' output topic" % where)
    out = dict(name=name, id=internal_name(name), image=image,
               camera_info=str(spec.get("camera_info", "") or ""),
               frame=str(spec.get("frame", "") or ""),
               header_frame=str(spec.get("header_frame", "") or ""),
               camera_info_out=str(spec.get("camera_info_out", "") or ""))
    out["rate"] = _num(spec, "rate", default_rate, where)
    if out["rate"] <= 0:
        raise ConfigError("%s: rate must be > 0, got %r" % (where, out["rate"]))
    fmt = str(spec.get("format", "rgb8"))
    if fmt not in FORMATS:
        raise ConfigError("%s: format %r is not supported; use one of %s"
                          % (where, fmt, ", ".join(sorted(FORMATS))))
    out["format"] = FORMATS[fmt]
    out["noise_mean"] = _num(spec, "noise_mean", 0.0, where)
    out["noise_stddev"] = _num(spec, "noise_stddev", 0.0, where)
    if out["noise_stddev"] < 0:
        raise ConfigError("%s: noise_stddev must be >= 0" % where)
    out["hack_baseline"] = _num(spec, "hack_baseline", 0.0, where)
    out["clip_near"] = _num(spec, "clip_near", CLIP_NEAR, where)
    out["clip_far"] = _num(spec, "clip_far", CLIP_FAR, where)
    if not 0 < out["clip_near"] < out["clip_far"]:
        raise ConfigError("%s: clip needs 0 < clip_near < clip_far, got %r and %r"
                          % (where, out["clip_near"], out["clip_far"]))
    lens = spec.get("lens")
    out["lens"] = None
    if lens not in (None, "", {}):
        if not isinstance(lens, dict) or set(lens) - set(LENS_KEYS):
            raise ConfigError("%s: lens must be a dict of %s, got %r" % (where, ", ".join(LENS_KEYS), lens))
        out["lens"] = tuple(_num(lens, k, 0.5 if k.startswith("center") else 0.0, where + " lens")
                            for k in LENS_KEYS)
    out["trigger"] = str(spec.get("trigger", "") or "")
    for key in ("depth_image", "depth_camera_info", "points"):
        out[key] = str(spec.get(key, "") or "")
    out["depth_format"] = str(spec.get("depth_format", "32FC1"))
    if out["depth_format"] not in depth.DEPTH_FORMATS:
        raise ConfigError("%s: depth_format %r is not supported; use one of %s"
                          % (where, out["depth_format"], ", ".join(depth.DEPTH_FORMATS)))
    out["point_cloud_cutoff"] = _num(spec, "point_cloud_cutoff", 0.0, where)
    cmax = spec.get("point_cloud_cutoff_max")
    out["point_cloud_cutoff_max"] = (float("inf") if cmax in (None, "", "inf") or cmax == float("inf")
                                     else _num(spec, "point_cloud_cutoff_max", 0.0, where))
    if not out["point_cloud_cutoff"] < out["point_cloud_cutoff_max"]:
        raise ConfigError("%s: point_cloud_cutoff %r must be below point_cloud_cutoff_max %r"
                          % (where, out["point_cloud_cutoff"], out["point_cloud_cutoff_max"]))
    out["depth"] = bool(out["depth_image"] or out["depth_camera_info"] or out["points"])
    out["intrinsics"] = None
    if not out["camera_info"]:
        if "width" not in spec or "fx" not in spec and "hfov" not in spec:
            raise ConfigError("%s needs a 'camera_info' topic or fixed intrinsics "
                              "(width, height and fx or hfov)" % where)
        w, h = pinhole.check_size(spec.get("width"), spec.get("height"), where)
        if "hfov" in spec:
            out["intrinsics"] = pinhole.gazebo_intrinsics(w, h, spec["hfov"])
        else:
            fx = _num(spec, "fx", 0.0, where)
            fy = _num(spec, "fy", fx, where)
            out["intrinsics"] = pinhole.Intrinsics(w, h, fx, fy, _num(spec, "cx", w / 2.0, where),
                                                   _num(spec, "cy", h / 2.0, where))
            if fx <= 0 or fy <= 0:
                raise ConfigError("%s: fx and fy must be > 0" % where)
        if not out["frame"]:
            raise ConfigError("%s: fixed intrinsics need a 'frame' to render from" % where)
    return out


def parse_all(specs, default_rate, where="~cameras"):
    """List of camera dicts; names must be unique."""
    if specs in (None, ""):
        return []
    if isinstance(specs, dict):
        specs = [dict(v, name=v.get("name", k)) if isinstance(v, dict) else v
                 for k, v in sorted(specs.items())]
    if not isinstance(specs, list):
        raise ConfigError("%s must be a list of camera dicts, got %r" % (where, specs))
    cams, seen = [], set()
    for i, spec in enumerate(specs):
        cam = parse(spec, default_rate, "%s[%d]" % (where, i))
        if cam["id"] in seen:
            raise ConfigError("%s: two cameras are named %r" % (where, cam["name"]))
        seen.add(cam["id"])
        cams.append(cam)
    return cams


def apply_noise(img, mean, stddev, rng):
    """Gazebo's gaussian pixel noise (units of full scale), clipped to 0..255; img uint8."""
    if stddev <= 0 and mean == 0:
        return img
    import numpy as np
    noisy = img.astype(np.float32) + rng.normal(mean * 255.0, stddev * 255.0, img.shape).astype(np.float32)
    return np.clip(noisy, 0, 255).astype(np.uint8)


def convert(img, fmt):
    """RGB uint8 (h, w, 3) -> (array, encoding, step) in the camera's format (an encoding of
    FORMATS' values). 16-bit: the 8-bit value times 257 (full scale to full scale), little-endian;
    mono: luminance 0.299 R + 0.587 G + 0.114 B; bayer_xyzw8: one colour a pixel, the 2x2 pattern
    x y / z w from the top-left pixel (as Gazebo's camera makes its BAYER formats)."""
    import numpy as np
    if fmt == "bgr8":
        img = img[:, :, ::-1]
    elif fmt in ("mono8", "mono16"):
        lum = 0.299 * img[:, :, 0] + 0.587 * img[:, :, 1] + 0.114 * img[:, :, 2]
        if fmt == "mono8":
            return lum.astype(np.uint8), fmt, img.shape[1]
        return (np.rint(lum) * 257).astype("<u2"), fmt, img.shape[1] * 2
    elif fmt == "rgb16":
        return img.astype("<u2") * 257, fmt, img.shape[1] * 6
    elif fmt.startswith("bayer_"):
        out = np.empty(img.shape[:2], np.uint8)
        for colour, (dy, dx) in zip(fmt[len("bayer_"):len("bayer_") + 4], ((0, 0), (0, 1), (1, 0), (1, 1))):
            out[dy::2, dx::2] = img[dy::2, dx::2, "rgb".index(colour)]
        return out, fmt, img.shape[1]
    return img, fmt, img.shape[1] * 3


def screen_size(text):
    """'4096x2304' -> (4096, 2304), or ConfigError."""
    try:
        w, h = (int(v) for v in str(text).lower().split("x"))
    except ValueError:
        raise ConfigError("~screen must look like 4096x2304, got %r" % (text,))
    if w < 64 or h < 64:
        raise ConfigError("~screen %dx%d is too small" % (w, h))
    return w, h


def colour(text):
    """'178,178,178' -> (178, 178, 178), or ConfigError."""
    try:
        rgb = tuple(int(v) for v in str(text).split(","))
    except ValueError:
        rgb = ()
    if len(rgb) != 3 or not all(0 <= c <= 255 for c in rgb):
        raise ConfigError("~background must be 'r,g,b' with values 0..255, got %r" % (text,))
    return rgb
