"""How hard the gripper (modrob_description/urdf/gripper.xacro) can be shaken with the Bulbs and Slides
bulb in it, in the ODE core alone (no ROS): the gripper points down from a cart on a rail, closes on
the real bulb model (glass cylinder across the pads, as the scenario grasps it), then the rail moves
sinusoidally at 5 Hz with a given peak acceleration along one of the gripper's axes.

Across the closing axis (gripper x and z) friction holds the bulb: mu 2 F = 6 N against 0.05 kg,
and along z the tilted normals at the pad rows' edges (docs/modules.md), since friction alone
would let go at 76 m/s^2: the bulb's centre of mass is 14 mm off the grasp centre.
Along the closing axis (gripper y) friction does not help: finger 2 is driven to finger 1's position
against the gripper base (the mimic coupling), so a load towards finger 1 is carried by finger 1's
grip force F alone, which must also accelerate finger 1 itself: the pads let go above
F / (m_bulb + m_finger) = 3 / (0.05 + 0.05) = 30 m/s^2 at 3 N (70 at 7 N). The arm reaches that along
the closing axis when joint1 and joint5 swing together (docs/bulbs_and_slides.md, grasp robustness);
a rack-and-pinion coupling would share the load between the fingers (F_total / m_bulb)."""
import math
import os
import xml.etree.ElementTree as ET

import pytest

from modrob_build.gains import finger_gains, finger_load
from modrob_build.gripper import attach_gripper
from modrob_sim.physics import World
from modrob_sim.physics.transforms import transform_point

BULB_SDF = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "modrob_description",
                        "models", "bulb", "model.sdf")
GLASS_CENTRE = 0.0325      # m along the bulb's axis (x) from its model frame (generate_bulbs_and_slides.py)
FINGERS = ("gripper_finger1_joint", "gripper_finger2_joint")
AXES = {"x": (1, 0, 0), "y (closing)": (0, 1, 0), "z (approach)": (0, 0, 1)}   # the gripper's, in the world


def gripper_on_rail(grip_force, axis):
    """The gripper pointing down (its x = world x, y = -world y, z = -world z) on a cart that slides
    along ``axis`` (world frame)."""
    root = ET.fromstring(
        '<robot name="g"><link name="world"/><link name="cart"><inertial><mass value="1.0"/>'
        '<inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="rail" type="prismatic"><parent link="world"/><child link="cart"/>'
        '<origin xyz="0 0 0.5" rpy="0 0 0"/><axis xyz="%g %g %g"/>'
        '<limit lower="-1" upper="1" effort="10000" velocity="100"/></joint>'
        '<link name="ee"><inertial><mass value="0.1"/>'
        '<inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="fix" type="fixed"><parent link="cart"/><child link="ee"/>'
        '<origin xyz="0 0 0" rpy="3.14159265 0 0"/></joint></robot>' % tuple(axis))
    return attach_gripper(root, "", "ee", grip_force)


def shake(grip_force, axis, peak_acceleration, freq=5.0, seconds=2.0):
    """Largest distance [m] of the bulb's glass centre from the grasp centre while the rail shakes,
    and the blow-up guard's events."""
    world = World(time_step=0.001)
    model = world.add_urdf("g", gripper_on_rail(grip_force, AXES[axis]),
                           joint_positions={FINGERS[0]: 0.031})     # 1 mm from the glass
    tcp = model.links["gripper_tcp"]
    p = tcp.pose[0]
    with open(BULB_SDF) as f:
        sdf = f.read()
    assert "<model name='bulb'>" in sdf
    world.add_sdf(sdf.replace("<model name='bulb'>", "<model name='bulb'><pose>%.6f %.6f %.6f 0 0 0</pose>"
                              % (p[0] - GLASS_CENTRE, p[1], p[2]), 1))
    glass = world.models["bulb"].links["link"]
    leader, rail = model.joints[FINGERS[0]], model.joints["rail"]
    gains = finger_gains(finger_load(FINGERS[0], grip_force))
    w = 2 * math.pi * freq
    amplitude = peak_acceleration / w ** 2
    close_steps = 600
    worst = 0.0
    for i in range(close_steps + int(seconds * 1000)):
        # the finger controller as the scenario closes: the target ramps past the bulb, the PD
        # saturates at the effort limit (the grip force)
        target = 0.031 * max(0.0, 1.0 - i / 300.0)
        leader.set_effort(gains.p * (target - leader.position) - gains.d * leader.velocity)
        t = (i - close_steps) * 0.001
        v = 0.0
        if t >= 0.0:
            v = min(1.0, t / 0.2) * amplitude * w * math.cos(w * t)   # 0.2 s fade-in
        rail.set_velocity_target(v, 1e4)
        world.step()
        if t >= 0.0:
            centre = transform_point(glass.pose, (GLASS_CENTRE, 0.0, 0.0))
            worst = max(worst, math.dist(centre, tcp.pose[0]))
    return worst, world.pop_events()


@pytest.mark.parametrize("axis", sorted(AXES))
def test_3n_grip_holds_the_bulb_at_25_m_s2_along_every_axis(axis):
    worst, events = shake(3.0, axis, 25.0)
    assert events == []
    assert worst < 0.005, "the bulb moved %.1f mm from the grasp centre" % (1000 * worst)


@pytest.mark.parametrize("axis", ["x", "z (approach)"])
def test_3n_grip_holds_the_bulb_at_90_m_s2_across_the_closing_axis(axis):
    worst, events = shake(3.0, axis, 90.0)
    assert events == []
    assert worst < 0.005, "the bulb moved %.1f mm from the grasp centre" % (1000 * worst)


def test_7n_grip_holds_the_bulb_at_60_m_s2_along_the_closing_axis():
    worst, events = shake(7.0, "y (closing)", 60.0)
    assert events == []
    assert worst < 0.005, "the bulb moved %.1f mm from the grasp centre" % (1000 * worst)


@pytest.mark.xfail(strict=True, reason="known limit: finger 2 is servoed to finger 1 against the gripper "
                   "base, so 3 N lets go above 3 / (m_bulb + m_finger) = 30 m/s^2 along the closing axis; "
                   "a two-way (rack-and-pinion) coupling would hold this")
def test_3n_grip_holds_the_bulb_at_45_m_s2_along_the_closing_axis():
    worst, events = shake(3.0, "y (closing)", 45.0)
    assert worst < 0.005, "the bulb moved %.1f mm from the grasp centre" % (1000 * worst)
