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
    (SENSOR.replace("R8G8B8", "R32G32B32F"), "format"),
    (SENSOR.replace("</noise>", "</noise><distortion><center>0.5</center></distortion>"), "center"),
    (SENSOR.replace("<hackBaseline>", "<Cx>-3</Cx><hackBaseline>"), "Cx"),
    (SENSOR.replace("<near>0.02", "<near>400"), "clip"),
    (SENSOR.replace('type="camera"', 'type="ray"'), "type"),
])
def test_bad_sensors_name_the_problem(bad, match):
    with pytest.raises(ModelError, match=match):
        _parse(bad)


@pytest.mark.parametrize("fmt,encoding", [
    ("R8G8B8", "rgb8"), ("RGB_INT8", "rgb8"), ("B8G8R8", "bgr8"), ("L8", "mono8"), ("L_INT8", "mono8"),
    ("L16", "mono16"), ("L_INT16", "mono16"), ("R16G16B16", "rgb16"), ("RGB_INT16", "rgb16"),
    ("BAYER_RGGB8", "bayer_rggb8"), ("BAYER_BGGR8", "bayer_bggr8"), ("BAYER_GBRG8", "bayer_gbrg8"),
    ("BAYER_GRBG8", "bayer_grbg8")])
def test_formats_to_the_encodings_gazebo_plugins_publishes(fmt, encoding):
    assert _parse(SENSOR.replace("R8G8B8", fmt)).encoding == encoding


def test_cx_cy_focal_length_as_gazebo_plugins():
    c = _parse(SENSOR.replace("<hackBaseline>", "<Cx>390</Cx><Cy>0</Cy><focalLength>500</focalLength>"
                                                "<hackBaseline>"))
    info = plugin.camera_info(c, c.hfov, "camera_link")
    assert (info.K[0], info.K[4], info.K[2], info.K[5]) == (500.0, 500.0, 390.0, 300.5)   # Cy 0: Gazebo's
    assert info.P[0] == 500.0 and info.P[2] == 390.0
    zoomed = plugin.camera_info(c, 0.5, "camera_link")           # zoomed: the field of view's focal length
    assert zoomed.K[0] == pytest.approx(800 / (2 * math.tan(0.25)))


LENS = "<distortion><k1>-0.25</k1><k2>0.05</k2><k3>0.01</k3><p1>0.001</p1><p2>-0.002</p2>" \
       "<center>0.5 0.5</center></distortion>"


def test_lens_drawn_and_d_from_the_plugin_or_the_lens():
    c = _parse(SENSOR.replace("</noise>", "</noise>" + LENS))
    assert c.lens == (-0.25, 0.05, 0.01, 0.001, -0.002, 0.5, 0.5)
    assert c.distortion == [0.1, 0.0, 0.0, 0.0, 0.0]             # D: the plugin's distortionK1.. keys
    auto = _parse(SENSOR.replace("</noise>", "</noise>" + LENS).replace(
        "<alwaysOn>", "<autoDistortion>true</autoDistortion><alwaysOn>"))
    assert auto.distortion == [-0.25, 0.05, 0.001, -0.002, 0.01]  # ROS's order k1 k2 p1 p2 k3
    assert _parse().lens is None


STEREO = """<sensor type="multicamera" name="stereo"><update_rate>10</update_rate>
  <camera name="left_cam"><horizontal_fov>1.0</horizontal_fov>
    <image><width>160</width><height>120</height><format>L8</format></image></camera>
  <camera name="right_cam"><pose>0 -0.07 0 0 0 0</pose><horizontal_fov>1.0</horizontal_fov>
    <image><width>160</width><height>120</height><format>L8</format></image></camera>
  <plugin name="stereo_controller" filename="libgazebo_ros_multicamera.so">
    <cameraName>stereo</cameraName><frameName>stereo_optical</frameName><hackBaseline>0.07</hackBaseline>
  </plugin></sensor>"""


def test_multicamera_cameras_as_gazebo_plugins():
    s = ET.fromstring(STEREO)
    cams = s.findall("camera")
    left = sensor_config.parse(s, s.find("plugin"), "head", "bot", "", "libgazebo_ros_multicamera.so",
                               types=("multicamera",), camera=cams[0], name_suffix="/left", hack_baseline=0.0)
    right = sensor_config.parse(s, s.find("plugin"), "head", "bot", "", "libgazebo_ros_multicamera.so",
                                types=("multicamera",), camera=cams[1], name_suffix="/right")
    assert sensor_config.topic(left, left.image_topic) == "/stereo/left/image_raw"
    assert sensor_config.topic(right, right.info_topic) == "/stereo/right/camera_info"
    assert (left.hack_baseline, right.hack_baseline) == (0.0, 0.07)
    assert right.camera_pose == (0.0, -0.07, 0.0, 0.0, 0.0, 0.0) and left.camera_pose == (0.0,) * 6
    assert left.frame_name == right.frame_name == "stereo_optical"
    assert plugin.camera_info(right, right.hfov, "f").P[3] == pytest.approx(-right.hack_baseline * 160 / (
        2 * math.tan(0.5)))


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


def _multi_configs(text):
    import types
    s = ET.fromstring(text)
    spec = types.SimpleNamespace(sensor=s, element=s.find("plugin"), link="head")
    multi = object.__new__(plugin.GazeboRosMultiCameraPlugin)     # only its sensor reading
    return multi._configs(spec, "bot", "")


def test_multicamera_plugin_publishes_left_and_right_only():
    names = [name for name, _cfg in _multi_configs(STEREO)]
    assert names == ["stereo/left_cam", "stereo/right_cam"]
    third = STEREO.replace("<plugin ", '<camera name="middle"><horizontal_fov>1</horizontal_fov>'
                                       '</camera><plugin ')
    assert [n for n, _c in _multi_configs(third)] == names          # 'middle' not published (warned)
    with pytest.raises(ModelError, match="left"):
        _multi_configs(STEREO.replace("left_cam", "a").replace("right_cam", "b"))
    with pytest.raises(ModelError, match="multicamera"):
        _multi_configs(STEREO.replace('type="multicamera"', 'type="camera"'))
