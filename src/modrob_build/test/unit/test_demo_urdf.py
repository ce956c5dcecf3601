"""The committed RViz demo robot (urdf/modrob_4dof_demo.urdf) is what the build produces today,
and it is a valid four-joint URDF."""
import os
import subprocess

from modrob_build.demo_robot import DEMO_NAME, demo_urdf
from modrob_build.module_database import default_database_path

DEMO = os.path.join(os.path.dirname(os.path.dirname(default_database_path())), "urdf",
                    "modrob_4dof_demo.urdf")


def test_committed_demo_urdf_equals_regenerated():
    with open(DEMO) as f:
        committed = f.read()
    assert committed == demo_urdf(), (
        "urdf/modrob_4dof_demo.urdf is stale: run `rosrun modrob_build create_demo_urdf` and commit it")


def test_demo_urdf_passes_check_urdf_with_four_revolute_joints():
    out = subprocess.run(["check_urdf", DEMO], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "robot name is: %s" % DEMO_NAME in out.stdout
    with open(DEMO) as f:
        text = f.read()
    assert text.count('type="revolute"') == 4
    assert '<link name="ee_link"' in text and '<link name="base_link"' in text
