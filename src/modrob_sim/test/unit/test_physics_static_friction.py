"""Tier 1: a held object stays held. ODE's quickStep stops after a fixed number of iterations, so
the friction of a squeezed object never quite reaches what holding it needs; the contacts' anchors
(docs/physics.md, Contacts) take back what it slipped in each step. A cube squeezed between two
light fingers (fixtures/physics/pinch_hand.urdf) with gravity tilted 45 degrees in the pads' plane:
without the anchors it crept 2.7-2.8 mm along the pads and turned 1.2 degrees about the squeeze in
10 s on both backends (and out of a franka_description hand's fingers in 10 s). A box on a ramp
steeper than its friction still slides (test_physics_contacts.py)."""
import importlib.util
import math
import os

import pytest

from modrob_sim.physics import World, actuators, backends
from modrob_sim.physics import native as native_mod

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)

needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")
BACKENDS = [False, pytest.param(True, marks=needs_c)]
CUBE = H.robot("cube", H.box_link("cube", 0.1, (0.03, 0.03, 0.03), 1.0))


def squeezed_cube(native, tilt=math.radians(45), squeeze=10.0):
    """The pinch hand squeezing a 3 cm, 0.1 kg cube with ``squeeze`` N per finger, gravity tilted
    by ``tilt`` about the squeeze axis (y)."""
    world = World(gravity=(9.81 * math.sin(tilt), 0.0, -9.81 * math.cos(tilt)), native=native)
    hand = world.add_urdf("hand", H.fixture("pinch_hand.urdf"),
                          joint_positions={"left_slide": 0.0155, "right_slide": 0.0155})
    cube = world.add_urdf("cube", CUBE, pose=((0.0, 0.0, 0.26), (0.0, 0.0, 0.0, 1.0)))
    for name in ("left_slide", "right_slide"):
        a = world.add_actuator(hand.joints[name], actuators.EFFORT)
        a.command = -squeeze
    return world, hand, cube


def angle_between(q1, q2):
    d = abs(sum(a * b for a, b in zip(q1, q2)))
    return 2.0 * math.acos(min(1.0, d))


@pytest.mark.parametrize("native", BACKENDS)
def test_a_cube_squeezed_between_light_fingers_stays_where_it_was_gripped(native):
    world, hand, cube = squeezed_cube(native)
    world.step(500)                              # gripped: the fingers have closed on it
    (p0, q0) = cube.pose
    world.step(10000)                            # 10 s held
    (p1, q1) = cube.pose
    along_pads = math.hypot(p1[0] - p0[0], p1[2] - p0[2])
    assert along_pads < 0.0003, "the cube crept %.2f mm along the pads" % (1000 * along_pads)
    assert angle_between(q0, q1) < math.radians(0.1), "the cube turned %.2f degrees" % math.degrees(
        angle_between(q0, q1))
    assert world.pop_events() == []


@pytest.mark.parametrize("native", BACKENDS)
def test_a_cube_squeezed_too_lightly_slides_out(native):
    # 0.2 N per finger, mu 1: 0.4 N of friction against 0.69 N of weight along the pads
    world, hand, cube = squeezed_cube(native, squeeze=0.2)
    world.step(500)
    p0 = cube.pose[0]
    world.step(500)
    p1 = cube.pose[0]
    # a = g sin(45) - 0.4 N / 0.1 kg = 2.9 m/s^2: 0.36 m in 0.5 s unhindered (it leaves the pads)
    assert p1[0] - p0[0] > 0.05


def spun_box(native, twist):
    """A 6 x 4 x 2 cm, 0.2 kg box (mu 0.1) on the floor, set moving with ``twist``, until it stops:
    its displacement and the angle it turned."""
    world = World(native=native)
    world.add_urdf("ground", H.fixture("ground_box.urdf"))
    box = world.add_urdf("box", H.robot("box", H.box_link("box", 0.2, (0.06, 0.04, 0.02), 0.1)),
                         pose=((0.0, 0.0, 0.0105), (0.0, 0.0, 0.0, 1.0)))
    world.step(300)
    (p0, q0) = box.pose
    box.set_twist(twist)
    world.step(600)
    (p1, q1) = box.pose
    return (p1[0] - p0[0], p1[1] - p0[1]), angle_between(q0, q1)


@pytest.mark.parametrize("native", BACKENDS)
@pytest.mark.parametrize("twist", [((0.0, 0.0, 0.0), (0.0, 0.0, 3.0)), ((0.2, 0.0, 0.0), (0.0, 0.0, 2.0))])
def test_a_contact_with_a_static_side_is_not_anchored(native, twist, monkeypatch):
    # A box spinning, or spinning as it slides, on the static floor comes to rest as ODE's own
    # friction brings it there (anchors switched off on the pure backend): only contacts between
    # two moving bodies are anchored. With the floor's contacts anchored, the spinning box turned
    # 0.029 rad instead of 0.044 and the sliding one 0.165 instead of 0.037 (as a TurtleBot3
    # burger's box caster, dragged along, turned the robot at the start of a straight drive).
    moved, turned = spun_box(native, twist)
    monkeypatch.setattr(backends.PureBackend, "_anchor", lambda *args: None)
    free_moved, free_turned = spun_box(False, twist)
    assert turned == pytest.approx(free_turned, rel=1e-9)
    assert math.hypot(moved[0] - free_moved[0], moved[1] - free_moved[1]) < 1e-9
