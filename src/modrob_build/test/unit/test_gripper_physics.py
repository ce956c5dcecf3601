"""The gripper macro (urdf/gripper.xacro): expands with xacro, passes check_urdf, and in the
modrob ODE core (no ROS) holds a 60 mm, 50 g sphere and the bulb's 60 mm glass cylinder (soft
contact, kp 1e5) lying across the fingers (axis along the gripper's x: the side grasp) and along
the approach (axis along z: the axial grasp) with 3, 7 and 10 N, finger 2 following finger 1 (its
mimic), the flat pads resting on the object (q = its radius)."""
import math
import subprocess
import xml.etree.ElementTree as ET

import pytest

from modrob_build.gains import finger_gains, finger_load
from modrob_build.gripper import attach_gripper
from modrob_sim.physics import World

SPHERE = """<?xml version="1.0"?>
<sdf version="1.6"><model name="bulb"><pose>{x} {y} {z} 0 0 0</pose><link name="glass">
  <inertial><mass>0.05</mass><inertia><ixx>1.8e-5</ixx><iyy>1.8e-5</iyy><izz>1.8e-5</izz>
    <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
  <collision name="glass"><geometry><sphere><radius>0.03</radius></sphere></geometry>
    <surface><friction><ode><mu>1.0</mu><mu2>1.0</mu2></ode></friction></surface></collision>
</link></model></sdf>"""
CYLINDER = """<?xml version="1.0"?>
<sdf version="1.6"><model name="bulb"><pose>{x} {y} {z} 0 0 0</pose><link name="glass">
  <inertial><mass>0.05</mass><inertia><ixx>1.7e-5</ixx><iyy>4.6e-5</iyy><izz>4.6e-5</izz>
    <ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
  <collision name="glass"><pose>0 0 0 0 1.570796 0</pose>
    <geometry><cylinder><radius>0.03</radius><length>0.065</length></cylinder></geometry>
    <surface><friction><ode><mu>1.0</mu><mu2>1.0</mu2></ode></friction>
      <contact><ode><kp>100000</kp><kd>1</kd><min_depth>0.001</min_depth></ode></contact></surface>
  </collision>
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
    assert {t.find("joint").get("name") for t in root.findall("transmission")} == {FINGERS[0]}
    mimic = prismatic[1].find("mimic")
    assert mimic.get("joint") == FINGERS[0]
    assert (float(mimic.get("multiplier")), float(mimic.get("offset"))) == (1.0, 0.0)


@pytest.mark.parametrize("shape", ["sphere", "cylinder along x", "cylinder along z"])
@pytest.mark.parametrize("grip_force", [3.0, 7.0, 10.0])
def test_holds_a_bulb(grip_force, shape):
    """The gripper points down; the object is placed at gripper_tcp and finger 1 is commanded to
    close past it. 10 N is above the tested-stable 7 N: the pads must still not creep through."""
    world = World(time_step=0.001)
    model = world.add_urdf("g", gripper_pointing_down(grip_force),
                           joint_positions={FINGERS[0]: 0.031})   # 1 mm from the object
    tcp = model.links["gripper_tcp"].pose[0]
    sdf = {"sphere": SPHERE, "cylinder along x": CYLINDER,
           "cylinder along z": CYLINDER.replace("0 0 0 0 1.570796 0", "0 0 0 0 0 0")}[shape]
    world.add_sdf(sdf.format(x=tcp[0], y=tcp[1], z=tcp[2]))
    bulb = world.models["bulb"]
    leader, follower = model.joints[FINGERS[0]], model.joints[FINGERS[1]]
    assert follower.position == pytest.approx(0.031, abs=1e-9)
    gains = finger_gains(finger_load(FINGERS[0], grip_force))
    for i in range(1500):
        # as the controller with the scenario's close: the target ramps to 0 over 0.3 s, so the
        # PD saturates at the effort limit (the grip force) once the fingers touch
        target = 0.031 * max(0.0, 1.0 - i / 300.0)
        leader.set_effort(gains.p * (target - leader.position) - gains.d * leader.velocity)
        world.step()
        if i == 300:
            gripped = bulb.pose[0]
    assert world.pop_events() == []
    for j in (leader, follower):
        # flat pads: q = the radius, less up to minDepth (1 mm of penetration is left uncorrected)
        assert 0.0285 < j.position < 0.0305
    assert abs(leader.effort) == pytest.approx(grip_force, rel=1e-6)
    drop = math.dist(bulb.pose[0], tcp)   # mostly the fall while the fingers close
    assert drop < 0.005, "the %s is %.4f m from the grasp centre" % (shape, drop)
    slip = math.dist(bulb.pose[0], gripped)
    assert slip < 0.0005, "the %s slipped %.4f m in the closed gripper" % (shape, slip)
