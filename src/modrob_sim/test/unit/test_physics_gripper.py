"""Tier 1: Gazebo's <gripper> grasp check welds an object held from two sides to the palm and lets
it go once the contact is gone (physics/gripper.py)."""
import importlib.util
import os

import pytest

from modrob_sim.errors import ModelError
from modrob_sim.physics import World
from modrob_sim.physics.gripper import UPDATE_PERIOD

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)


def hand_and_box():
    world = World(time_step=0.001)
    hand = world.add_urdf("hand", H.fixture("gripper_hand.urdf"))
    box = world.add_urdf("box", H.robot("box", H.box_link("box", 0.1, (0.1, 0.1, 0.1))),
                         pose=((0, 0, 0.9), (0, 0, 0, 1)))
    squeeze = {"f": 20.0}

    def drive(t, dt):
        if "hand" not in world.models:
            return
        hand.joints["left"].set_effort(-squeeze["f"])
        hand.joints["right"].set_effort(squeeze["f"])
    world.add_step_hook(before=drive)
    return world, hand, box, squeeze


def seconds(world, s):
    world.step(int(round(s / world.time_step)))


def test_an_object_held_from_two_sides_is_attached_then_released_after_the_contact_goes():
    world, hand, box, squeeze = hand_and_box()
    g = hand._grippers[0]
    seconds(world, 2 * UPDATE_PERIOD)
    assert g.attached is None  # not before attach_steps updates and a still pose
    seconds(world, 14 * UPDATE_PERIOD)
    assert g.attached is not None and g.attached[0] is box and g.attached[1] == "box"
    z_held = box.pose[0][2]
    squeeze["f"] = -20.0  # open: the fingers leave, the weld holds the box
    seconds(world, 1.0)
    assert hand.joints["left"].position > 0.0 > hand.joints["right"].position  # fingers wide open
    assert abs(box.pose[0][2] - z_held) < 0.002
    seconds(world, 4 * UPDATE_PERIOD)  # more than detach_steps updates without contact
    assert g.attached is None
    seconds(world, 0.5)
    assert box.pose[0][2] < z_held - 0.5  # falls


def test_deleting_the_held_object_or_the_hand_lets_go_cleanly():
    world, hand, box, squeeze = hand_and_box()
    seconds(world, 16 * UPDATE_PERIOD)
    g = hand._grippers[0]
    assert g.attached is not None
    world.remove_model("box")
    world.step(5)
    assert g.attached is None
    world.remove_model("hand")
    world.step(5)
    assert g._hook is None


def test_a_gripper_naming_an_unknown_link_is_refused():
    xml = H.fixture("gripper_hand.urdf").replace("<palm_link>palm</palm_link>", "<palm_link>paw</palm_link>")
    world = World()
    with pytest.raises(ModelError, match="<gripper name='grasp'>: no link named 'paw'"):
        world.add_urdf("hand", xml)
    assert not world.models


def test_sdf_gripper_element_is_read():
    sdf = ("<sdf version='1.6'><model name='m'><link name='palm'/><link name='f'/>"
           "<gripper name='g'><grasp_check><attach_steps>3</attach_steps></grasp_check>"
           "<gripper_link>f</gripper_link><palm_link>palm</palm_link></gripper></model></sdf>")
    m = World().add_sdf(sdf)[0]
    d = m._grippers[0].desc
    assert (d.attach_steps, d.detach_steps, d.min_contact_count, d.gripper_links) == (3, 40, 2, ("f",))


def test_dropping_the_world_while_an_object_is_held_exits_cleanly():
    """The weld joint must go before the ODE world (it segfaulted when freed after it)."""
    import subprocess
    import sys
    code = ("import importlib.util, gc\n"
            "spec = importlib.util.spec_from_file_location('t', %r)\n"
            "t = importlib.util.module_from_spec(spec); spec.loader.exec_module(t)\n"
            "world, hand, box, sq = t.hand_and_box()\n"
            "t.seconds(world, 16 * t.UPDATE_PERIOD)\n"
            "g = hand._grippers[0]\n"
            "assert g.attached is not None\n"
            "del world, sq; gc.collect()\n"
            "del hand, box, g; gc.collect()\n"
            "print('clean')\n" % os.path.abspath(__file__))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.strip() == "clean"
    assert "Exception ignored" not in r.stderr
