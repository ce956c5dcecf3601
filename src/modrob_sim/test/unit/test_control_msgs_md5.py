"""control_msgs and controller_manager_msgs must be field-identical to ROS Noetic's: the MD5 sums
below were taken from code generated from Noetic's definitions (rosserial, gennodejs, roslisp
outputs in public repositories). A differing sum means a Noetic client cannot talk to us."""
import pytest

control_msgs_msg = pytest.importorskip("control_msgs.msg")
cm_srv = pytest.importorskip("controller_manager_msgs.srv")
cm_msg = pytest.importorskip("controller_manager_msgs.msg")

NOETIC_MD5 = {
    ("control_msgs", "FollowJointTrajectoryGoal"): "69636787b6ecbde4d61d711979bc7ecb",
    ("control_msgs", "FollowJointTrajectoryResult"): "493383b18409bfb604b4e26c676401d2",
    ("control_msgs", "FollowJointTrajectoryFeedback"): "10817c60c2486ef6b33e97dcd87f4474",
    ("control_msgs", "JointTolerance"): "f544fe9c16cf04547e135dd6063ff5be",
    ("control_msgs", "JointTrajectoryControllerState"): "10817c60c2486ef6b33e97dcd87f4474",
    ("control_msgs", "PidState"): "b138ec00e886c10e73f27e8712252ea6",
    ("control_msgs", "JointControllerState"): "987ad85e4756f3aef7f1e5e7fe0595d1",
    ("control_msgs", "GripperCommand"): "680acaff79486f017132a7f198d40f08",
    ("control_msgs", "GripperCommandGoal"): "86fd82f4ddc48a4cb6856cfa69217e43",
    ("control_msgs", "GripperCommandResult"): "e4cbff56d3562bcf113da5a5adeef91f",
    ("control_msgs", "JointJog"): "1685da700c8c2e1254afc92a5fb89c96",
    ("control_msgs", "PointHeadGoal"): "8b92b1cd5e06c8a94c917dc3209a4c1d",
    ("control_msgs", "SingleJointPositionGoal"): "fbaaa562a23a013fd5053e5f72cbb35c",
    ("control_msgs", "SingleJointPositionFeedback"): "8cee65610a3d08e0a1bded82f146f1fd",
    ("control_msgs", "JointTrajectoryGoal"): "2a0eff76c870e8595636c2a562ca298e",
    ("controller_manager_msgs", "ControllerState"): "aeb6b261d97793ab74099a3740245272",
    ("controller_manager_msgs", "ListControllersResponse"): "1341feb2e63fa791f855565d0da950d8",
    ("controller_manager_msgs", "ListControllerTypesResponse"): "c1d4cd11aefa9f97ba4aeb5b33987f4e",
    ("controller_manager_msgs", "SwitchController"): "b29a7abc673b2c54c14b54e50f8d06a5",
}


def _lookup(pkg, name):
    if pkg == "control_msgs":
        return getattr(control_msgs_msg, name)
    return getattr(cm_msg, name, None) or getattr(cm_srv, name)


@pytest.mark.parametrize("pkg,name", sorted(NOETIC_MD5))
def test_md5_matches_noetic(pkg, name):
    assert _lookup(pkg, name)._md5sum == NOETIC_MD5[(pkg, name)], "%s/%s differs from Noetic" % (pkg, name)


def test_switch_controller_constants_and_fields():
    req = cm_srv.SwitchControllerRequest()
    assert (req.BEST_EFFORT, req.STRICT) == (1, 2)
    assert req.__slots__ == ["start_controllers", "stop_controllers", "strictness", "start_asap", "timeout"]


def test_follow_joint_trajectory_action_is_usable_by_actionlib():
    action = control_msgs_msg.FollowJointTrajectoryAction()
    assert action.action_goal.goal.__class__ is control_msgs_msg.FollowJointTrajectoryGoal
    result = control_msgs_msg.FollowJointTrajectoryResult()
    assert result.INVALID_JOINTS == -2 and hasattr(result, "error_string")
