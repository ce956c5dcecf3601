"""The ``libgazebo_ros_camera.so`` plugin of the /gazebo node.

For a ``<sensor type="camera">`` it publishes the sensor's optical frame in tf (through the scene
publisher: ``gazebo/<model>/<link>/<sensor>``), its Gazebo intrinsics (f = width / (2 tan(hfov/2)),
principal point (w+1)/2, (h+1)/2) on a latched internal CameraInfo topic, and registers the camera
under ``/gazebo/camera_sensors/<model>__<sensor>`` so that the camera renderer (a separate process
that the node runs while a camera is subscribed: renderer_process; the simulation never waits for
it) renders and publishes ``<robotNamespace>/<cameraName>/<imageTopicName>`` and
``.../<cameraInfoTopicName>`` at the update rate, stamped with sim time.

Depth cameras (``<sensor type="depth">``): ``libgazebo_ros_openni_kinect.so`` and
``libgazebo_ros_depth_camera.so`` register the same way with their depth image, depth CameraInfo
and point cloud topics (sensor_config.parse_depth); the renderer draws them from its depth buffer.

Zoom while running: ``<robotNamespace>/<cameraName>/set_hfov`` (std_msgs/Float64, rad) or the
service ``.../set_camera_info`` (sensor_msgs/SetCameraInfo; hfov from K[0] and the width).
"""
import math
import re
import threading

import roslib.packages
import rospkg
import rospy
from sensor_msgs.msg import CameraInfo, Image, PointCloud2
from sensor_msgs.srv import SetCameraInfo, SetCameraInfoResponse
from std_msgs.msg import Empty, Float64

from modrob_sim.camera import sensor_config
from modrob_sim.camera.renderer_process import RendererProcess, check_display
from modrob_sim.camera.scene import ScenePublisher
from modrob_sim.gazebo_ros.package_exports import PackageExports
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.plugin_base import SensorPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin

FILENAME = "libgazebo_ros_camera.so"
MIN_HFOV, MAX_HFOV = 0.01, 3.1
#: a camera's output topics (keys of its registration) and their types
OUTPUTS = (("image", Image), ("camera_info_out", CameraInfo), ("depth_image", Image),
           ("depth_camera_info", CameraInfo), ("points", PointCloud2))


def intrinsics(width, height, hfov):
    """(fx, fy, cx, cy) of Gazebo's camera: f = width / (2 tan(hfov / 2)), centre (w+1)/2, (h+1)/2."""
    f = width / (2.0 * math.tan(hfov / 2.0))
    return f, f, (width + 1.0) / 2.0, (height + 1.0) / 2.0


def camera_info(cfg, hfov, frame_id):
    """The CameraInfo gazebo_plugins publishes: Gazebo's intrinsics, or the plugin's nonzero
    ``Cx``, ``Cy`` and ``focalLength`` (the latter until the field of view is zoomed), D from the
    plugin's distortion keys. The renderer draws the image with exactly these intrinsics."""
    fx, fy, cx, cy = intrinsics(cfg.width, cfg.height, hfov)
    if cfg.focal_length > 0 and hfov == cfg.hfov:
        fx = fy = cfg.focal_length
    cx, cy = cfg.cx or cx, cfg.cy or cy
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width, info.height = cfg.width, cfg.height
    info.distortion_model = "plumb_bob"
    info.D = list(cfg.distortion)
    info.K = [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]
    info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    info.P = [fx, 0.0, cx, -fx * cfg.hack_baseline, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    return info


def _find_executable(package, name):
    try:
        found = roslib.packages.find_node(package, name)
    except rospkg.ResourceNotFound:
        return None
    return found[0] if found else None


def renderer_process(node_name):
    """The node's RendererProcess (made on first use from the node's ``~render_cameras``,
    ``~render_display`` and ``~render_idle_stop``; stopped with the node)."""
    def make():
        enabled = bool(rospy.get_param(node_name + "/render_cameras", True))
        display = rospy.get_param(node_name + "/render_display", "")
        try:
            check_display(display)
        except ValueError as err:
            rospy.logerr("%s; the renderer draws on its private Xvfb", err)
            display = ""
        proc = RendererProcess(node_name, PackageExports(), _find_executable,
                               enabled=enabled, display=display,
                               idle_stop=float(rospy.get_param(node_name + "/render_idle_stop", 10.0)))
        if not enabled:
            rospy.loginfo("%s: ~render_cameras is false: the camera sensors' images come from a renderer "
                          "you run yourself (rosrun modrob_viz camera_renderer _sensors_param:=%s)",
                          node_name, proc.sensors_param)
        rospy.on_shutdown(proc.shutdown)
        return proc
    return RendererProcess.for_node(node_name, make)


class CameraOutput(object):
    """One camera of a sensor plugin: its optical frame in the scene, its intrinsics on the latched
    internal CameraInfo topic, its registration for the renderer, its output topics advertised,
    zoom (``set_hfov``, ``set_camera_info``) and, for a triggered camera, its trigger topic."""

    def __init__(self, model, cfg, name, context):
        """``name``: the camera's name under its link: the sensor's, or 'sensor/camera' of a
        multicamera (frame ``gazebo/<model>/<link>/<name>``, registration ``<model>__<name>``)."""
        self.cfg = cfg
        self.hfov = cfg.hfov
        self.key = key = re.sub(r"[^A-Za-z0-9_]", "_", "%s__%s" % (model.name, name))
        self.scene = ScenePublisher.for_world(context.world)
        self.frame = "%s/%s" % (self.scene.link_frame(model.name, cfg.link), name)
        x, y, z, r, p, yw = cfg.pose
        pose = ((x, y, z), tf.quat_from_rpy(r, p, yw))
        if cfg.camera_pose is not None:         # a multicamera's camera, relative to the sensor
            cx, cy, cz, cr, cp, cyw = cfg.camera_pose
            pose = tf.compose(pose, ((cx, cy, cz), tf.quat_from_rpy(cr, cp, cyw)))
        optical = ((0.0, 0.0, 0.0), tf.quat_from_rpy(*sensor_config.OPTICAL_RPY))
        self.scene.add_frame(self.frame, model.name, cfg.link, tf.compose(pose, optical))
        self.renderer = renderer_process(context.node_name or "/gazebo")
        self.param = "%s/%s" % (self.renderer.sensors_param, key)
        self.info_topic = self.param + "/camera_info"
        self._info_pub = rospy.Publisher(self.info_topic, CameraInfo, queue_size=1, latch=True)
        computed = intrinsics(cfg.width, cfg.height, cfg.hfov)[0]
        if cfg.focal_length > 0 and abs(cfg.focal_length - computed) > 1e-6 * computed:
            rospy.logwarn("model '%s' camera '%s': <focalLength> %g does not agree with the image width %d "
                          "and horizontal_fov %g (width / (2 tan(hfov / 2)) = %g), as Gazebo warns; the "
                          "CameraInfo gives %g and the image is drawn with it", model.name,
                          cfg.sensor_name, cfg.focal_length, cfg.width, cfg.hfov, computed, cfg.focal_length)
        self._publish_intrinsics()
        registration = {
            "name": sensor_config.topic(cfg, "").strip("/") or key,
            "camera_info": self.info_topic, "frame": self.frame, "header_frame": cfg.frame_name,
            "image": sensor_config.topic(cfg, cfg.image_topic),
            "camera_info_out": sensor_config.topic(cfg, cfg.info_topic),
            "rate": cfg.update_rate, "format": cfg.encoding, "noise_mean": cfg.noise_mean,
            "noise_stddev": cfg.noise_stddev, "hack_baseline": cfg.hack_baseline,
            "clip_near": cfg.near, "clip_far": cfg.far}
        if cfg.lens is not None:
            registration["lens"] = dict(cfg.lens._asdict())
        if cfg.depth is not None:
            d = cfg.depth
            registration.update(
                depth_image=sensor_config.topic(cfg, d.depth_image_topic),
                depth_camera_info=sensor_config.topic(cfg, d.depth_info_topic),
                points=sensor_config.topic(cfg, d.points_topic),
                depth_format="16UC1" if d.depth16 else "32FC1", point_cloud_cutoff=d.cutoff)
            if math.isfinite(d.cutoff_max):
                registration["point_cloud_cutoff_max"] = d.cutoff_max
        self._trigger = None
        if cfg.trigger_topic is not None:
            self._trigger = TriggerRelay(sensor_config.topic(cfg, cfg.trigger_topic), self.param + "/trigger")
            registration["trigger"] = self._trigger.internal_topic
        rospy.set_param(self.param, registration)
        # advertised here too, as gzserver does: rostopic subscribes only to an advertised topic, and
        # these silent publishers count the subscribers (the renderer's publish the images)
        self._outputs = [rospy.Publisher(registration[k], cls, queue_size=1) for k, cls in OUTPUTS
                         if k in registration]
        if self._trigger is not None:
            self._trigger.image_pub = self._outputs[0]
        self.renderer.register(key, self._outputs)
        self._zoom_sub = rospy.Subscriber(sensor_config.topic(cfg, "set_hfov"), Float64, self._on_hfov,
                                          queue_size=1)
        self._zoom_srv = rospy.Service(sensor_config.topic(cfg, "set_camera_info"), SetCameraInfo,
                                       self._srv_set_info)
        rospy.loginfo("model '%s': camera '%s' on link '%s' -> %s (%dx%d %s, hfov %.3f rad, %s; "
                      "rendered while subscribed)", model.name, cfg.sensor_name, cfg.link,
                      registration["image"], cfg.width, cfg.height, cfg.encoding, cfg.hfov,
                      "one frame per message on %s" % self._trigger.topic if self._trigger is not None
                      else "%.1f Hz" % cfg.update_rate)

    def _publish_intrinsics(self):
        self._info_pub.publish(camera_info(self.cfg, self.hfov, self.cfg.frame_name))

    def set_hfov(self, hfov):
        """Zoom: new horizontal field of view [rad]; returns an error text or ''."""
        if not (isinstance(hfov, (int, float)) and math.isfinite(hfov) and MIN_HFOV <= hfov <= MAX_HFOV):
            return ("camera '%s': horizontal fov %r rad refused: give a value in [%.2f, %.2f]"
                    % (self.cfg.sensor_name, hfov, MIN_HFOV, MAX_HFOV))
        self.hfov = float(hfov)
        self._publish_intrinsics()
        return ""

    def _on_hfov(self, msg):
        err = self.set_hfov(msg.data)
        if err:
            rospy.logwarn(err)

    def _srv_set_info(self, req):
        info = req.camera_info
        if info.width and info.width != self.cfg.width:
            return SetCameraInfoResponse(False, "width %d differs from the sensor's %d: only the field "
                                         "of view "
                                         "(K[0]) can change" % (info.width, self.cfg.width))
        fx = info.K[0] if len(info.K) == 9 else 0.0
        if not (fx > 0 and math.isfinite(fx)):
            return SetCameraInfoResponse(False, "K[0] (fx) must be a positive number, got %r" % (fx,))
        err = self.set_hfov(2.0 * math.atan(self.cfg.width / (2.0 * fx)))
        return SetCameraInfoResponse(not err, err or "hfov %.4f rad" % self.hfov)

    def shutdown(self):
        self.renderer.unregister(self.key)
        for pub in self._outputs:
            pub.unregister()
        if self._trigger is not None:
            self._trigger.shutdown()
        self._zoom_sub.unregister()
        self._zoom_srv.shutdown()
        self._info_pub.unregister()
        self.scene.remove_frame(self.frame)
        try:
            rospy.delete_param(self.param)
        except KeyError:
            pass


class TriggerRelay(rospy.SubscribeListener):
    """gazebo_ros_triggered_camera's trigger: each std_msgs/Empty on ``<camera>/image_trigger``
    while the image topic has a subscriber asks for one frame (as Gazebo, which renders the frame
    but publishes it only to subscribers). The requests go to the renderer on an internal topic;
    those made before the renderer has subscribed to it (it starts with the first subscriber, seconds
    later) wait and are handed to it when it connects, so none is lost to its start-up."""

    def __init__(self, topic, internal_topic):
        self.topic = topic
        self.internal_topic = internal_topic
        self.image_pub = None
        self.waiting = 0
        self._lock = threading.Lock()
        self._pub = rospy.Publisher(internal_topic, Empty, queue_size=100, subscriber_listener=self)
        self._sub = rospy.Subscriber(topic, Empty, self._on_trigger, queue_size=100)

    def _on_trigger(self, _msg):
        if self.image_pub is None or self.image_pub.get_num_connections() == 0:
            return
        with self._lock:
            if self._pub.get_num_connections() == 0:
                self.waiting += 1
                return
        self._pub.publish(Empty())

    def peer_subscribe(self, _topic_name, _topic_publish, peer_publish):
        with self._lock:
            waiting, self.waiting = self.waiting, 0
        for _ in range(waiting):
            peer_publish(Empty())

    def shutdown(self):
        self._sub.unregister()
        self._pub.unregister()


class GazeboRosCameraPlugin(SensorPlugin):
    """No per-step work (no ``sense``: no due time): the renderer renders at the update rate from
    the published frame."""

    triggered = False

    def _parse(self, spec, model_name, namespace):
        return sensor_config.parse(spec.sensor, spec.element, spec.link, model_name, namespace)

    def _configs(self, spec, model_name, namespace):
        """[(name, CameraSensorConfig)] of the sensor's cameras (CameraOutput's name)."""
        cfg = self._parse(spec, model_name, namespace)
        return [(cfg.sensor_name, cfg)]

    def load(self, model, spec, context):
        namespace = spec.robot_namespace or getattr(context, "robot_namespace", "") or ""
        configs = self._configs(spec, model.name, namespace)
        for _suffix, cfg in configs:
            if cfg.link is None or cfg.link not in model.links:
                raise sensor_config.ModelError("model '%s' sensor '%s': its link %r is not in the model"
                                               % (model.name, cfg.sensor_name, cfg.link))
        if self.triggered:
            configs = [(suffix, cfg._replace(trigger_topic=_trigger_topic(spec.element)))
                       for suffix, cfg in configs]
        self.cameras = [CameraOutput(model, cfg, name, context) for name, cfg in configs]

    def shutdown(self):
        for cam in self.cameras:
            cam.shutdown()


def _trigger_topic(plugin):
    node = plugin.find("triggerTopicName") if plugin is not None else None
    return node.text.strip() if node is not None and node.text and node.text.strip() else "image_trigger"


class GazeboRosTriggeredCameraPlugin(GazeboRosCameraPlugin):
    """``libgazebo_ros_triggered_camera.so``: a frame for each message on
    ``<cameraName>/<triggerTopicName>`` (image_trigger), none otherwise."""

    filename = "libgazebo_ros_triggered_camera.so"
    triggered = True


class GazeboRosMultiCameraPlugin(GazeboRosCameraPlugin):
    """``libgazebo_ros_multicamera.so`` on a ``<sensor type="multicamera">`` (a stereo pair): each
    ``<camera>`` whose name contains "left" or "right" publishes under ``<cameraName>/left`` or
    ``<cameraName>/right`` (the others nothing, as gazebo_plugins), from the sensor pose plus the
    camera's ``<pose>``, all with ``frameName``; the right camera's P[3] is -fx * hackBaseline,
    the left's 0."""

    filename = "libgazebo_ros_multicamera.so"
    sensor_types = ("multicamera",)

    def _configs(self, spec, model_name, namespace):
        sensor = spec.sensor
        if sensor is None or sensor.get("type") not in self.sensor_types:
            raise sensor_config.ModelError(
                "model '%s': %s needs <sensor type=\"multicamera\">, not %r"
                % (model_name, self.filename, None if sensor is None else sensor.get("type")))
        configs, skipped = [], []
        for cam in sensor.findall("camera"):
            name = cam.get("name", "")
            side = "left" if "left" in name else "right" if "right" in name else None
            if side is None:
                skipped.append(name)
                continue
            baseline = 0.0 if side == "left" else None      # None: the plugin's hackBaseline
            cfg = sensor_config.parse(sensor, spec.element, spec.link, model_name, namespace,
                                      self.filename, types=self.sensor_types, camera=cam,
                                      name_suffix="/" + side, hack_baseline=baseline)
            configs.append(("%s/%s" % (cfg.sensor_name, name or side), cfg))
        if skipped:
            rospy.logwarn("model '%s' sensor '%s': %s publishes only cameras named with 'left' or 'right', "
                          "as gazebo_plugins; not published: %s", model_name, sensor.get("name"),
                          self.filename, ", ".join(repr(n) for n in skipped))
        if not configs:
            raise sensor_config.ModelError(
                "model '%s' sensor '%s': %s found no <camera name=\"...left...\"> or "
                "<camera name=\"...right...\"> in the sensor"
                % (model_name, sensor.get("name"), self.filename))
        return configs


class GazeboRosTriggeredMultiCameraPlugin(GazeboRosMultiCameraPlugin):
    """``libgazebo_ros_triggered_multicamera.so``: the stereo pair, each camera triggered on its own
    topic (``<cameraName>/left/image_trigger``, ``.../right/image_trigger``), as gazebo_plugins."""

    filename = "libgazebo_ros_triggered_multicamera.so"
    triggered = True


class GazeboRosOpenniKinectPlugin(GazeboRosCameraPlugin):
    """``libgazebo_ros_openni_kinect.so``: a depth camera (rgb, depth image, points)."""

    filename = "libgazebo_ros_openni_kinect.so"

    def _parse(self, spec, model_name, namespace):
        return sensor_config.parse_depth(spec.sensor, spec.element, spec.link, model_name, namespace,
                                         self.filename)


class GazeboRosDepthCameraPlugin(GazeboRosOpenniKinectPlugin):
    """``libgazebo_ros_depth_camera.so``: the same without an upper point cloud cutoff."""

    filename = "libgazebo_ros_depth_camera.so"


register_plugin(FILENAME, GazeboRosCameraPlugin)
register_plugin(GazeboRosOpenniKinectPlugin.filename, GazeboRosOpenniKinectPlugin)
register_plugin(GazeboRosDepthCameraPlugin.filename, GazeboRosDepthCameraPlugin)
register_plugin(GazeboRosTriggeredCameraPlugin.filename, GazeboRosTriggeredCameraPlugin)
register_plugin(GazeboRosMultiCameraPlugin.filename, GazeboRosMultiCameraPlugin)
register_plugin(GazeboRosTriggeredMultiCameraPlugin.filename, GazeboRosTriggeredMultiCameraPlugin)
