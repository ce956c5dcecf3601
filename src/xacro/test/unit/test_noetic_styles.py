"""Files written the way ur_description and franka_description (ROS Noetic) write their robots
expand to the URDF that Noetic's xacro 1.14 makes of them (the *.expected.urdf beside each)."""
import os

import pytest
import xacro

from xacro_xml_compare import canonical

FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures")


@pytest.fixture(autouse=True)
def on_package_path(monkeypatch):
    """$(find xacro) must name this source tree (the fixtures use it as ur_description does)."""
    src = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    monkeypatch.setenv("ROS_PACKAGE_PATH", src + os.pathsep + os.environ.get("ROS_PACKAGE_PATH", ""))


def expected(style, name):
    with open(os.path.join(FIXTURES, style, name)) as f:
        return canonical(f.read())


def test_ur_style_arm():
    doc = xacro.process_file(os.path.join(FIXTURES, "ur_style", "arm.urdf.xacro"))
    assert canonical(doc) == expected("ur_style", "arm.expected.urdf")


def test_ur_style_yaml_units_and_parent_scope():
    """!degrees / !radians / !millimeters converted, values set into the caller with scope="parent"."""
    doc = xacro.process_file(os.path.join(FIXTURES, "ur_style", "arm.urdf.xacro"),
                             mappings={"safety_limits": "true"})
    joints = {j.getAttribute("name"): j for j in doc.documentElement.childNodes
              if getattr(j, "tagName", None) == "joint"}
    limit = joints["base_joint"].getElementsByTagName("limit")[0]
    assert float(limit.getAttribute("upper")) == pytest.approx(4.71238898038469)     # !degrees 270
    assert float(limit.getAttribute("velocity")) == pytest.approx(1.5707963267948966)
    elbow = joints["elbow_joint"].getElementsByTagName("limit")[0]
    assert float(elbow.getAttribute("lower")) == pytest.approx(-1.5707963267948966)  # !radians -pi/2
    assert joints["base_joint"].getElementsByTagName("origin")[0].getAttribute("xyz") == "0 0 0.0892"
    soft = joints["base_joint"].getElementsByTagName("safety_controller")[0]
    assert float(soft.getAttribute("soft_upper_limit")) == pytest.approx(4.71238898038469 - 0.15)
    assert joints["world_joint"].getElementsByTagName("origin")[0].getAttribute("xyz") == "0 0 0.1"


def test_panda_style_arm_defaults(capsys):
    doc = xacro.process_file(os.path.join(FIXTURES, "panda_style", "arm.urdf.xacro"))
    assert canonical(doc) == expected("panda_style", "arm.expected.urdf")
    assert "warning" not in capsys.readouterr().err


def test_panda_style_arm_with_hand_in_gazebo(capsys):
    doc = xacro.process_file(os.path.join(FIXTURES, "panda_style", "arm.urdf.xacro"),
                             mappings={"hand": "true", "gazebo": "true", "arm_id": "panda"})
    assert canonical(doc) == expected("panda_style", "arm_hand_gazebo.expected.urdf")
    err = capsys.readouterr().err
    # xacro.warning() prints with the macro and file stack, and leaves no text in the document
    assert "No inertia properties defined for: link2" in err
    assert "when instantiating macro: inertial_props" in err
    assert "instantiated from: link" in err
