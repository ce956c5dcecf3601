"""<transmission> and <plugin> parsing; SimpleTransmission round trips."""
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.ros_control.plugin_config import PluginConfig
from modrob_sim.ros_control.transmissions import (SimpleTransmission, canonical_interface,
                                                  parse_transmissions)
import xml.etree.ElementTree as ET

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")


def _read(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


def test_parse_ptrz_transmissions_with_and_without_prefix():
    trs = parse_transmissions(_read("ptrz_camera.urdf"))
    assert [t.joints[0].name for t in trs] == ["pan", "tilt", "roll"]
    assert [canonical_interface(t.joints[0].interfaces[0]) for t in trs] == ["EffortJointInterface"] * 3
    assert trs[1].joints[0].interfaces == ["EffortJointInterface"]          # prefix-less form kept
    assert trs[0].type == "transmission_interface/SimpleTransmission"
    assert trs[0].actuators[0].reduction == 1.0


@pytest.mark.parametrize("text,expected", [
    ("hardware_interface/PositionJointInterface", "PositionJointInterface"),
    ("VelocityJointInterface", "VelocityJointInterface"),
    ("hardware_interface::EffortJointInterface", "EffortJointInterface"),
    ("hardware_interface/JointStateInterface", None),
])
def test_canonical_interface(text, expected):
    assert canonical_interface(text) == expected


def test_bad_reduction_and_bad_xml_are_refused():
    with pytest.raises(ModelError, match="mechanicalReduction 'x'"):
        parse_transmissions('<robot name="r"><transmission name="t"><actuator name="a">'
                            '<mechanicalReduction>x</mechanicalReduction></actuator></transmission></robot>')
    with pytest.raises(ModelError, match="not valid XML"):
        parse_transmissions("<robot")


@pytest.mark.parametrize("reduction,offset", [(1.0, 0.0), (160.0, 0.0), (-50.0, 0.3), (0.25, -1.0)])
def test_simple_transmission_actuator_joint_actuator_is_identity(reduction, offset):
    tr = SimpleTransmission(reduction, offset)
    for value in (-3.0, 0.0, 0.7, 12.5):
        assert tr.joint_to_actuator_effort(tr.actuator_to_joint_effort(value)) == pytest.approx(value)
        assert tr.joint_to_actuator_velocity(tr.actuator_to_joint_velocity(value)) == pytest.approx(value)
        assert tr.joint_to_actuator_position(tr.actuator_to_joint_position(value)) == pytest.approx(value)
    assert tr.actuator_to_joint_effort(1.0) == pytest.approx(reduction)


def test_plugin_config_namespaces_and_legacy_mode():
    el = ET.fromstring(_read("ptrz_camera.urdf")).find("gazebo/plugin")
    cfg = PluginConfig.from_element(el, "pan")
    assert cfg.robot_namespace == "/ptrz" and cfg.legacy_mode_ns and not cfg.legacy_mode_given
    assert cfg.pid_gains_namespaces() == ["/gazebo_ros_control/pid_gains",
                                          "/ptrz/gazebo_ros_control/pid_gains"]
    el = ET.fromstring('<plugin filename="libgazebo_ros_control.so"><robotNamespace>modrob0</robotNamespace>'
                       '<legacyModeNS>false</legacyModeNS><controlPeriod>0.002</controlPeriod></plugin>')
    cfg = PluginConfig.from_element(el, "m")
    assert cfg.robot_namespace == "/modrob0" and not cfg.legacy_mode_ns and cfg.control_period == 0.002
    assert cfg.pid_gains_namespaces()[0] == "/modrob0/gazebo_ros_control/pid_gains"
    assert PluginConfig.from_element(None, "car", default_namespace="").robot_namespace == "/car"
    with pytest.raises(ModelError, match="legacyModeNS"):
        PluginConfig.from_element(ET.fromstring("<plugin><legacyModeNS>maybe</legacyModeNS></plugin>"), "m")
