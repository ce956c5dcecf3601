"""Configuration files: the seed's YAML unchanged, the network's controllers equal to it, the
camera poses, and the xacro model equal to the seed's."""
import os
import xml.etree.ElementTree as ET

import pytest
import yaml

from ptrz_camera import description
from ptrz_camera.errors import ConfigError

PKG = description.PACKAGE_DIR


def load(*path):
    with open(os.path.join(PKG, *path)) as f:
        return yaml.safe_load(f)


def test_seed_yaml_is_unchanged_and_network_controllers_equal_it():
    seed = load("test", "fixtures", "seed_ptrz.yaml")
    assert load("config", "ptrz.yaml") == seed
    assert load("config", "camera_controllers.yaml") == seed["ptrz"]
    assert seed["ptrz"]["pan_position_controller"]["pid"] == {"p": 100.0, "i": 0.01, "d": 30}
    assert seed["ptrz"]["roll_position_controller"]["pid"] == {"p": 100, "i": 0.01, "d": 10}


def test_camera_poses_file_lists_four_cameras():
    poses = description.load_camera_poses()
    assert list(poses) == ["ptrz1", "ptrz2", "ptrz3", "ptrz4"]
    assert description.network_names(3) == ["ptrz1", "ptrz2", "ptrz3"]
    with pytest.raises(ConfigError, match="poses for 4 camera"):
        description.network_names(5)


@pytest.mark.parametrize("text, match", [
    ("[1, 2]", "must map namespaces"),
    ("ptrz1: {x: a}", "ptrz1.x = 'a' is not a number"),
    ("ptrz1: {x: .nan}", "not finite"),
    ("ptrz1: {x: 1, z: 2}", "unknown keys"),
    ("ptrz1: [1, 2]", "must be {x"),
    ("ptrz1: {x: 1", "not valid YAML"),
])
def test_bad_poses_files_are_named(tmp_path, text, match):
    f = tmp_path / "poses.yaml"
    f.write_text(text)
    with pytest.raises(ConfigError, match=match):
        description.load_camera_poses(str(f))


def test_missing_poses_file_is_named(tmp_path):
    with pytest.raises(ConfigError, match="cannot be read"):
        description.load_camera_poses(str(tmp_path / "none.yaml"))


def xyz(text):
    return tuple(round(float(v), 9) for v in text.split())


def joints_of(urdf, strip=""):
    root = ET.fromstring(urdf)
    out = {}
    for j in root.findall("joint"):
        axis = j.find("axis")
        out[j.get("name")] = (j.get("type"), j.find("parent").get("link").replace(strip, ""),
                              j.find("child").get("link").replace(strip, ""),
                              xyz(j.find("origin").get("xyz")), axis.get("xyz") if axis is not None else None)
    links = {}
    for ln in root.findall("link"):
        mass = ln.find("inertial/mass")
        links[ln.get("name").replace(strip, "")] = mass.get("value") if mass is not None else None
    return out, links


def test_product_xacro_is_the_seed_model():
    seed = description.robot_description(xacro_file=os.path.join(PKG, "test", "fixtures", "seed_ptrz.xacro"))
    ours = description.robot_description()
    assert joints_of(ours) == joints_of(seed)
    _, links = joints_of(ours)
    assert float(links["camera"]) == 1e-5 and float(links["pole"]) == 1.0
    root = ET.fromstring(ours)
    assert root.find(".//sensor/camera/horizontal_fov").text == "1.3962634"
    assert root.find(".//plugin[@filename='libgazebo_ros_camera.so']/cameraName").text == "ptrz/camera1"
    assert root.find(".//plugin[@filename='libgazebo_ros_control.so']/robotNamespace").text == "/ptrz"
    assert [t.get("name") for t in root.findall("transmission")] == ["pan_trans", "tilt_trans", "roll_trans"]


def test_network_camera_has_its_namespace_prefix_and_pole():
    urdf = description.robot_description("ptrz2", "ptrz2_", (3.5, -3.5, 1.5708), width=64, height=32)
    root = ET.fromstring(urdf)
    joints, _ = joints_of(urdf, strip="ptrz2_")
    assert joints == joints_of(description.robot_description())[0] | {
        "base_joint": ("fixed", "world", "pole", (3.5, -3.5, 2.0), None)}
    assert root.find(".//cameraName").text == "ptrz2/camera1"
    assert root.find(".//frameName").text == "ptrz2_camera"
    assert root.find(".//image/width").text == "64"
    assert root.find(".//robotNamespace").text == "/ptrz2"


def test_description_cli_errors(capsys):
    from ptrz_camera.description_cli import main
    assert main(["--ns", "ptrz9", "--poses", description.CAMERAS_FILE]) == 1
    assert "no pose for camera 'ptrz9'" in capsys.readouterr().err
    assert main(["--list", "2", "--poses", description.CAMERAS_FILE]) == 0
    assert capsys.readouterr().out == "ptrz1 ptrz2"
    assert main(["width=3"]) == 2


def test_network_rviz_configs_are_current_and_show_each_camera_once():
    from ptrz_camera import rviz_config
    for n in range(2, rviz_config.MAX_CAMERAS + 1):
        path = rviz_config.config_path(os.path.join(PKG, "config"), n)
        with open(path) as f:
            text = f.read()
        assert text == rviz_config.network_config(n), "%s is stale: python3 -m ptrz_camera.rviz_config" % path
        displays = yaml.safe_load(text)["Visualization Manager"]["Displays"]
        images = [d["Image Topic"] for d in displays if d["Class"] == "rviz/Image"]
        models = [d["Robot Description"] for d in displays if d["Class"] == "rviz/RobotModel"]
        assert images == ["/ptrz%d/camera1/image_raw" % i for i in range(1, n + 1)]
        assert models == ["ptrz%d/robot_description" % i for i in range(1, n + 1)]
    with pytest.raises(ValueError, match="2 to 4 cameras"):
        rviz_config.network_config(5)
