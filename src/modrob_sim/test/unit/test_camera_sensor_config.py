"""libgazebo_ros_camera.so: the <sensor>/<plugin> parameters and Gazebo's intrinsics."""
import math
import xml.etree.ElementTree as ET

import pytest

from modrob_sim.camera import plugin, sensor_config
from modrob_sim.errors import ModelError

SENSOR = """<sensor type="camera" name="camera1"><update_rate>30.0</update_rate>
  <camera name="head"><horizontal_fov>1.3962634</horizontal_fov>
    <image><width>800</width><height>600</height><format>R8G8B8</format></image>
    <clip><near>0.02</near><far>300</far></clip>
    <noise><type>gaussian</type><mean>0.0</mean><stddev>0.007</stddev></noise></camera>
  <plugin name="camera_controller" filename="libgazebo_ros_camera.so">
    <alwaysOn>true</alwaysOn><updateRate>0.0</updateRate><cameraName>ptrz/camera1</cameraName>
    <imageTopicName>image_raw</imageTopicName><cameraInfoTopicName>camera_info</cameraInfoTopicName>
    <frameName>camera_link</frameName><hackBaseline>0.07</hackBaseline><distortionK1>0.1</distortionK1>
  </plugin></sensor>"""


def _parse(text=SENSOR, ns=""):
    s = ET.fromstring(text)
    return sensor_config.parse(s, s.find("plugin"), "camera_link", "ptrz", ns)


def test_parameters():
    c = _parse()
    assert (c.width, c.height, c.format, c.update_rate) == (800, 600, "R8G8B8", 30.0)
    assert c.hfov == pytest.approx(1.3962634)
    assert (c.near, c.far, c.noise_stddev, c.hack_baseline) == (0.02, 300.0, 0.007, 0.07)
    assert c.distortion[0] == 0.1
    assert sensor_config.topic(c, c.image_topic) == "/ptrz/camera1/image_raw"
    assert sensor_config.topic(_parse(ns="/robot"), "set_hfov") == "/robot/ptrz/camera1/set_hfov"


def test_camera_info_follows_gazebo_formula():
    c = _parse()
    info = plugin.camera_info(c, c.hfov, "camera_link")
    f = 800 / (2 * math.tan(1.3962634 / 2))
    assert info.K[0] == pytest.approx(f) and info.K[4] == pytest.approx(f)
    assert (info.K[2], info.K[5]) == (400.5, 300.5)
    assert info.P[3] == pytest.approx(-f * 0.07)
    zoomed = plugin.camera_info(c, c.hfov / 2, "camera_link")
    assert zoomed.K[0] > 2 * info.K[0]          # tan is convex: half the angle, more than twice f


@pytest.mark.parametrize("bad,match", [
    (SENSOR.replace("1.3962634", "3.5"), "horizontal_fov"),
    (SENSOR.replace("<width>800", "<width>0"), "width/height"),
    (SENSOR.replace("R8G8B8", "BAYER_RGGB8"), "format"),
    (SENSOR.replace("<near>0.02", "<near>400"), "clip"),
    (SENSOR.replace('type="camera"', 'type="ray"'), "type"),
])
def test_bad_sensors_name_the_problem(bad, match):
    with pytest.raises(ModelError, match=match):
        _parse(bad)


# ---- depth cameras (TurtleBot3 waffle's realsense_R200 block, in our own words) -------------------
DEPTH = """<sensor type="depth" name="depth_cam"><update_rate>20</update_rate>
  <camera><horizontal_fov>1.2</horizontal_fov>
    <image><width>320</width><height>240</height><format>R8G8B8</format></image>
    <depth_camera/><clip><near>0.05</near><far>50</far></clip></camera>
  <plugin name="camera_controller" filename="libgazebo_ros_openni_kinect.so">
    <cameraName>cam</cameraName><frameName>cam_optical</frameName>
    %s
  </plugin></sensor>"""


def _parse_depth(extra="<baseline>0.1</baseline>", filename="libgazebo_ros_openni_kinect.so"):
    s = ET.fromstring(DEPTH % extra)
    return sensor_config.parse_depth(s, s.find("plugin"), "cam_link", "bot", "", filename)


def test_depth_camera_defaults_as_gazebo_plugins():
    c = _parse_depth()
    assert (c.image_topic, c.info_topic) == ("ir/image_raw", "ir/camera_info")
    d = c.depth
    topics = (d.depth_image_topic, d.depth_info_topic, d.points_topic)
    assert topics == ("depth/image_raw", "depth/camera_info", "points")
    assert (d.cutoff, d.cutoff_max, d.depth16) == (0.4, 5.0, False)
    assert (c.width, c.height, c.near, c.far, c.update_rate) == (320, 240, 0.05, 50.0, 20.0)
    plain = _parse_depth(filename="libgazebo_ros_depth_camera.so")
    assert plain.depth.cutoff_max == math.inf       # the depth_camera plugin has no upper cutoff


def test_depth_camera_parameters():
    c = _parse_depth("<imageTopicName>rgb/image_raw</imageTopicName><pointCloudTopicName>depth/points"
                     "</pointCloudTopicName><pointCloudCutoff>0.2</pointCloudCutoff><pointCloudCutoffMax>8"
                     "</pointCloudCutoffMax><useDepth16UC1Format>true</useDepth16UC1Format>")
    assert c.image_topic == "rgb/image_raw" and c.depth.points_topic == "depth/points"
    assert (c.depth.cutoff, c.depth.cutoff_max, c.depth.depth16) == (0.2, 8.0, True)
    assert sensor_config.topic(c, c.depth.points_topic) == "/cam/depth/points"


@pytest.mark.parametrize("extra,match", [
    ("<pointCloudCutoff>6</pointCloudCutoff>", "pointCloudCutoff"),
    ("<useDepth16UC1Format>maybe</useDepth16UC1Format>", "useDepth16UC1Format"),
    ("<baseline>x</baseline>", "baseline"),
])
def test_bad_depth_parameters_named(extra, match):
    with pytest.raises(ModelError, match=match):
        _parse_depth(extra)


def test_depth_plugin_needs_a_depth_sensor():
    s = ET.fromstring(SENSOR)
    with pytest.raises(ModelError, match=r'libgazebo_ros_openni_kinect.so needs <sensor type="depth">'):
        sensor_config.parse_depth(s, s.find("plugin"), "l", "m")
