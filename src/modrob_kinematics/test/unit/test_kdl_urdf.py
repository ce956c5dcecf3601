"""KDL tree and chain from a URDF string, checked against hand-written products of transforms."""
import math
import os

import numpy as np
import pytest

from modrob_kinematics import kdl_urdf
from modrob_kinematics.errors import KinematicsError, UnreachableError, UrdfError

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")


def fixture(name):
    with open(os.path.join(FIXTURES, name)) as f:
        return f.read()


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def origin(xyz, rpy=(0, 0, 0)):
    """URDF <origin>: translate, then rotate by R = Rz(yaw) Ry(pitch) Rx(roll)."""
    t = np.eye(4)
    t[:3, :3] = rot_z(rpy[2]).dot(rot_y(rpy[1])).dot(rot_x(rpy[0]))
    t[:3, 3] = xyz
    return t


def rotate_about(axis, angle):
    """Rodrigues' formula, axis normalised."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = np.eye(4)
    t[:3, :3] = np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx.dot(kx)
    return t


def slide_along(axis, d):
    t = np.eye(4)
    t[:3, 3] = np.asarray(axis, dtype=float) / np.linalg.norm(axis) * d
    return t


def mixed_by_hand(q1, q2, q3, q4, upto="tool0"):
    """world -> tool0 of mixed_joints.urdf, link by link."""
    t = origin((0.1, -0.2, 0.5), (0, 0, math.pi / 2))
    t = t.dot(origin((0, 0, 0.1))).dot(rotate_about((0, 0, 1), q1))
    if upto == "sensor_link":
        return t.dot(origin((0, 0.1, 0.05)))
    t = t.dot(origin((0.05, 0, 0.2), (0.3, 0, 0))).dot(slide_along((0, 0, 1), q2))
    t = t.dot(origin((0, 0.02, 0.15), (0, 0, 0.4))).dot(rotate_about((0, 1, 0), q3))
    t = t.dot(origin((0.2, 0, 0), (0.1, 0.2, 0.3))).dot(rotate_about((1, 1, 0), q4))
    return t.dot(origin((0.1, 0, 0)))


CONFIGS = [(0, 0, 0, 0), (0.5, 0.1, -1.2, 0.7), (-2.5, 0.2, 4.0, -1.9), (1.0, 0.05, math.pi, 1.5)]


@pytest.fixture(scope="module")
def tree():
    return kdl_urdf.tree_from_urdf_string(fixture("mixed_joints.urdf"))


def test_tree_structure(tree):
    assert tree.root == "world"
    assert tree.joint_names == ["j1", "j2", "j3", "j4"]
    assert tree.tree.getNrOfJoints() == 4
    assert tree.tree.getNrOfSegments() == 7  # every link but the root
    assert tree.limits["j1"] == (-2.9, 2.9)
    assert tree.limits["j2"] == (0.0, 0.2)
    assert tree.limits["j3"] == (-math.inf, math.inf)
    assert tree.joint_types["tool_joint"] == "fixed"
    assert tree.warnings == []


@pytest.mark.parametrize("q", CONFIGS)
def test_chain_fk_matches_hand_product(tree, q):
    chain = kdl_urdf.KinematicChain(tree, "world", "tool0")
    assert chain.joint_names == ["j1", "j2", "j3", "j4"]
    np.testing.assert_allclose(chain.fk_matrix(q), mixed_by_hand(*q), atol=1e-9)


@pytest.mark.parametrize("q", CONFIGS)
def test_tree_fk_matches_hand_product_on_both_branches(tree, q):
    solver = kdl_urdf.TreeFkSolverPos(tree)
    by_name = dict(zip(tree.joint_names, q))
    np.testing.assert_allclose(kdl_urdf.frame_to_matrix(solver.jnt_to_cart(by_name, "tool0")),
                               mixed_by_hand(*q), atol=1e-9)
    np.testing.assert_allclose(kdl_urdf.frame_to_matrix(solver.jnt_to_cart(list(q), "sensor_link")),
                               mixed_by_hand(*q, upto="sensor_link"), atol=1e-9)


def test_sub_chain_and_pose_outputs(tree):
    q = (0.3, 0.1, 0.2, -0.4)
    sub = kdl_urdf.KinematicChain(tree, "link2", "tool0")
    assert sub.joint_names == ["j3", "j4"]
    full = kdl_urdf.KinematicChain(tree, "world", "tool0")
    link2 = kdl_urdf.KinematicChain(tree, "world", "link2")
    expect = np.linalg.inv(link2.fk_matrix(q[:2])).dot(full.fk_matrix(q))
    np.testing.assert_allclose(sub.fk_matrix(q[2:]), expect, atol=1e-9)
    (x, y, z), quat = full.fk_pose(q)
    np.testing.assert_allclose((x, y, z), full.fk_matrix(q)[:3, 3], atol=1e-12)
    assert abs(np.linalg.norm(quat) - 1.0) < 1e-9


def test_inertia_is_rotated_into_the_link_frame(tree):
    info = tree.segments["link3"]
    rbi = info.segment.getInertia()
    assert rbi.getMass() == pytest.approx(0.5)
    cog = rbi.getCOG()
    np.testing.assert_allclose([cog[0], cog[1], cog[2]], [0.1, 0, 0], atol=1e-12)
    # pitch +90 deg swaps the x and z principal axes: (0.003, 0.002, 0.001) -> (0.001, 0.002, 0.003)
    np.testing.assert_allclose(np.diag(info.inertia_matrix), [0.001, 0.002, 0.003], atol=1e-12)


def test_ik_round_trip_position_and_pose(tree):
    chain = kdl_urdf.KinematicChain(tree, "world", "tool0")
    for q in [(0.5, 0.1, -1.2, 0.7), (-1.0, 0.15, 2.0, 1.0)]:
        target = chain.fk_position(q)
        sol = chain.ik(target, q0=(0, 0.05, 0, 0))
        assert chain.within_limits(sol)
        np.testing.assert_allclose(chain.fk_position(sol), target, atol=1e-4)
        pose = chain.fk_matrix(q)
        sol = chain.ik(pose, q0=(q[0] + 0.2, 0.1, q[2] - 0.2, q[3] + 0.2))
        np.testing.assert_allclose(chain.fk_matrix(sol), pose, atol=1e-3)


def test_ik_unreachable_is_reported(tree):
    chain = kdl_urdf.KinematicChain(tree, "world", "tool0")
    with pytest.raises(UnreachableError) as err:
        chain.ik((3.0, 3.0, 3.0))
    assert "reaches at most" in str(err.value)
    # inside the reach bound, but out of the workspace (straight below the base, under the table)
    with pytest.raises(UnreachableError) as err:
        chain.ik((0.1, -0.2, 0.05), attempts=5)
    assert err.value.residual > 1e-3
    assert "best position error" in str(err.value)


def test_ik_respects_limits_on_a_two_link_arm():
    arm = kdl_urdf.KinematicChain.from_urdf_string(fixture("planar_limited.urdf"))
    assert arm.tip_link == "tip"
    # reachable geometrically only with shoulder = -1.0 rad, below its lower limit of -0.5
    target = arm.fk_position((-1.0, 0.3))
    with pytest.raises(UnreachableError):
        arm.ik(target)
    target = arm.fk_position((0.4, 0.3))
    sol = arm.ik(target)
    assert arm.within_limits(sol)


def test_bad_inputs_name_the_problem(tree):
    with pytest.raises(UrdfError, match="exactly one root link"):
        kdl_urdf.tree_from_urdf_string(fixture("two_roots_bad.urdf"))
    with pytest.raises(UrdfError, match="empty"):
        kdl_urdf.tree_from_urdf_string("")
    with pytest.raises(UrdfError, match="not a valid URDF"):
        kdl_urdf.tree_from_urdf_string("<robot name='x'><link name='a'/")
    bad_link = fixture("mixed_joints.urdf").replace('<child link="tool0"/>', '<child link="tool9"/>')
    with pytest.raises(UrdfError, match="tool9"):
        kdl_urdf.tree_from_urdf_string(bad_link)
    no_limit = fixture("mixed_joints.urdf").replace(
        '<limit lower="-2" upper="2" effort="5" velocity="1"/>', '')
    with pytest.raises(UrdfError, match="j4"):
        kdl_urdf.tree_from_urdf_string(no_limit)
    with pytest.raises(KinematicsError, match="nosuch"):
        kdl_urdf.KinematicChain(tree, "world", "nosuch")
    with pytest.raises(KinematicsError, match="not an ancestor"):
        kdl_urdf.KinematicChain(tree, "sensor_link", "tool0")
    chain = kdl_urdf.KinematicChain(tree, "world", "tool0")
    with pytest.raises(KinematicsError, match="4 joints"):
        chain.fk([0, 0])
    with pytest.raises(KinematicsError, match="non-finite"):
        chain.fk([0, float("nan"), 0, 0])
    with pytest.raises(KinematicsError, match="non-finite"):
        chain.ik((0.1, float("inf"), 0.2))
    with pytest.raises(KinematicsError, match="not a movable joint"):
        kdl_urdf.TreeFkSolverPos(tree).jnt_to_cart({"elbow": 1.0}, "tool0")


def test_floating_joint_becomes_fixed_with_warning():
    xml = fixture("mixed_joints.urdf").replace('name="world_to_base" type="fixed"',
                                               'name="world_to_base" type="floating"')
    tree = kdl_urdf.tree_from_urdf_string(xml)
    assert any("world_to_base" in w for w in tree.warnings)
    assert tree.joint_names == ["j1", "j2", "j3", "j4"]
