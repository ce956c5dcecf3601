"""A Gazebo camera sensor and its ``libgazebo_ros_camera.so`` plugin, read from XML (pure).

SDF ``<sensor type="camera">``: ``<update_rate>``, ``<pose>``, ``<camera>`` with
``<horizontal_fov>`` (default 1.047 rad), ``<image><width><height><format>`` (320 x 240, R8G8B8;
the formats Gazebo names, each to the sensor_msgs encoding gazebo_plugins publishes: FORMATS),
``<clip><near><far>`` (0.1, 100), ``<noise><type>gaussian</type><mean><stddev>``,
``<distortion><k1><k2><k3><p1><p2><center>`` (Brown's model, centre in image fractions, 0.5 0.5;
drawn into the image: ``lens``).
Plugin: ``cameraName`` (""), ``imageTopicName`` (image_raw), ``cameraInfoTopicName``
(camera_info), ``frameName`` (world), ``updateRate`` (0 = the sensor's rate), ``hackBaseline``
(0), ``robotNamespace``; ``distortionK1..K3``, ``distortionT1``, ``distortionT2`` (CameraInfo's D,
or the sensor's ``<distortion>`` with ``autoDistortion`` true), ``Cx``, ``Cy``, ``focalLength``
(0 = Gazebo's: (w + 1) / 2, (h + 1) / 2, w / (2 tan(hfov / 2))); ``CxPrime``, ``borderCrop``,
``alwaysOn`` are accepted. ``triggerTopicName`` (image_trigger) for the triggered cameras.

Depth cameras (``<sensor type="depth">``, :func:`parse_depth`): ``libgazebo_ros_openni_kinect.so``
and ``libgazebo_ros_depth_camera.so`` take the camera's keys with the image topics defaulting to
``ir/image_raw`` and ``ir/camera_info``, and ``depthImageTopicName`` (depth/image_raw),
``depthImageCameraInfoTopicName`` (depth/camera_info), ``pointCloudTopicName`` (points),
``pointCloudCutoff`` (0.4 m), ``pointCloudCutoffMax`` (5 m; the openni_kinect plugin only: the
depth_camera plugin has no upper cutoff), ``useDepth16UC1Format`` (false), ``baseline`` (accepted).
"""
import collections
import math

from modrob_sim.errors import ModelError

CameraSensorConfig = collections.namedtuple(
    "CameraSensorConfig",
    "sensor_name link pose update_rate hfov width height format near far noise_mean noise_stddev "
    "camera_name image_topic info_topic frame_name hack_baseline distortion robot_namespace depth "
    "encoding cx cy focal_length lens camera_pose trigger_topic")
CameraSensorConfig.__new__.__defaults__ = (None, "rgb8", 0.0, 0.0, 0.0, None, None, None)

#: Gazebo's ``<image><format>`` names -> the sensor_msgs encoding gazebo_plugins publishes them in
FORMATS = {"R8G8B8": "rgb8", "RGB_INT8": "rgb8", "B8G8R8": "bgr8", "BGR_INT8": "bgr8",
           "L8": "mono8", "L_INT8": "mono8", "L16": "mono16", "L_INT16": "mono16",
           "R16G16B16": "rgb16", "RGB_INT16": "rgb16",
           "BAYER_RGGB8": "bayer_rggb8", "BAYER_BGGR8": "bayer_bggr8", "BAYER_GBRG8": "bayer_gbrg8",
           "BAYER_GRBG8": "bayer_grbg8"}
#: Brown's lens model as SDF gives it (``<distortion>``): k1 k2 k3 p1 p2 and the centre (fractions)
Lens = collections.namedtuple("Lens", "k1 k2 k3 p1 p2 center_x center_y")

#: a depth camera's own outputs (``CameraSensorConfig.depth``; None for a plain camera)
DepthConfig = collections.namedtuple(
    "DepthConfig", "depth_image_topic depth_info_topic points_topic cutoff cutoff_max depth16")
DEFAULT_RATE = 30.0      # Hz, when neither the sensor nor the plugin gives one (Gazebo: unlimited)


def _text(elem, path, default=None):
    if elem is None:
        return default
    node = elem.find(path)
    if node is None or node.text is None or not node.text.strip():
        return default
    return node.text.strip()


def _float(elem, path, default, where):
    text = _text(elem, path)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        raise ModelError("%s: <%s> must be a number, got %r" % (where, path, text))
    if not math.isfinite(value):
        raise ModelError("%s: <%s> must be finite, got %r" % (where, path, text))
    return value


def _pose(text, where):
    if text is None:
        return (0.0,) * 6
    try:
        v = tuple(float(x) for x in text.split())
    except ValueError:
        v = ()
    if len(v) != 6:
        raise ModelError("%s: <pose> needs 6 numbers 'x y z roll pitch yaw', got %r" % (where, text))
    return v


def _lens(cam, where):
    """Lens of the <camera>'s <distortion>, or None (none, or every coefficient 0)."""
    dist = cam.find("distortion") if cam is not None else None
    if dist is None:
        return None
    k = [_float(dist, key, 0.0, where) for key in ("k1", "k2", "k3", "p1", "p2")]
    centre = _text(dist, "center", "0.5 0.5")
    try:
        cx, cy = (float(v) for v in centre.split())
    except ValueError:
        raise ModelError("%s: <distortion><center> needs 2 numbers (fractions of the image), got %r"
                         % (where, centre))
    if not all(math.isfinite(v) for v in (cx, cy)):
        raise ModelError("%s: <distortion><center> must be finite, got %r" % (where, centre))
    return Lens(*(k + [cx, cy])) if any(k) else None


def parse(sensor, plugin, link, model_name, spawn_namespace="", filename="libgazebo_ros_camera.so",
          types=("camera", "wideanglecamera"), image_topic="image_raw", info_topic="camera_info",
          camera=None, name_suffix="", hack_baseline=None):
    """CameraSensorConfig from the <sensor> and <plugin> Elements, or ModelError naming the model,
    the sensor and the element. ``filename``, ``types`` and the topic defaults are those of the
    plugin read (parse_depth for the depth cameras). ``camera``: one <camera> of a multicamera
    sensor (default: the sensor's first), ``name_suffix`` added to cameraName and
    ``hack_baseline`` instead of the plugin's, as gazebo_ros_multicamera gives each camera."""
    sname = sensor.get("name", "camera") if sensor is not None else "camera"
    where = "model '%s' sensor '%s'" % (model_name, sname)
    if sensor is None:
        raise ModelError("%s: %s must be inside a <sensor type=\"%s\">" % (where, filename, types[0]))
    stype = sensor.get("type", "")
    if stype not in types:
        raise ModelError("%s: %s needs <sensor type=\"%s\">, not type=%r"
                         % (where, filename, types[0], stype))
    cam = sensor.find("camera") if camera is None else camera
    hfov = _float(cam, "horizontal_fov", 1.047, where)
    if not 0.01 <= hfov <= 3.1:
        raise ModelError("%s: <horizontal_fov> %g rad is outside [0.01, 3.1]" % (where, hfov))
    width = _float(cam, "image/width", 320, where)
    height = _float(cam, "image/height", 240, where)
    if not (1 <= width <= 8192 and 1 <= height <= 8192) or width != int(width) or height != int(height):
        raise ModelError("%s: <image> width/height must be whole numbers 1..8192, got %g x %g"
                         % (where, width, height))
    fmt = _text(cam, "image/format", "R8G8B8")
    if fmt not in FORMATS:
        raise ModelError("%s: <image><format> %r is not supported; use one of %s"
                         % (where, fmt, ", ".join(sorted(FORMATS))))
    near = _float(cam, "clip/near", 0.1, where)
    far = _float(cam, "clip/far", 100.0, where)
    if not 0 < near < far:
        raise ModelError("%s: <clip> needs 0 < near < far, got near %g far %g" % (where, near, far))
    noise = cam.find("noise") if cam is not None else None
    mean = stddev = 0.0
    if noise is not None:
        ntype = _text(noise, "type", "gaussian")
        if ntype not in ("gaussian", "none"):
            raise ModelError("%s: <noise><type> %r is not supported; use gaussian" % (where, ntype))
        if ntype == "gaussian":
            mean = _float(noise, "mean", 0.0, where)
            stddev = _float(noise, "stddev", 0.0, where)
            if stddev < 0:
                raise ModelError("%s: <noise><stddev> must not be negative" % where)
    rate = _float(plugin, "updateRate", 0.0, where)
    if rate <= 0:
        rate = _float(sensor, "update_rate", 0.0, where)
    if rate <= 0:
        rate = DEFAULT_RATE
    where_p = "%s plugin" % where
    lens = _lens(cam, where)
    if _bool(plugin, "autoDistortion", False, where_p):
        # CameraInfo's D from the sensor's lens, in ROS's order k1 k2 p1 p2 k3
        distortion = [lens.k1, lens.k2, lens.p1, lens.p2, lens.k3] if lens is not None else [0.0] * 5
    else:
        distortion = [_float(plugin, k, 0.0, where_p) for k in
                      ("distortionK1", "distortionK2", "distortionT1", "distortionT2", "distortionK3")]
    _bool(plugin, "borderCrop", True, where_p)
    cx, cy, focal = (_float(plugin, k, 0.0, where_p) for k in ("Cx", "Cy", "focalLength"))
    if cx < 0 or cy < 0 or focal < 0:
        raise ModelError("%s: <Cx>, <Cy> and <focalLength> must be >= 0 (0: Gazebo's value), got %g %g %g"
                         % (where_p, cx, cy, focal))
    ns = _text(plugin, "robotNamespace", None)
    ns = spawn_namespace if ns is None else ns
    camera_name = _text(plugin, "cameraName", "")
    if hack_baseline is None:
        hack_baseline = _float(plugin, "hackBaseline", 0.0, where_p)
    return CameraSensorConfig(
        sensor_name=sname, link=link, pose=_pose(_text(sensor, "pose"), where), update_rate=rate, hfov=hfov,
        width=int(width), height=int(height), format=fmt, near=near, far=far, noise_mean=mean,
        noise_stddev=stddev, camera_name=camera_name + name_suffix,
        image_topic=_text(plugin, "imageTopicName", image_topic),
        info_topic=_text(plugin, "cameraInfoTopicName", info_topic),
        frame_name=_text(plugin, "frameName", "world"),
        hack_baseline=hack_baseline, distortion=distortion, robot_namespace=ns.strip("/"),
        encoding=FORMATS[fmt], cx=cx, cy=cy, focal_length=focal, lens=lens,
        camera_pose=_pose(_text(cam, "pose"), where) if camera is not None else None)


DEPTH_PLUGINS = {"libgazebo_ros_openni_kinect.so": 5.0, "libgazebo_ros_depth_camera.so": math.inf}


def _bool(elem, path, default, where):
    text = _text(elem, path)
    if text is None:
        return default
    if text.lower() in ("1", "true"):
        return True
    if text.lower() in ("0", "false"):
        return False
    raise ModelError("%s: <%s> must be true or false, got %r" % (where, path, text))


def parse_depth(sensor, plugin, link, model_name, spawn_namespace="",
                filename="libgazebo_ros_openni_kinect.so"):
    """CameraSensorConfig (with ``depth``) of a ``<sensor type="depth">`` and its openni_kinect or
    depth_camera plugin, with those plugins' defaults; ModelError naming what is wrong."""
    cfg = parse(sensor, plugin, link, model_name, spawn_namespace, filename, types=("depth",),
                image_topic="ir/image_raw", info_topic="ir/camera_info")
    where = "model '%s' sensor '%s' plugin %s" % (model_name, cfg.sensor_name, filename)
    cutoff = _float(plugin, "pointCloudCutoff", 0.4, where)
    cutoff_max = DEPTH_PLUGINS[filename]
    if math.isfinite(cutoff_max):
        cutoff_max = _float(plugin, "pointCloudCutoffMax", cutoff_max, where)
    if cutoff < 0 or not cutoff < cutoff_max:
        raise ModelError("%s: <pointCloudCutoff> %g must be >= 0 and below <pointCloudCutoffMax> %g"
                         % (where, cutoff, cutoff_max))
    _float(plugin, "baseline", 0.0, where)
    return cfg._replace(depth=DepthConfig(
        depth_image_topic=_text(plugin, "depthImageTopicName", "depth/image_raw"),
        depth_info_topic=_text(plugin, "depthImageCameraInfoTopicName", "depth/camera_info"),
        points_topic=_text(plugin, "pointCloudTopicName", "points"),
        cutoff=cutoff, cutoff_max=cutoff_max,
        depth16=_bool(plugin, "useDepth16UC1Format", False, where)))


def topic(cfg, name):
    """'/<robotNamespace>/<cameraName>/<name>' without empty parts."""
    parts = [p.strip("/") for p in (cfg.robot_namespace, cfg.camera_name, name) if p and p.strip("/")]
    return "/" + "/".join(parts)


#: Gazebo's camera looks along its link's +x with +z up; the optical frame (z forward, x right,
#: y down) is that frame turned by roll -pi/2, yaw -pi/2 (as in every Gazebo camera URDF).
OPTICAL_RPY = (-math.pi / 2.0, 0.0, -math.pi / 2.0)
