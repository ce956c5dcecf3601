"""franka_msgs and franka_gripper must be field-identical to franka_ros' (0.10): these MD5 sums were
computed with genmsg from franka_ros' own definitions. A differing sum means franka_ros clients
(MoveIt's franka configs, franka_example_controllers' scripts) cannot talk to the simulation."""
import pytest

franka_msgs = pytest.importorskip("franka_msgs.msg")
franka_srv = pytest.importorskip("franka_msgs.srv")
franka_gripper = pytest.importorskip("franka_gripper.msg")

FRANKA_ROS_MD5 = {
    ("franka_msgs", "FrankaState"): "431567d5df6caf4e4dd7385f25cb71ee",
    ("franka_msgs", "Errors"): "082e9a670c96d8bc64b53e32777458e7",
    ("franka_msgs", "ErrorRecoveryAction"): "d5a016b49f278075666fbc901debbd08",
    ("franka_gripper", "GraspEpsilon"): "95b2c5464a6f679bd1dacaf86414f095",
    ("franka_gripper", "GraspGoal"): "627a0f0b10ad0c919fbd62b0b3427e63",
    ("franka_gripper", "GraspResult"): "45872d25d65c97743cc71afc6d4e884d",
    ("franka_gripper", "GraspAction"): "6f89449359949eaf1f0fef57b7e0db2a",
    ("franka_gripper", "MoveGoal"): "d16050a0fe85f1c2cb8347c99678362e",
    ("franka_gripper", "HomingResult"): "45872d25d65c97743cc71afc6d4e884d",
    ("franka_gripper", "StopResult"): "45872d25d65c97743cc71afc6d4e884d",
    ("franka_srv", "SetLoad"): "c9a8ec436164dd9cbc1e5e137d358e0b",
    ("franka_srv", "SetEEFrame"): "459aea8fa6dbdd34ba4bc52d3eddbacf",
    ("franka_srv", "SetKFrame"): "11b22d30e6a11a7b51828be575a77359",
    ("franka_srv", "SetForceTorqueCollisionBehavior"): "b1e592d1b6960bc05e6e3cba1eb02349",
    ("franka_srv", "SetFullCollisionBehavior"): "c6fef9a8ad446db9a39cca3b7bc200d8",
    ("franka_srv", "SetJointImpedance"): "f11c4defa2a13040512214f9d77dc982",
    ("franka_srv", "SetCartesianImpedance"): "c648a0b1340a53eac0c535568e9b5c60",
    ("franka_srv", "SetJointConfiguration"): "772aebee560c498b58210c453ba3c24c",
}
MODULES = {"franka_msgs": franka_msgs, "franka_srv": franka_srv, "franka_gripper": franka_gripper}


@pytest.mark.parametrize("module,name", sorted(FRANKA_ROS_MD5))
def test_md5_matches_franka_ros(module, name):
    assert getattr(MODULES[module], name)._md5sum == FRANKA_ROS_MD5[(module, name)]
