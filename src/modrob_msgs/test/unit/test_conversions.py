import pytest
from sensor_msgs.msg import JointState

from modrob_msgs.conversions import config_to_joint_state, joint_state_to_config
from modrob_msgs.msg import RobotConfigMeasured


def test_round_trip_keeps_header_names_and_positions():
    js = JointState()
    js.header.frame_id = "base"
    js.header.stamp.secs = 7
    js.name = ["joint1", "joint2", "joint3"]
    js.position = [0.1, -0.2, 1.5]
    cfg = joint_state_to_config(js, RobotConfigMeasured)
    assert cfg.joint_names == js.name and cfg.joint_angles == js.position
    back = config_to_joint_state(cfg, JointState)
    assert back.header.stamp.secs == 7 and back.header.frame_id == "base"
    assert back.name == js.name and back.position == js.position


def test_mismatched_lengths_are_refused_with_counts():
    js = JointState(name=["a", "b"], position=[0.0])
    with pytest.raises(ValueError, match="2 names but 1 positions"):
        joint_state_to_config(js, RobotConfigMeasured)
