"""Tier 1: xyz targets through KDL IK (modrob_kinematics.kdl_urdf) land within 5 mm; far ones are refused."""
import math
import os

import pytest

from modrob_motion.cartesian import CartesianIk, default_tip
from modrob_motion.errors import MotionError
from modrob_motion.robot_info import robot_info_from_urdf
from modrob_motion.terminal import DictDirectory, MotionTerminal

pytest.importorskip("PyKDL")

LINK = ('<link name="%s"><inertial><mass value="0.5"/>'
        '<inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial></link>')
LINKS = ("base", "l1", "l2", "l3", "gripper_base", "finger_a")
URDF = "<robot name='arm'>" + "".join(LINK % n for n in LINKS) + """
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-2.5" upper="2.5" effort="10" velocity="1"/></joint>
  <joint name="tool" type="fixed"><parent link="l3"/><child link="gripper_base"/>
    <origin xyz="0 0 0.25"/></joint>
  <joint name="finger_a_joint" type="prismatic"><parent link="gripper_base"/><child link="finger_a"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.03" effort="3" velocity="0.1"/></joint>
</robot>"""

BASE = ((0.2, -0.1, 1.02), (0.0, 0.0, math.sin(0.25), math.cos(0.25)))


def make_ik():
    info = robot_info_from_urdf(0, URDF)
    tip = default_tip(URDF, info.gripper.joints)
    ik = CartesianIk(URDF, info.arm_joints, tip_link=tip, tcp_offset=(0, 0, 0.05), base_pose=BASE)
    return info, ik


def test_default_tip_is_gripper_base():
    info = robot_info_from_urdf(0, URDF)
    assert default_tip(URDF, info.gripper.joints) == "gripper_base"


def test_fk_then_ik_reaches_within_5mm():
    info, ik = make_ik()
    for q in ([0.3, 0.4, 0.8], [-1.0, -0.3, 1.2], [2.0, 0.9, -0.5]):
        target = ik.forward(dict(zip(info.arm_joints, q)))
        solved = ik.solve(info, target, [0.0, 0.0, 0.0])
        reached = ik.forward(dict(zip(info.arm_joints, solved)))
        assert math.dist(target, reached) < 0.005


def test_unreachable_says_so():
    info, ik = make_ik()
    with pytest.raises(MotionError, match="unreachable for modrob0"):
        ik.solve(info, (3.0, 0.0, 1.0), [0.0, 0.0, 0.0])


def test_terminal_xyz_line():
    info, ik = make_ik()
    term = MotionTerminal(DictDirectory({0: info}), ik_solver=ik.solve)
    target = ik.forward({"j1": 0.2, "j2": 0.5, "j3": 0.6})
    reply = term.handle("xyz %.6f %.6f %.6f" % target)
    assert reply.ok, reply.text
    reached = ik.forward(dict(zip(reply.command.names, reply.command.positions)))
    assert math.dist(target, reached) < 0.005
    reply = term.handle("xyz 0 0 9")
    assert not reply.ok and "unreachable" in reply.text


def test_chain_through_a_finger_is_refused():
    info = robot_info_from_urdf(0, URDF)
    with pytest.raises(MotionError, match="finger_a_joint"):
        CartesianIk(URDF, info.arm_joints, tip_link="finger_a")


def test_fixture_file_present():
    here = os.path.dirname(os.path.abspath(__file__))
    assert os.path.exists(os.path.join(here, "test_motion_arm_gripper.urdf"))
