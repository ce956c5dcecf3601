"""Tier 1: roboticsgroup's mimic joint plugin through the node's plugin host on a real World, on
both physics backends: the follower keeps within 1 mrad of multiplier * master + offset while the
master moves (the World's coupling, natively between hooks), with <hasPID> its PID holds it there
(the World's FOLLOW_PID actuator: the same steps as the every-step Python PID it replaced, without
a stop for Python at every step; reset and unloading), bad configuration names the joint, and
unloading gives the joint back."""
import importlib.util
import os

import pytest

from modrob_sim.arm_plugins import mimic_joint
from modrob_sim.physics import World
from modrob_sim.physics import native as native_mod
from modrob_sim.physics.actuators import EFFORT, FOLLOW_PID, POSITION_PID, Pid, PidGains

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


@pytest.mark.parametrize("has_pid", ["", "<hasPID/>"])
def test_a_joint_that_mimics_itself_is_named_and_the_model_spawns(caplog, monkeypatch, has_pid):
    monkeypatch.setattr(mimic_joint.MimicJointPlugin, "read_gains", lambda self, ns: PidGains(1.0))
    w, host, m, loaded, drive = fingers(None, has_pid, replace=[("<mimicJoint>left_finger_joint",
                                                                 "<mimicJoint>right_finger_joint")])
    assert loaded == []
    assert "are both 'right_finger_joint': a joint cannot mimic itself" in caplog.text
    assert m.joints["right_finger_joint"].actuator is drive


def test_a_negative_max_effort_is_named_and_its_size_used(caplog, monkeypatch):
    monkeypatch.setattr(mimic_joint.MimicJointPlugin, "read_gains", lambda self, ns: PidGains(50.0))
    negative = ("<maxEffort>5.0</maxEffort>", "<maxEffort>-5.0</maxEffort>")
    w, host, m, loaded, drive = fingers(None, "<hasPID/>", replace=[negative])
    assert len(loaded) == 1 and loaded[0].max_effort == 5.0
    assert "<maxEffort> -5.0 must be >= 0: using 5" in caplog.text
    drive.command = 0.3
    w.step(200)
    assert 0.0 < abs(m.joints["left_finger_joint"].effort) <= 5.0      # it pushes, within 5 N


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


GAINS = PidGains(5.0, 20.0, 0.02, 0.5, -0.5)
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


@pytest.fixture
def pid_gains(monkeypatch):
    seen = []
    monkeypatch.setattr(mimic_joint.MimicJointPlugin, "read_gains", lambda self, ns: seen.append(ns) or GAINS)
    return seen


def closing_and_opening(w, drive, m, steps=3000):
    """The master closes to 0.3 rad and opens to -0.3 rad (a set-point ramp every 10 steps); both
    fingers' positions and the follower's effort every 10 steps."""
    seen = []
    for k in range(steps // 10):
        drive.command = 0.006 * k if k <= 50 else max(-0.3, 0.3 - 0.006 * (k - 50))
        w.step(10)
        seen.append(tuple((j.position, j.velocity, j.effort) for j in m.joints.values()
                          if j.name in ("right_finger_joint", "left_finger_joint")))
    return seen


class OldRule(object):
    """The plugin's <hasPID> rule as it ran before, at every step in Python (test-only copy):
    clamp(pid(multiplier * master + offset - q), +-maxEffort) unless |error| < sensitiveness."""

    def __init__(self, master, joint, multiplier, offset, sensitiveness, max_effort, gains):
        self.master, self.joint, self.pid = master, joint, Pid(gains)
        self.multiplier, self.offset = multiplier, offset
        self.sensitiveness, self.max_effort = sensitiveness, max_effort

    def before_step(self, t, dt):
        error = self.multiplier * self.master.position + self.offset - self.joint.position
        if abs(error) < self.sensitiveness:
            return
        effort = self.pid.compute(error, dt)
        self.joint.set_effort(max(-self.max_effort, min(self.max_effort, effort)))


@pytest.mark.parametrize("native", BACKENDS)
def test_with_has_pid_the_steps_are_those_of_the_every_step_python_pid(native, pid_gains):
    w, host, m, loaded, drive = fingers(native, "<hasPID/><sensitiveness>0.002</sensitiveness>")
    assert m.joints["left_finger_joint"].actuator.kind == FOLLOW_PID
    ours = closing_and_opening(w, drive, m)
    # the same fingers without the plugin, the old rule in a step hook
    w0 = World(native=native)
    plugin_rig.WORLDS.append(w0)
    m0 = w0.add_urdf("fingers", plugin_rig.fixture_text("force/mimic_fingers.urdf"))
    drive0 = w0.add_actuator(m0.joints["right_finger_joint"], POSITION_PID, gains=PidGains(1.0, 0.0, 0.01))
    old = OldRule(m0.joints["right_finger_joint"], m0.joints["left_finger_joint"], multiplier=-1.0,
                  offset=0.05, sensitiveness=0.002, max_effort=5.0, gains=GAINS)
    w0.add_step_hook(old.before_step)
    theirs = closing_and_opening(w0, drive0, m0)
    assert max(abs(a[0][0]) for a in ours) > 0.25, "the fingers should have moved"
    worst = max(abs(x - y) for a, b in zip(ours, theirs) for ja, jb in zip(a, b) for x, y in zip(ja, jb))
    assert len(ours) == len(theirs) == 300 and worst <= 1e-12


@needs_c
def test_with_has_pid_the_world_does_not_stop_for_python_at_every_step(pid_gains):
    w, host, m, loaded, drive = fingers(None, "<hasPID/>")
    drive.command = 0.3
    w.step(1000)
    assert w.stops <= 5, "%d stops in 1000 steps" % w.stops
    # a follower that has another actuator already keeps it: the PID's effort goes on top of it
    # from Python, at every step (as Gazebo adds the two efforts)
    host.unload("fingers")
    w.add_actuator(m.joints["left_finger_joint"], EFFORT)
    plugin = host.load(m)[0]
    assert plugin.pid is not None and plugin.actuator is None
    stops = w.stops
    w.step(1000)
    assert w.stops - stops >= 1000


@pytest.mark.parametrize("native", BACKENDS)
def test_reset_zeroes_the_pid_and_unloading_frees_the_joint(native, pid_gains):
    w, host, m, loaded, drive = fingers(native, "<hasPID/>")
    left = m.joints["left_finger_joint"]
    a = left.actuator
    drive.command = 0.3
    w.step(200)
    assert a.pid_state() != (0.0,) * 5
    w.reset_world()
    host.reset(False)
    assert a.pid_state() == (0.0,) * 5
    host.unload("fingers")
    assert left.actuator is None and a not in w.actuators
    # a model removed: its actuators go with it, the plugin's shutdown after that is quiet
    w2, host2, m2, loaded2, drive2 = fingers(native, "<hasPID/>")
    w2.remove_model("fingers")
    host2.unload("fingers")
    assert w2.actuators == ()


@pytest.mark.parametrize("native", BACKENDS)
def test_gains_from_the_reconfigure_server_reach_the_actuator_at_the_next_step(native, pid_gains):
    w, host, m, loaded, drive = fingers(native, "<hasPID/>")
    plugin = loaded[0]
    assert plugin.reconfigure is None           # no ROS node in this test: read_gains is replaced
    left = m.joints["left_finger_joint"]
    drive.command = 0.3
    w.step(500)
    stops = w.stops
    new = PidGains(0.0, 0.0, 0.0)
    plugin.tuned.set_gains(new)                 # what the server's callback does, then it wakes
    plugin.context.wake()
    w.step(1)
    assert left.actuator.gains.as_dict() == new.as_dict() and w.stops == stops + 1
    w.step(300)
    if w.native:
        assert w.stops <= stops + 2, "no stop for Python once the gains are handed over"
    assert left.actuator.last.output == 0.0     # the PID gives nothing with zero gains


def test_a_controller_that_wants_the_followers_actuator_later_is_refused_by_name(pid_gains):
    from modrob_sim.errors import InputError
    from modrob_sim.ros_control.hardware import JointResource
    from modrob_sim.ros_control.transmissions import EFFORT as EFFORT_INTERFACE
    w, host, m, loaded, drive = fingers(None, "<hasPID/>")
    res = JointResource(m.joints["left_finger_joint"], EFFORT_INTERFACE, world=w)
    with pytest.raises(InputError, match="left_finger_joint.*already has an actuator.*FOLLOW_PID"):
        res.actuate(POSITION_PID)
    assert m.joints["left_finger_joint"].actuator is loaded[0].actuator
