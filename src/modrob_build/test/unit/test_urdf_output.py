"""Generated URDFs: check_urdf, joint counts, colours, transmissions, plugin, gripper, base pose."""
import subprocess
import xml.etree.ElementTree as ET

import pytest

from modrob_build.build import RobotSpec, build_robot_set
from modrob_build.module_database import load_database

SEED_3DOF = [59, 3, 55, 63, 57, 5]
SEED_6DOF = [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5]


@pytest.fixture(scope="module")
def db():
    return load_database()


def generate(db, order, gripper=False, base=None, tmp=None):
    result = build_robot_set([RobotSpec(order, base)], gripper=gripper, db=db)
    return result.files["modrob0.urdf"], result


def check_urdf(tmp_path, text):
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    out = subprocess.run(["check_urdf", str(path)], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    return out.stdout


def joints(root, jtype):
    return [j for j in root.findall("joint") if j.get("type") == jtype]


@pytest.mark.parametrize("order,n_joints", [(SEED_3DOF, 3), (SEED_6DOF, 6)])
@pytest.mark.parametrize("gripper", [False, True])
def test_seed_orders_pass_check_urdf(db, tmp_path, order, n_joints, gripper):
    text, _ = generate(db, order, gripper)
    out = check_urdf(tmp_path, text)
    assert "root Link: world" in out
    root = ET.fromstring(text)
    revolute = joints(root, "revolute")
    assert [j.get("name") for j in revolute] == ["joint%d" % k for k in range(1, n_joints + 1)]
    prismatic = joints(root, "prismatic")
    assert len(prismatic) == (2 if gripper else 0)
    for j in prismatic:
        assert j.find("axis").get("xyz") == "0 1 0"
        assert float(j.find("limit").get("effort")) == 3.0
    actuated = [j for j in prismatic if j.find("mimic") is None]
    if gripper:   # finger 2 mimics finger 1: one actuated finger, as a parallel gripper
        assert [j.get("name") for j in actuated] == ["gripper_finger1_joint"]
        assert prismatic[1].find("mimic").get("joint") == "gripper_finger1_joint"
    transmissions = root.findall("transmission")
    assert len(transmissions) == n_joints + len(actuated)
    names = {t.find("joint").get("name") for t in transmissions}
    assert names == {j.get("name") for j in revolute + actuated}


def test_transmissions_as_seed_figure_6(db):
    text, _ = generate(db, SEED_3DOF)
    root = ET.fromstring(text)
    for k, tr in enumerate(root.findall("transmission"), start=1):
        assert tr.get("name") == "trans%d" % k
        assert tr.findtext("type") == "transmission_interface/SimpleTransmission"
        assert tr.find("joint").get("name") == "joint%d" % k
        assert tr.find("joint").findtext("hardwareInterface") == "hardware_interface/EffortJointInterface"
        act = tr.find("actuator")
        assert act.get("name") == "motor%d" % k
        assert act.findtext("hardwareInterface") == "hardware_interface/EffortJointInterface"
        assert float(act.findtext("mechanicalReduction")) == 160.0


def test_control_plugin_namespace_per_robot(db):
    result = build_robot_set([RobotSpec(SEED_3DOF), RobotSpec(SEED_6DOF)], db=db)
    for n in (0, 1):
        root = ET.fromstring(result.files["modrob%d.urdf" % n])
        plugins = [p for g in root.findall("gazebo") for p in g.findall("plugin")]
        assert len(plugins) == 1
        p = plugins[0]
        assert p.get("name") == "gazebo_ros_control" and p.get("filename") == "libgazebo_ros_control.so"
        assert p.findtext("robotNamespace") == "/modrob%d" % n
        assert p.findtext("robotSimType") == "gazebo_ros_control/DefaultRobotHWSim"


def test_colours_links_grey_joints_blue(db):
    text, _ = generate(db, SEED_6DOF)
    root = ET.fromstring(text)
    rgba = {m.get("name"): m.find("color").get("rgba") for m in root.findall("material")}
    gz = {g.get("reference"): g for g in root.findall("gazebo") if g.get("reference")}
    n_checked = 0
    for link in root.findall("link"):
        name = link.get("name")
        if link.find("visual") is None:
            continue
        is_joint_module = "_housing" in name or "_output" in name
        expected = "Gazebo/Blue" if is_joint_module else "Gazebo/DarkGrey"
        assert gz[name].findtext("material") == expected, name
        assert float(gz[name].findtext("mu1")) > 0 and float(gz[name].findtext("mu2")) > 0
        for vis in link.findall("visual"):
            colour = [float(v) for v in rgba[vis.find("material").get("name")].split()]
            if is_joint_module:
                assert colour[2] > 0.5 and colour[0] < 0.2, name
            else:
                assert max(colour[:3]) < 0.3, name
        n_checked += 1
    assert n_checked == 1 + 5 + 2 * 6   # base, five tubes, two bodies per joint module


def test_joint_dynamics_and_limits_from_database(db):
    text, _ = generate(db, SEED_3DOF)
    root = ET.fromstring(text)
    j1 = next(j for j in root.findall("joint") if j.get("name") == "joint1")
    m = db[55]
    assert float(j1.find("dynamics").get("damping")) == m.damping
    assert float(j1.find("dynamics").get("friction")) == m.friction
    assert float(j1.find("limit").get("effort")) == m.effort
    assert j1.find("axis").get("xyz") == "0 0 1"
    j2 = next(j for j in root.findall("joint") if j.get("name") == "joint2")
    assert j2.find("axis").get("xyz") == "0 1 0"


def test_base_fixed_to_world_at_base_pose(db):
    text, _ = generate(db, SEED_3DOF, base=(0.4, -0.2, 1.02, 0.5))
    root = ET.fromstring(text)
    wj = next(j for j in root.findall("joint") if j.get("name") == "world_joint")
    assert wj.get("type") == "fixed"
    assert wj.find("parent").get("link") == "world"
    assert wj.find("child").get("link") == "modrob0_base_link"
    assert wj.find("origin").get("xyz") == "0.4 -0.2 1.02"
    assert wj.find("origin").get("rpy") == "0 0 0.5"


def test_ee_frame_at_the_tip_and_gripper_tcp(db):
    text, _ = generate(db, SEED_3DOF, gripper=True)
    root = ET.fromstring(text)
    names = [lk.get("name") for lk in root.findall("link")]
    for expected in ("modrob0_ee_link", "modrob0_gripper_base", "modrob0_gripper_finger1",
                     "modrob0_gripper_finger2", "modrob0_gripper_tcp"):
        assert expected in names
    ee = next(j for j in root.findall("joint") if j.get("name") == "ee_joint")
    assert ee.find("parent").get("link") == "modrob0_tube2"
    assert ee.find("origin").get("xyz") == "0 0 %g" % db[5].length


def test_grip_force_argument(db):
    result = build_robot_set([RobotSpec(SEED_3DOF)], gripper=True, grip_force=7.0, db=db)
    root = ET.fromstring(result.files["modrob0.urdf"])
    assert [float(j.find("limit").get("effort")) for j in joints(root, "prismatic")] == [7.0, 7.0]
    assert "gripper_finger1_position_controller" in result.files["modrob0_controllers.yaml"]


def test_output_is_deterministic(db):
    a = build_robot_set([RobotSpec(SEED_6DOF)], gripper=True, db=db, out_dir="/x").files
    b = build_robot_set([RobotSpec(SEED_6DOF)], gripper=True, db=db, out_dir="/x").files
    assert a == b
