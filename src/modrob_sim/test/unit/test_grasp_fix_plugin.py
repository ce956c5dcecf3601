"""Tier 1: gazebo-pkgs' grasp fix through the node's plugin host on a real World, on both physics
backends: a can squeezed between two fingers is attached to the palm after the grip count passes
its threshold and lifted with it (its own friction could not), released when the fingers open and
falls back; collisions off while held when asked; bad configuration is named."""
import importlib.util
import os

import pytest

from modrob_sim.arm_plugins import grasp_fix
from modrob_sim.physics.actuators import EFFORT, POSITION_PID, PidGains

_FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
_spec = importlib.util.spec_from_file_location("plugin_rig", os.path.join(_FIXTURES, "plugin_rig.py"))
plugin_rig = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(plugin_rig)
close_worlds = plugin_rig.close_worlds          # (autouse: the Worlds of a test closed after it)
plugin_world = plugin_rig.plugin_world
BACKENDS = [None, False]


def rig(native, replace=()):
    w, host, m, loaded = plugin_world(native, "force/grasp_rig.urdf", "grasp_rig", replace,
                                      before=[("ground", "physics/ground_box.urdf")])
    can = w.add_urdf("can", plugin_rig.fixture_text("force/can.urdf"))
    lift = w.add_actuator(m.joints["lift"], POSITION_PID, gains=PidGains(3000.0, 2000.0, 120.0, 50.0, -50.0))
    fingers = [w.add_actuator(m.joints[j], EFFORT) for j in ("left_finger_joint", "right_finger_joint")]
    return w, host, m, loaded, can, lift, fingers


def squeeze(fingers, f):
    for a in fingers:
        a.command = f


@pytest.mark.parametrize("native", BACKENDS)
def test_a_squeezed_can_is_attached_lifted_released_and_falls(native):
    w, host, m, loaded, can, lift, fingers = rig(native)
    assert len(loaded) == 1 and isinstance(loaded[0], grasp_fix.GraspFix)
    plugin = loaded[0]
    body = can.links["can"]
    w.step(300)                                   # the can settles, the fingers stay open
    assert plugin.attached == {}
    squeeze(fingers, 5.0)
    w.step(400)                                   # touch, then 3 gripping updates at 20 Hz
    assert plugin.attached == {"rig": ("can", "can")}
    z0, palm0 = body.pose[0][2], m.links["palm"].pose[0][2]
    lift.command = 0.1
    w.step(1000)
    rise = m.links["palm"].pose[0][2] - palm0
    assert rise > 0.09
    assert body.pose[0][2] - z0 == pytest.approx(rise, abs=0.003)     # the can went up with the palm
    squeeze(fingers, -5.0)                        # open: no grip, the count falls, the fingers are off
    w.step(400)
    assert plugin.attached == {}
    w.step(600)
    assert body.pose[0][2] == pytest.approx(0.0, abs=0.003)            # back on the ground
    if w.native:
        # the plugin runs at its 20 Hz update: the C loop makes the steps between
        assert w.native_steps >= 0.9 * w.iterations, "%d of %d" % (w.native_steps, w.iterations)


@pytest.mark.parametrize("native", BACKENDS)
def test_without_the_fix_the_slippery_can_stays_down(native):
    # the same squeeze and lift with a threshold above the count's ceiling (never attaches):
    # friction alone cannot lift it
    never = [("<grip_count_threshold>2", "<grip_count_threshold>9"),
             ("<max_grip_count>4", "<max_grip_count>8")]
    w, host, m, loaded, can, lift, fingers = rig(native, never)
    w.step(300)
    squeeze(fingers, 5.0)
    w.step(400)
    assert loaded[0].attached == {}
    lift.command = 0.1
    w.step(1000)
    assert can.links["can"].pose[0][2] < 0.03


def test_collisions_of_the_held_object_are_off_while_attached():
    w, host, m, loaded, can, lift, fingers = rig(None, [("<disable_collisions_on_attach>false",
                                                         "<disable_collisions_on_attach>true")])
    w.step(300)
    squeeze(fingers, 5.0)
    w.step(400)
    assert loaded[0].attached and can.links["can"].collides is False
    squeeze(fingers, -5.0)
    w.step(600)
    assert loaded[0].attached == {} and can.links["can"].collides is True


def test_the_grip_rule():
    a, b = (1.0, 0.0, 0.0), (-1.0, 0.1, 0.0)
    assert grasp_fix.is_grip([a, b], 1.75)                 # about 174 degrees apart
    assert not grasp_fix.is_grip([a, (0.0, 1.0, 0.0)], 1.75)   # 90 degrees
    assert not grasp_fix.is_grip([a, (-0.2, 0.0, 0.0)], 1.75)  # opposite, but 0.2 < 0.3 of the other
    assert not grasp_fix.is_grip([a], 1.75)


def test_bad_configuration_is_named(caplog):
    *_, loaded, _c, _l, _f = rig(None, [("<palm_link> palm </palm_link>", "<palm_link> plam </palm_link>")])
    assert loaded == []
    assert "palm link 'plam' is not a link of model 'grasp_rig'" in caplog.text
    caplog.clear()
    *_, loaded, _c, _l, _f = rig(None, [("<forces_angle_tolerance>100", "<forces_angle_tolerance>80")])
    assert loaded == [] and "<forces_angle_tolerance> 80" in caplog.text
