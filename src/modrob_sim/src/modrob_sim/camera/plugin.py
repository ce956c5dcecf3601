"""The ``libgazebo_ros_camera.so`` plugin of the /gazebo node.

For a ``<sensor type="camera">`` it publishes the sensor's optical frame in tf (through the scene
publisher: ``gazebo/<model>/<link>/<sensor>``), its Gazebo intrinsics (f = width / (2 tan(hfov/2)),
principal point (w+1)/2, (h+1)/2) on a latched internal CameraInfo topic, and registers the camera
under ``/gazebo/camera_sensors/<model>__<sensor>`` so that the ``camera_renderer`` node (a separate
process: the simulation never waits for it) renders and publishes
``<robotNamespace>/<cameraName>/<imageTopicName>`` and ``.../<cameraInfoTopicName>`` at the
update rate, stamped with sim time.

Zoom while running: ``<robotNamespace>/<cameraName>/set_hfov`` (std_msgs/Float64, rad) or the
service ``.../set_camera_info`` (sensor_msgs/SetCameraInfo; hfov from K[0] and the width).
"""
import math
import re

import rospy
from sensor_msgs.msg import CameraInfo
from sensor_msgs.srv import SetCameraInfo, SetCameraInfoResponse
from std_msgs.msg import Float64

from modrob_sim.camera import sensor_config
from modrob_sim.camera.scene import ScenePublisher
from modrob_sim.gazebo_ros import transforms as tf
from modrob_sim.gazebo_ros.plugin_base import SensorPlugin
from modrob_sim.gazebo_ros.plugins import register_plugin

FILENAME = "libgazebo_ros_camera.so"
MIN_HFOV, MAX_HFOV = 0.01, 3.1


def intrinsics(width, height, hfov):
    """(fx, fy, cx, cy) of Gazebo's camera: f = width / (2 tan(hfov / 2)), centre (w+1)/2, (h+1)/2."""
    f = width / (2.0 * math.tan(hfov / 2.0))
    return f, f, (width + 1.0) / 2.0, (height + 1.0) / 2.0


def camera_info(cfg, hfov, frame_id):
    fx, fy, cx, cy = intrinsics(cfg.width, cfg.height, hfov)
    info = CameraInfo()
    info.header.frame_id = frame_id
    info.width, info.height = cfg.width, cfg.height
    info.distortion_model = "plumb_bob"
    info.D = list(cfg.distortion)
    info.K = [fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]
    info.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    info.P = [fx, 0.0, cx, -fx * cfg.hack_baseline, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    return info


class GazeboRosCameraPlugin(SensorPlugin):
    """No per-step work (no ``sense``: no due time): the renderer renders at the update rate from
    the published frame."""

    def load(self, model, spec, context):
        cfg = sensor_config.parse(spec.sensor, spec.element, spec.link, model.name,
                                  spec.robot_namespace or getattr(context, "robot_namespace", "") or "")
        if cfg.link is None or cfg.link not in model.links:
            raise sensor_config.ModelError("model '%s' sensor '%s': its link %r is not in the model"
                                           % (model.name, cfg.sensor_name, cfg.link))
        self.cfg = cfg
        self.hfov = cfg.hfov
        self.key = re.sub(r"[^A-Za-z0-9_]", "_", "%s__%s" % (model.name, cfg.sensor_name))
        self.scene = ScenePublisher.for_world(context.world)
        self.frame = "%s/%s" % (self.scene.link_frame(model.name, cfg.link), cfg.sensor_name)
        x, y, z, r, p, yw = cfg.pose
        sensor_pose = ((x, y, z), tf.quat_from_rpy(r, p, yw))
        optical = ((0.0, 0.0, 0.0), tf.quat_from_rpy(*sensor_config.OPTICAL_RPY))
        self.scene.add_frame(self.frame, model.name, cfg.link, tf.compose(sensor_pose, optical))
        base = (context.node_name or "/gazebo").rstrip("/") + "/camera_sensors"
        self.param = "%s/%s" % (base, self.key)
        self.info_topic = self.param + "/camera_info"
        self._info_pub = rospy.Publisher(self.info_topic, CameraInfo, queue_size=1, latch=True)
        self._publish_intrinsics()
        rospy.set_param(self.param, {
            "name": sensor_config.topic(cfg, "").strip("/") or self.key,
            "camera_info": self.info_topic, "frame": self.frame, "header_frame": cfg.frame_name,
            "image": sensor_config.topic(cfg, cfg.image_topic),
            "camera_info_out": sensor_config.topic(cfg, cfg.info_topic),
            "rate": cfg.update_rate, "format": cfg.format, "noise_mean": cfg.noise_mean,
            "noise_stddev": cfg.noise_stddev, "hack_baseline": cfg.hack_baseline,
            "clip_near": cfg.near, "clip_far": cfg.far})
        self._zoom_sub = rospy.Subscriber(sensor_config.topic(cfg, "set_hfov"), Float64, self._on_hfov,
                                          queue_size=1)
        self._zoom_srv = rospy.Service(sensor_config.topic(cfg, "set_camera_info"), SetCameraInfo,
                                       self._srv_set_info)
        rospy.loginfo("model '%s': camera '%s' on link '%s' -> %s (%dx%d, hfov %.3f rad, %.1f Hz; "
                      "images from the camera_renderer node)", model.name, cfg.sensor_name, cfg.link,
                      sensor_config.topic(cfg, cfg.image_topic), cfg.width, cfg.height, cfg.hfov,
                      cfg.update_rate)

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
        self._zoom_sub.unregister()
        self._zoom_srv.shutdown()
        self._info_pub.unregister()
        self.scene.remove_frame(self.frame)
        try:
            rospy.delete_param(self.param)
        except KeyError:
            pass


register_plugin(FILENAME, GazeboRosCameraPlugin)
