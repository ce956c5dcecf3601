"""Default gains from the auto-tuner's table (config/tuned_gains.yaml), the fallback to computed gains
for orders the table lacks, and clear refusals for a malformed table."""
import os
import subprocess
import sys

import pytest
import yaml

from modrob_build import gains as gains_mod
from modrob_build.build import RobotSpec, build_robot_set
from modrob_build.errors import BuildError
from modrob_build.module_database import load_database
from modrob_build.order import validate_order
from modrob_build.robot_model import build_robot_model
from modrob_build.tuned_gains import default_table_path, load_tuned_gains, order_key

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "scripts", "create_urdf_and_gazebo")
ARM3 = [59, 3, 55, 63, 57, 5]
SEED_6DOF = [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5]
GAINS = {"joint1": {"p": 1111.0, "i": 2222.0, "d": 33.0, "i_clamp": 4.0, "antiwindup": True,
                    "method": "relay+robot+sine"},
         "joint2": {"p": 5555.0, "i": 6666.0, "d": 77.0, "i_clamp": 8.0, "antiwindup": True}}


@pytest.fixture(scope="module")
def db():
    return load_database()


def write_table(path, robots):
    path.write_text(yaml.safe_dump({"robots": robots}))
    return str(path)


def pids(result, name="modrob0"):
    cfg = yaml.safe_load(result.files["%s_controllers.yaml" % name])[name]
    return {c["joint"]: c["pid"] for c in cfg.values() if "pid" in c}


def computed(db, order, gripper=True):
    robot = build_robot_model(validate_order(order, db), order)
    payload = gains_mod.GRIPPER_PAYLOAD if gripper else None
    return {lo.joint: gains_mod.pid_from_load(lo).as_dict() for lo in gains_mod.joint_loads(robot, payload)}


def test_tuned_joints_take_the_tables_gains_the_rest_are_computed(tmp_path, db):
    table = write_table(tmp_path / "t.yaml", {order_key(ARM3, True): GAINS})
    res = build_robot_set([RobotSpec(ARM3)], gripper=True, db=db, gains_table=table)
    got = pids(res)
    for j in ("joint1", "joint2"):
        assert {k: got[j][k] for k in ("p", "i", "d", "i_clamp")} == {
            k: GAINS[j][k] for k in ("p", "i", "d", "i_clamp")}
    assert got["joint3"] == computed(db, ARM3)["joint3"]
    assert res.manifest["robots"][0]["gains"] == {"joint1": "tuned", "joint2": "tuned", "joint3": "computed"}
    header = res.files["modrob0_controllers.yaml"].split("modrob0:")[0]
    assert "joint1, joint2: tuned by `rosrun modrob_motion tune_pid --all`" in header
    assert "joint3: computed" in header
    # the message says which joints fell back and how to tune them
    msg = " ".join(res.messages)
    assert "no tuned gains for joint3" in msg and "tune_pid --order 59,3,55,63,57,5 --gripper --all" in msg


def test_the_table_is_per_order_and_gripper(tmp_path, db):
    table = write_table(tmp_path / "t.yaml", {order_key(ARM3, True): GAINS})
    bare = build_robot_set([RobotSpec(ARM3)], gripper=False, db=db, gains_table=table)
    assert pids(bare)["joint1"] == computed(db, ARM3, gripper=False)["joint1"]
    assert "no tuned gains for joint1, joint2, joint3 of module order 59,3,55,63,57,5 " in bare.messages[0]


def test_computed_gains_ignore_the_table(tmp_path, db):
    table = write_table(tmp_path / "t.yaml", {order_key(ARM3, True): GAINS})
    res = build_robot_set([RobotSpec(ARM3)], gripper=True, db=db, gains="computed", gains_table=table)
    assert pids(res)["joint1"] == computed(db, ARM3)["joint1"]
    assert res.messages == []
    with pytest.raises(BuildError, match="gains 'fast'"):
        build_robot_set([RobotSpec(ARM3)], gripper=True, db=db, gains="fast")


def test_a_missing_table_means_computed_gains(tmp_path, db):
    res = build_robot_set([RobotSpec(ARM3)], gripper=True, db=db, gains_table=str(tmp_path / "none.yaml"))
    assert pids(res)["joint2"] == computed(db, ARM3)["joint2"]


@pytest.mark.parametrize("text, fragments", [
    ("robots: [1, 2", ["not valid YAML", "tune_pid --all"]),
    ("robots: [1, 2]", ["'robots' must map"]),
    ("robots: {'59,3': [1]}", ["robots/59,3 must map joint names"]),
    ("robots: {'59,3': {joint1: 5}}", ["robots/59,3/joint1 is not a mapping"]),
    ("robots: {'59,3': {joint1: {p: -1, i: 0, d: 0, i_clamp: 0}}}", ["robots/59,3/joint1", "'p' is -1"]),
    ("robots: {'59,3': {joint1: {p: .nan, i: 0, d: 0, i_clamp: 0}}}", ["'p' is nan"]),
    ("robots: {'59,3': {joint1: {p: 1, i: 0, d: 0}}}", ["'i_clamp' is None"]),
])
def test_a_malformed_table_is_refused_naming_file_and_entry(tmp_path, text, fragments):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(BuildError) as info:
        load_tuned_gains(str(path))
    assert str(path) in str(info.value)
    for f in fragments:
        assert f in str(info.value)


def test_cli_refuses_a_malformed_table_and_writes_nothing(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("robots: {'59,3,55,63,57,5': {joint1: {p: x}}}")
    out = tmp_path / "never"
    r = subprocess.run([sys.executable, SCRIPT, "--order", "59,3,55,63,57,5", "--gains-table", str(bad),
                        "--out", str(out)], capture_output=True, text=True)
    assert r.returncode == 2, r.stdout + r.stderr
    assert str(bad) in r.stderr and "'p' is 'x'" in r.stderr and "nothing was written" in r.stderr
    assert not out.exists()
    ok = subprocess.run([sys.executable, SCRIPT, "--order", "59,3,55,63,57,5", "--gains", "computed",
                         "--gains-table", str(bad), "--out", str(out)], capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr


def test_the_shipped_table_covers_the_bulbs_and_slides_robots():
    """The robots `make demo` builds get tuned gains for every arm joint; the table is what
    `tune_pid --all --defaults` wrote (its notes say how each joint fared in the checks)."""
    table = load_tuned_gains(default_table_path())
    for order, n in ((SEED_6DOF, 6), (ARM3, 3)):
        got = table.lookup(order, True)
        assert sorted(got) == ["joint%d" % k for k in range(1, n + 1)], (order, table.keys())
        for joint, entry in table.robots[order_key(order, True)].items():
            assert entry["method"].startswith("relay"), (order, joint)
            assert "large step" in entry["checked"] and len(entry["checked"]) >= 3, (order, joint)
            sine = entry["checked"].get("fast sine")
            assert sine is not None, (order, joint)     # a 1.5 Hz swing is followed
            assert sine["amplitude_ratio"] >= min(0.8, sine["before"]["amplitude_ratio"]), (order, joint)
            for label, fig in entry["checked"].items():
                if label == "fast sine":
                    continue
                # tune_pid's acceptance rule: every step settles (within 2 % in the 1.8 s observed),
                # overshooting at most 15 % or no more than with the gains it replaced
                assert fig["settling_time"] < 1.8, (order, joint, label)
                assert fig["overshoot"] <= max(0.15, fig["before"]["overshoot"]), (order, joint, label)
