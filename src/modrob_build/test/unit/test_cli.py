"""create_urdf_and_gazebo: exit 0 writes every file; exit 2 refuses with the reason, writes nothing."""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest
import yaml

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                      "scripts", "create_urdf_and_gazebo")


def run(*args):
    return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)


def test_two_robots_with_gripper(tmp_path):
    out = tmp_path / "robots"
    r = run("--order", "59,3,55,63,57,5", "--base", "0,0,1.02", "--order", "59,3,55,63,64,4,66,4,67,5,56,5",
            "--base", "0.2,0,1.02", "--gripper", "--safety-distance", "0.9", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert sorted(os.listdir(out)) == sorted(["modrob0.urdf", "modrob1.urdf", "modrob0_controllers.yaml",
                                              "modrob1_controllers.yaml", "modrob_spawn.launch",
                                              "modrob_robots.launch", "modrob_robots.yaml"])
    assert "safety distance" in r.stdout and "modrob1" in r.stdout
    manifest = yaml.safe_load((out / "modrob_robots.yaml").read_text())
    assert manifest["robots"][1]["base"][:3] == pytest.approx([0.9, 0.0, 1.02])
    launch = ET.parse(str(out / "modrob_spawn.launch")).getroot()
    groups = launch.findall("group")
    assert [g.get("ns") for g in groups] == ["modrob0", "modrob1"]
    for n, g in enumerate(groups):
        assert g.find("param").get("textfile") == str(out / ("modrob%d.urdf" % n))
        nodes = {nd.get("type"): nd for nd in g.findall("node")}
        assert nodes["spawn_model"].get("pkg") == "modrob_sim"
        assert nodes["spawn_model"].get("args") == "-urdf -param robot_description -model modrob%d" % n
        assert nodes["spawner"].get("pkg") == "modrob_sim"
        spawned = nodes["spawner"].get("args").split()
        assert spawned[:2] == ["joint_state_controller", "joint1_position_controller"]
        assert spawned[-1] == "gripper_finger1_position_controller"   # finger 2 mimics it
        assert nodes["robot_state_publisher"].find("remap").get("to") == "/modrob%d/joint_states" % n
        assert g.find("rosparam").get("file") == str(out / ("modrob%d_controllers.yaml" % n))
    world = ET.parse(str(out / "modrob_robots.launch")).getroot()
    inc = world.findall("include")
    assert inc[0].get("file") == "$(find modrob_sim)/launch/empty_world.launch"
    assert {a.get("name") for a in inc[0].findall("arg")} == {"world_name", "paused", "gui", "headless",
                                                              "real_time_factor"}


@pytest.mark.parametrize("args,fragments", [
    (["--order", "59,3,99"], ["position 3", "ID 99"]),
    (["--order", "3,59,55"], ["position 1", "ID 3"]),
    (["--order", "59,3,55,59,63"], ["position 4", "ID 59"]),
    (["--order", "59,3,4"], ["no joint"]),
    (["--order", ""], ["empty"]),
    (["--order", "59,3,fifty"], ["position 3", "'fifty'"]),
    (["--order", "59,3,55", "--order", "59,4,99"], ["modrob1", "position 3", "ID 99"]),
    (["--order", "59,3,55", "--base", "0,0"], ["X,Y,Z"]),
    (["--order", "59,3,55", "--order", "59,3,55", "--base", "0,0,0"], ["one --base per --order"]),
    (["--order", "59,3,55", "--gripper", "--grip-force", "50"], ["grip force"]),
    (["--order", "59,3,55", "--safety-distance", "-1"], ["safety_distance"]),
])
def test_refused_input_exit_2_and_nothing_written(tmp_path, args, fragments):
    out = tmp_path / "never"
    r = run(*(args + ["--out", str(out)]))
    assert r.returncode == 2, r.stdout + r.stderr
    for f in fragments:
        assert f in r.stderr
    assert "nothing was written" in r.stderr
    assert not out.exists()


def test_refused_input_leaves_existing_folder_untouched(tmp_path):
    (tmp_path / "keep.txt").write_text("x")
    r = run("--order", "59,3,99", "--out", str(tmp_path))
    assert r.returncode == 2
    assert os.listdir(tmp_path) == ["keep.txt"]
