"""Tier 1: roboticsgroup's mimic joint plugin through the node's plugin host on a real World, on
both physics backends: the follower keeps within 1 mrad of multiplier * master + offset while the
master moves (the World's coupling, natively between hooks), with <hasPID> its PID holds it there,
bad configuration names the joint, and unloading gives the joint back."""
import importlib.util
import os

import pytest

from modrob_sim.arm_plugins import mimic_joint
from modrob_sim.physics.actuators import POSITION_PID, PidGains

_FIXTURES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures")
_spec = importlib.util.spec_from_file_location("plugin_rig", os.path.join(_FIXTURES, "plugin_rig.py"))
plugin_rig = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(plugin_rig)
close_worlds = plugin_rig.close_worlds          # (autouse: the Worlds of a test closed after it)
BACKENDS = [None, False]


def fingers(native, plugin_extra="", replace=None):
    edits = [("<maxEffort>5.0</maxEffort>", "<maxEffort>5.0</maxEffort>" + plugin_extra)]
    edits += list(replace or ())
    w, host, m, loaded = plugin_rig.plugin_world(native, "force/mimic_fingers.urdf", "fingers", edits)
    drive = w.add_actuator(m.joints["right_finger_joint"], POSITION_PID, gains=PidGains(1.0, 0.0, 0.01))
    return w, host, m, loaded, drive


def follow_error(m):
    q = m.joints["right_finger_joint"].position
    return abs(m.joints["left_finger_joint"].position - (-q + 0.05))


@pytest.mark.parametrize("native", BACKENDS)
def test_the_mimic_joint_follows_within_a_milliradian(native):
    w, host, m, loaded, drive = fingers(native)
    assert len(loaded) == 1 and isinstance(loaded[0], mimic_joint.MimicJointPlugin)
    worst = 0.0
    # a gripper's pace, 0.3 rad/s: closes 0 -> 0.3 rad in 1 s, opens to -0.3 in 2 s. The coupling
    # lags 2 v dt behind a moving master (0.6 mrad here), nothing at rest
    for k in range(300):
        drive.command = 0.003 * k if k <= 100 else 0.3 - 0.003 * (k - 100)
        w.step(10)
        if k >= 1:
            worst = max(worst, follow_error(m))
    assert m.joints["right_finger_joint"].position < -0.25      # the master did move
    assert worst < 1e-3
    w.step(300)
    assert follow_error(m) < 1e-5
    if w.native:   # the coupling is the World's: every step in C, no Python hook
        assert w.native_steps >= 0.95 * w.iterations, "%d of %d" % (w.native_steps, w.iterations)


@pytest.mark.parametrize("native", BACKENDS)
def test_with_has_pid_the_gains_hold_it(native, monkeypatch):
    seen = []

    def gains(self, ns):
        seen.append(ns)
        return PidGains(5.0, 20.0, 0.02, 0.5, -0.5)
    monkeypatch.setattr(mimic_joint.MimicJointPlugin, "read_gains", gains)
    w, host, m, loaded, drive = fingers(native, "<hasPID/>")
    assert seen == ["/gazebo_ros_control/pid_gains/left_finger_joint"]
    drive.command = 0.3
    w.step(1500)
    assert abs(m.joints["right_finger_joint"].position - 0.3) < 0.01
    assert follow_error(m) < 1e-3
    # the effort is the PID's, clamped to maxEffort
    assert abs(m.joints["left_finger_joint"].effort) <= 5.0


def test_a_named_pid_namespace_is_relative_to_the_robot_namespace(monkeypatch):
    seen = []
    monkeypatch.setattr(mimic_joint.MimicJointPlugin, "read_gains",
                        lambda self, ns: seen.append(ns) or PidGains(1.0))
    fingers(None, "<hasPID>my_gains/left</hasPID><robotNamespace>arm</robotNamespace>")
    assert seen == ["/arm/my_gains/left"]


def test_a_missing_joint_is_named_and_the_model_spawns(caplog):
    w, host, m, loaded, drive = fingers(None, replace=[("<mimicJoint>left_finger_joint",
                                                       "<mimicJoint>left_fnger_joint")])
    assert loaded == []
    assert "no joint named 'left_fnger_joint'" in caplog.text and "left_finger_joint" in caplog.text


def test_the_upatras_successor_is_the_same_plugin():
    upatras = ("libroboticsgroup_gazebo_mimic_joint_plugin.so",
               "libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so")
    w, host, m, loaded, drive = fingers(None, replace=[upatras])
    assert len(loaded) == 1 and m.joints["left_finger_joint"].mimic == ("right_finger_joint", -1.0, 0.05)


def test_unloading_releases_the_joint():
    w, host, m, loaded, drive = fingers(None)
    assert m.joints["left_finger_joint"].mimic == ("right_finger_joint", -1.0, 0.05)
    host.unload("fingers")
    assert m.joints["left_finger_joint"].mimic is None
