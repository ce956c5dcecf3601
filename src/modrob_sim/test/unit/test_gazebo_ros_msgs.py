"""gazebo_msgs must stay wire-identical to ROS Noetic's gazebo_msgs: same fields, types, order and
constants give the same MD5 sums, which rospy checks on every connection. The expected sums are
those of Noetic's generated code (2.9.x); a changed field makes this test fail."""
import importlib

import pytest

NOETIC_MD5 = {
    "msg/ContactState": "48c0ffb054b8c444f870cecea1ee50d9",
    "msg/ContactsState": "acbcb1601a8e525bf72509f18e6f668d",
    "msg/LinkState": "0818ebbf28ce3a08d48ab1eaa7309ebe",
    "msg/LinkStates": "48c080191eb15c41858319b4d8a609c2",
    "msg/ModelState": "9330fd35f2fcd82d457e54bd54e10593",
    "msg/ModelStates": "48c080191eb15c41858319b4d8a609c2",
    "msg/ODEJointProperties": "1b744c32a920af979f53afe2f9c3511f",
    "msg/ODEPhysics": "667d56ddbd547918c32d1934503dc335",
    "msg/PerformanceMetrics": "884f71fd5037b886ec5e126b83c4425a",
    "msg/WorldState": "de1a9de3ab7ba97ac0e9ec01a4eb481e",
    "srv/ApplyBodyWrench": "585b9f9618aa0581b207e2f2d90866bc",
    "srv/ApplyJointEffort": "c0039811b8cc919490b3cff748cdf46b",
    "srv/BodyRequest": "5eade9afe7f232d78005bd0cafeab755",
    "srv/DeleteLight": "ae11ea8100d536d5b92c2b5917abf912",
    "srv/DeleteModel": "9ce56b4e9e54616de25d796dc972a262",
    "srv/GetJointProperties": "7b30be900f50aa21efec4a0ec92d91c9",
    "srv/GetLightProperties": "df2cef87e13e2e6990e81e8aaa454c19",
    "srv/GetLinkProperties": "0e06a70386d0ee3fb880c02f23fcd821",
    "srv/GetLinkState": "09d6c98cce97b35f7ab9bd70300657ab",
    "srv/GetModelProperties": "5717f7bd34ed990fa80e28b3015027a3",
    "srv/GetModelState": "4c515e936d3319c9610c559c60bfc3d4",
    "srv/GetPhysicsProperties": "575a5e74786981b7df2e3afc567693a6",
    "srv/GetWorldProperties": "36bb0f2eccf4d8be971410c22818ba3f",
    "srv/JointRequest": "0be1351618e1dc030eb7959d9a4902de",
    "srv/SetJointProperties": "15a76e921b1410c698d82782ea5fa370",
    "srv/SetJointTrajectory": "88f5c10979e3f9649d5ae87a3b12aa65",
    "srv/SetLightProperties": "e6f13430c57278bb364aca53a1bf5ebf",
    "srv/SetLinkProperties": "d534ce1b36ee99de0ffa806c3a6348f0",
    "srv/SetLinkState": "8a5146eb66ae4d26b0860b08f3f271be",
    "srv/SetModelConfiguration": "10e3139d3b669c40afc057d38956fff7",
    "srv/SetModelState": "5b3ab0281d4f5445def017e3a2e4a07b",
    "srv/SetPhysicsProperties": "97e2057080558ce4730434b5fae75c91",
    "srv/SpawnModel": "9ed9c82c96abe1a00c3e8cdaeee24413",
}


@pytest.mark.parametrize("name", sorted(NOETIC_MD5))
def test_md5_matches_noetic(name):
    kind, typ = name.split("/")
    module = importlib.import_module("gazebo_msgs." + kind)
    assert getattr(module, typ)._md5sum == NOETIC_MD5[name], name


def test_joint_type_constants():
    from gazebo_msgs.srv import GetJointPropertiesResponse as R
    assert (R.REVOLUTE, R.CONTINUOUS, R.PRISMATIC, R.FIXED, R.BALL, R.UNIVERSAL) == (0, 1, 2, 3, 4, 5)


def test_spawn_model_fields_in_order():
    from gazebo_msgs.srv import SpawnModelRequest
    assert SpawnModelRequest.__slots__ == [
        "model_name", "model_xml", "robot_namespace", "initial_pose", "reference_frame"]
