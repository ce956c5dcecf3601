"""Tier 1: the motion interface's pure parts (joint matching, controller map, URDF info)."""
import math
import os

import pytest

from modrob_motion.errors import MotionError, UnknownJointError
from modrob_motion.joint_matching import JointCommandMatcher, JointLimits
from modrob_motion.controller_map import position_controllers, command_topic
from modrob_motion.robot_info import parse_urdf_joints, robot_info_from_urdf

ARM_URDF_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "test_motion_arm_gripper.urdf")
with open(ARM_URDF_PATH) as _f:
    ARM_URDF = _f.read()


def test_match_by_name_in_robot_order():
    m = JointCommandMatcher(["a", "b", "c"])
    out = m.match(["c", "a"], [0.3, 0.1])
    assert list(out.items()) == [("a", 0.1), ("c", 0.3)]


def test_positional_needs_every_joint():
    m = JointCommandMatcher(["a", "b"], robot="modrob3")
    assert list(m.match([], [1, 2]).values()) == [1.0, 2.0]
    with pytest.raises(MotionError, match="modrob3.*needs 2 positions.*got 3"):
        m.match([], [1, 2, 3])


def test_unknown_name_refused_with_the_known_ones():
    m = JointCommandMatcher(["joint1", "joint2"], robot="modrob0")
    with pytest.raises(UnknownJointError) as err:
        m.match(["joint1", "joint9"], [0, 0])
    assert "joint9" in str(err.value) and "joint1, joint2" in str(err.value)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), "x"])
def test_non_finite_refused(bad):
    m = JointCommandMatcher(["a"])
    with pytest.raises(MotionError, match="'a'"):
        m.match(["a"], [bad])


def test_limits_refuse_and_tolerate_round_off():
    m = JointCommandMatcher(["a"], {"a": JointLimits(-1.0, 1.0)})
    assert m.match(["a"], [1.0 + 1e-9])["a"] == 1.0
    with pytest.raises(MotionError, match="above its upper limit"):
        m.match(["a"], [1.2])
    with pytest.raises(MotionError, match="below its lower limit"):
        m.match(["a"], [-1.2])


def test_length_mismatch_and_duplicates():
    m = JointCommandMatcher(["a", "b"])
    with pytest.raises(MotionError, match="2 joint names but 1 positions"):
        m.match(["a", "b"], [0])
    with pytest.raises(MotionError, match="named twice"):
        m.match(["a", "a"], [0, 1])


def test_controller_map_from_params():
    params = {
        "joint_state_controller": {"type": "joint_state_controller/JointStateController", "publish_rate": 50},
        "joint10_position_controller": {"type": "effort_controllers/JointPositionController",
                                        "joint": "joint10", "pid": {"p": 100}},
        "joint2_position_controller": {"type": "effort_controllers/JointPositionController",
                                       "joint": "joint2"},
        "robot_description": "<robot/>",
    }
    found = position_controllers(params, "/modrob0")
    assert found == {"joint10": "joint10_position_controller", "joint2": "joint2_position_controller"}
    topic = command_topic("/modrob0", "joint2_position_controller")
    assert topic == "/modrob0/joint2_position_controller/command"
    assert command_topic("modrob0/", "c") == "/modrob0/c/command"


def test_controller_map_empty_says_what_to_do():
    with pytest.raises(MotionError, match="load the robot's controller YAML"):
        position_controllers({"joint_state_controller": {"type": "x"}}, "/modrob7")


def test_robot_info_chain_order_and_gripper():
    info = robot_info_from_urdf(0, ARM_URDF)
    assert info.arm_joints == ["joint1", "joint2"]
    assert info.gripper.joints == ["finger_left_joint", "finger_right_joint"]
    # Both fingers move outward with positive q (the right one is rotated by pi): 0 is closed.
    assert info.gripper.closed_positions == {"finger_left_joint": 0.0, "finger_right_joint": 0.0}
    assert info.gripper.open_positions == {"finger_left_joint": 0.03, "finger_right_joint": 0.03}
    assert info.home == [0.0, 0.0]
    assert info.limits["joint1"].lower is None


def test_urdf_joints_carry_their_effort_limit():
    effort = {j.name: j.effort for j in parse_urdf_joints(ARM_URDF)}
    assert effort["finger_left_joint"] == 3.0 and effort["joint2"] == 10.0
    assert effort["joint1"] is None         # no <limit>: none given


def test_robot_info_home_respects_limits():
    urdf = ARM_URDF.replace('lower="-2" upper="2"', 'lower="0.5" upper="2"')
    info = robot_info_from_urdf(0, urdf)
    assert info.home == [0.0, 0.5]


def test_robot_info_bad_xml():
    with pytest.raises(MotionError, match="not valid XML"):
        robot_info_from_urdf(0, "<robot")
    with pytest.raises(MotionError, match="no movable arm joint"):
        robot_info_from_urdf(0, "<robot name='x'><link name='a'/></robot>")


def test_inward_finger_axes():
    # Fingers whose closed end is the upper limit (axes pointing at each other).
    urdf = ARM_URDF.replace('<origin xyz="0 0.01 0.05"/><axis xyz="0 1 0"/>',
                            '<origin xyz="0 0.04 0.05"/><axis xyz="0 -1 0"/>')
    info = robot_info_from_urdf(0, urdf)
    assert info.gripper.closed_positions["finger_left_joint"] == pytest.approx(0.03)
    assert math.isclose(info.gripper.open_positions["finger_left_joint"], 0.0)
