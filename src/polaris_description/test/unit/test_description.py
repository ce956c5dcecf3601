"""The Polaris description as polaris.launch expands it (the workspace's xacro, Noetic's 1.14
semantics) carries the HDL-32E the lap's obstacle stop reads: expanded from velodyne_description's
macro, not left as an unknown <HDL-32E> element (Noetic's xacro expands only xacro:-prefixed calls;
left unexpanded, the lap drove into the cone with no point cloud)."""
import os
import subprocess
import xml.etree.ElementTree as ET

XACRO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "urdf", "polaris.urdf.xacro")


def expand(*args):
    return ET.fromstring(subprocess.check_output(["xacro", XACRO] + list(args), text=True))


def test_the_lidar_is_in_the_description_with_velodyne_on():
    robot = expand("velodyne:=true")
    assert robot.find("HDL-32E") is None
    plugins = [p for p in robot.iter("plugin") if p.get("filename") == "libgazebo_ros_velodyne_laser.so"]
    assert len(plugins) == 1 and plugins[0].findtext("topicName") == "/velodyne_points2"
    assert expand("velodyne:=false").find(".//sensor[@type='ray']") is None
