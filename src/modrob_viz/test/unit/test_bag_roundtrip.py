"""Record/replay is lossless: 3700 joint points (the seed's figure) and 3D points through bags;
joint-path validation, FK of every point, decimation and milestone reduction."""
import math
import os

import numpy as np
import pytest
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

import genpy
import rosbag
from modrob_kinematics import kdl_urdf
from modrob_viz import bag_io, joint_path, paths
from modrob_viz.errors import BagError, TrajectoryError

FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
NAMES = ["j1", "j2", "j3", "j4"]


def seed_trajectory(n=3700, names=NAMES):
    traj = JointTrajectory()
    traj.header.frame_id = "world"
    traj.joint_names = list(names)
    for i in range(n):
        s = i / (n - 1.0)
        p = JointTrajectoryPoint()
        p.positions = [1.2 * math.sin(2 * math.pi * s), 0.1 + 0.08 * math.sin(6 * s),
                       -0.7 + s * 1.3 + 1e-13 * i, 0.9 * math.cos(3 * s)]
        p.time_from_start = genpy.Duration.from_sec(0.003 * i)
        traj.points.append(p)
    return traj


@pytest.fixture(scope="module")
def tree():
    with open(os.path.join(FIXTURES, "mixed_joints.urdf")) as f:
        return kdl_urdf.tree_from_urdf_string(f.read())


def test_joint_trajectory_bag_round_trip_is_lossless(tmp_path, tree):
    traj = seed_trajectory()
    bag = str(tmp_path / "joint.bag")
    assert bag_io.append_joint_trajectory(bag, traj) == 3700
    back = bag_io.read_joint_trajectory(bag)
    assert back.names == NAMES and len(back) == 3700
    sent = np.array([p.positions for p in traj.points])
    assert np.array_equal(back.positions, sent)  # bit-identical, not just close
    assert back.times[-1] == pytest.approx(0.003 * 3699)
    ee = joint_path.end_effector_path(tree, back, "tool0")
    assert ee.shape == (3700, 3)
    chain = kdl_urdf.KinematicChain(tree, "world", "tool0")
    for i in (0, 1234, 3699):
        np.testing.assert_allclose(ee[i], chain.fk_position(sent[i]), atol=1e-12)


def test_appending_two_trajectories_concatenates(tmp_path):
    bag = str(tmp_path / "joint.bag")
    bag_io.append_joint_trajectory(bag, seed_trajectory(100))
    bag_io.append_joint_trajectory(bag, seed_trajectory(50))
    assert len(bag_io.read_joint_trajectory(bag)) == 150
    bag_io.append_joint_trajectory(bag, seed_trajectory(10, names=["a", "b", "c", "d"]))
    with pytest.raises(BagError, match="different joints"):
        bag_io.read_joint_trajectory(bag)


def test_rosbag_record_of_tp_rv_topic_is_read(tmp_path):
    bag = str(tmp_path / "tp.bag")
    with rosbag.Bag(bag, "w") as b:
        b.write("/tp_rv_topic", seed_trajectory(300), genpy.Time(1))
    assert len(bag_io.read_joint_trajectory(bag)) == 300


def test_3d_points_round_trip_is_lossless(tmp_path):
    pts = paths.helix(n=3700)
    bag = str(tmp_path / "points.bag")
    assert bag_io.write_points(bag, pts, "world") == 3700
    back, frame = bag_io.read_points(bag)
    assert frame == "world" and back == pts


def test_bad_bags_are_named(tmp_path):
    missing = str(tmp_path / "nope.bag")
    with pytest.raises(BagError, match="does not exist"):
        bag_io.read_points(missing)
    junk = tmp_path / "junk.bag"
    junk.write_text("this is not a bag")
    with pytest.raises(BagError, match="cannot open bag"):
        bag_io.read_joint_trajectory(str(junk))
    points_bag = str(tmp_path / "points.bag")
    bag_io.write_points(points_bag, paths.line(n=5), "world")
    with pytest.raises(BagError, match="no joint trajectory.*/trajectory_3d/points"):
        bag_io.read_joint_trajectory(points_bag)
    with pytest.raises(BagError, match="no topic '/elsewhere'"):
        bag_io.read_points(points_bag, topic="/elsewhere")
    with pytest.raises(BagError, match="~bag_file"):
        bag_io.read_points("")


def test_joint_path_validation(tree):
    with pytest.raises(TrajectoryError, match="elbow.*lacks"):
        jp = joint_path.JointPath(["j1", "j2", "elbow", "j4"], [[0, 0, 0, 0]])
        joint_path.end_effector_path(tree, jp, "tool0")
    with pytest.raises(TrajectoryError, match="lacks joint.*j3"):
        joint_path.end_effector_path(tree, joint_path.JointPath(["j1", "j2", "j4"], [[0, 0, 0]]), "tool0")
    with pytest.raises(TrajectoryError, match="point 1 has 3 positions"):
        traj = seed_trajectory(3)
        traj.points[1].positions = [0, 0, 0]
        joint_path.JointPath.from_points(traj.joint_names, traj.points)
    with pytest.raises(TrajectoryError, match="non-finite"):
        joint_path.JointPath(NAMES, [[0, 0, float("nan"), 0]])
    # a side-branch joint the FK does not need is fine; the fixed joint's name is known too
    jp = joint_path.JointPath(NAMES, [[0, 0.1, 0, 0]])
    assert joint_path.end_effector_path(tree, jp, "link2").shape == (1, 3)


def test_decimate_keeps_last_of_every_five():
    assert joint_path.decimate(12, 5) == [4, 9, 11]
    assert joint_path.decimate(10, 5) == [4, 9]
    assert joint_path.decimate(3, 5) == [2]
    assert joint_path.decimate(4, 1) == [0, 1, 2, 3]
    assert len(joint_path.decimate(3700, 5)) == 740
    with pytest.raises(TrajectoryError, match="keep_every"):
        joint_path.decimate(10, 0)


def test_milestone_reduction_keeps_ee_path_within_tolerance(tree):
    jp = joint_path.JointPath.from_points(NAMES, seed_trajectory(3700).points)
    ee = joint_path.end_effector_path(tree, jp, "tool0")
    kept = joint_path.reduce_milestones(ee, 0.002)
    assert 2 < len(kept) < 3700 / 10
    reduced = jp.subset(kept)
    ee_reduced = joint_path.end_effector_path(tree, reduced, "tool0")
    from modrob_viz.geometry import PolylineDistance
    poly = PolylineDistance(ee_reduced)
    assert max(poly.distance(p) for p in ee) <= 0.002 + 1e-12


def test_bag_still_being_written_is_reported_as_waiting(tmp_path):
    path = str(tmp_path / "open.bag")
    writer = rosbag.Bag(path, "w")
    try:
        writer.write(bag_io.JOINT_POINTS_TOPIC, seed_trajectory(2).points[0], genpy.Time(1))
        writer.flush()
        with pytest.raises(BagError, match="unindexed") as err:
            bag_io.read_points(path)
        assert err.value.waiting
    finally:
        writer.close()
    with pytest.raises(BagError, match="does not exist") as err:
        bag_io.read_points(str(tmp_path / "later.bag"))
    assert err.value.waiting
