"""The gripper macro (urdf/gripper.xacro): expands with xacro, passes check_urdf, and in the
modrob ODE core (no ROS) holds a 60 mm, 50 g sphere with 3 N and with 7 N per finger, the fingers
resting where the V-groove geometry says (q = r / sin 60 deg)."""
import math
import subprocess
import xml.etree.ElementTree as ET

import pytest

from modrob_build.gripper import attach_gripper
from modrob_sim.physics import World

SPHERE = """<?xml version="1.0"?>
<sdf version="1.6"><model name="bulb"><pose>{x} {y} {z} 0 0 0</pose><link name="glass">
  <inertial><mass>0.05</mass><inertia><ixx>1.8e-5</ixx><iyy>1.8e-5</iyy><izz>1.8e-5</izz>
    <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
  <collision name="glass"><geometry><sphere><radius>0.03</radius></sphere></geometry>
    <surface><friction><ode><mu>1.0</mu><mu2>1.0</mu2></ode></friction></surface></collision>
</link></model></sdf>"""
FINGERS = ("gripper_finger1_joint", "gripper_finger2_joint")


def gripper_pointing_down(grip_force):
    root = ET.fromstring(
        '<robot name="g"><link name="world"/><link name="ee"><inertial><mass value="0.1"/>'
        '<inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="fix" type="fixed"><parent link="world"/><child link="ee"/>'
        '<origin xyz="0 0 0.5" rpy="3.14159265 0 0"/></joint></robot>')
    return attach_gripper(root, "", "ee", grip_force)


def test_macro_expands_and_passes_check_urdf(tmp_path):
    text = gripper_pointing_down(3.0)
    path = tmp_path / "g.urdf"
    path.write_text(text)
    out = subprocess.run(["check_urdf", str(path)], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
    root = ET.fromstring(text)
    prismatic = [j for j in root.findall("joint") if j.get("type") == "prismatic"]
    assert [j.get("name") for j in prismatic] == list(FINGERS)
    assert {t.find("joint").get("name") for t in root.findall("transmission")} == set(FINGERS)


@pytest.mark.parametrize("grip_force", [3.0, 7.0])
def test_holds_a_bulb_sized_sphere(grip_force):
    world = World(time_step=0.001)
    model = world.add_urdf("g", gripper_pointing_down(grip_force),
                           joint_positions={f: 0.0366 for f in FINGERS})
    tcp = model.links["gripper_tcp"].pose[0]
    world.add_sdf(SPHERE.format(x=tcp[0], y=tcp[1], z=tcp[2]))
    bulb = world.models["bulb"]
    for _ in range(1500):
        for f in FINGERS:
            model.joints[f].set_effort(-grip_force * 2)   # clamped to the effort limit
        world.step()
    assert world.pop_events() == []
    for f in FINGERS:
        assert model.joints[f].position == pytest.approx(0.03 / math.sin(math.pi / 3), abs=0.001)
        assert abs(model.joints[f].effort) == pytest.approx(grip_force, rel=1e-6)
    drop = math.dist(bulb.pose[0], tcp)
    assert drop < 0.003, "the sphere slipped %.4f m" % drop
