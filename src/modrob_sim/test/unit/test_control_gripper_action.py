"""position_/effort_controllers GripperActionController on an integrator finger: reached_goal,
stalled after stall_timeout, preemption, cancel, goals refused, the effort clamp to max_effort."""
import pytest

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import STRICT, ControllerManager
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions

EFFORT_GRIPPER = {"type": "effort_controllers/GripperActionController", "joint": "finger",
                  "goal_tolerance": 0.002, "stall_velocity_threshold": 0.001, "stall_timeout": 0.5,
                  "gains": {"finger": {"p": 200.0, "d": 5.0}}}
POSITION_GRIPPER = {"type": "position_controllers/GripperActionController", "joint": "finger",
                    "goal_tolerance": 0.002, "stall_timeout": 0.5}


def rig(params, iface, stop_at=0.0, pid_gains=None):
    """A finger opening 0 .. 0.04 m; ``stop_at``: where something stops it when it closes."""
    finger = IntegratorJoint(name="finger", type_="prismatic", inertia=0.05, damping=2.0, lower=stop_at,
                             upper=0.04, effort_limit=20.0, velocity_limit=0.1, position=0.04)
    hw = RobotHWSim({"finger": finger}, simple_transmissions({"finger": iface}),
                    Params(pid_gains, "/g/gazebo_ros_control/pid_gains") if pid_gains else None)
    mgr = ControllerManager(hw, "/g")
    c = mgr.load("gripper_controller", params)
    assert mgr.switch(["gripper_controller"], [], STRICT)[0]
    return finger, mgr, c, IntegratorModel([finger])


def run(mgr, model, c, seconds):
    """Run; return the events with the simulated time they came at."""
    out = []

    def grab(t):
        out.extend((t,) + e for e in c.events)
        del c.events[:]
    model.run(mgr, seconds, record=grab)
    return out


def test_effort_gripper_reaches_an_open_goal():
    finger, mgr, c, model = rig(EFFORT_GRIPPER, "EffortJointInterface")
    assert c.submit("g1", 0.01, 10.0, model.time) == (True, "")
    events = run(mgr, model, c, 2.0)
    assert [e[1:3] for e in events] == [("g1", "succeeded")]
    result = events[0][3]
    assert result["reached_goal"] and not result["stalled"]
    assert result["position"] == pytest.approx(0.01, abs=0.002)
    assert abs(result["effort"]) <= 10.0


def test_effort_gripper_on_an_object_stalls_after_stall_timeout():
    finger, mgr, c, model = rig(EFFORT_GRIPPER, "EffortJointInterface", stop_at=0.015)
    assert c.submit("g1", 0.0, 2.0, model.time)[0]
    events = run(mgr, model, c, 3.0)
    assert [e[1:3] for e in events] == [("g1", "aborted")]
    t, _, _, result, text = events[0]
    assert result["stalled"] and not result["reached_goal"]
    assert result["position"] == pytest.approx(0.015)
    assert result["effort"] == pytest.approx(-2.0)       # pressing with max_effort
    assert "stalled" in text and "'finger'" in text
    # the finger reaches the object, then 0.5 s without movement
    assert 0.5 < t < 1.0
    # still pressing after the goal ended, as in ros_controllers
    model.run(mgr, 0.1)
    assert finger.effort == pytest.approx(-2.0)


def test_max_effort_zero_gives_no_effort_and_says_so():
    finger, mgr, c, model = rig(EFFORT_GRIPPER, "EffortJointInterface")
    assert c.submit("g1", 0.0, 0.0, model.time)[0]
    assert any("max_effort 0" in n for n in c.notes(0.0, 0.0))
    events = run(mgr, model, c, 1.0)
    assert events[0][3]["stalled"] and finger.position == pytest.approx(0.04)


def test_position_gripper_with_pid_gains_reaches_and_stalls():
    gains = {"finger": {"p": 300.0, "d": 5.0}}
    finger, mgr, c, model = rig(POSITION_GRIPPER, "PositionJointInterface", stop_at=0.02, pid_gains=gains)
    assert c.claimed_resources == [("hardware_interface::PositionJointInterface", ["finger"])]
    assert c.submit("g1", 0.03, 7.0, model.time)[0]
    events = run(mgr, model, c, 2.0)
    assert events[0][1:3] == ("g1", "succeeded") and events[0][3]["reached_goal"]
    assert events[0][3]["effort"] == 7.0                  # the goal's max_effort, as ros_controllers
    assert c.submit("g2", 0.0, 7.0, model.time)[0]
    events = run(mgr, model, c, 2.0)
    assert events[0][1:3] == ("g2", "aborted") and events[0][3]["stalled"]


def test_a_new_goal_preempts_cancel_holds_stop_preempts():
    finger, mgr, c, model = rig(EFFORT_GRIPPER, "EffortJointInterface")
    assert c.submit("g1", 0.0, 10.0, model.time)[0]
    model.run(mgr, 0.01)
    assert c.submit("g2", 0.039, 0.2, model.time)[0]
    assert [e[:2] for e in c.events] == [("g1", "preempted")]
    del c.events[:]
    model.run(mgr, 0.05)
    assert c.cancel("g2", model.time) and c.events[0][:2] == ("g2", "canceled")
    assert c.target.read()[0] == c.joint.position         # holds where the last update read it
    assert not c.cancel("g2", model.time)
    assert c.submit("g3", 0.0, 10.0, model.time)[0]
    assert mgr.switch([], ["gripper_controller"], STRICT)[0]
    assert c.events[-1][:2] == ("g3", "preempted")


def test_goals_refused_when_not_running_or_not_finite():
    finger, mgr, c, model = rig(EFFORT_GRIPPER, "EffortJointInterface")
    ok, text = c.submit("g1", float("nan"), 1.0, 0.0)
    assert not ok and "command.position nan of joint 'finger' is not finite" in text
    ok, text = c.submit("g1", 0.01, float("inf"), 0.0)
    assert not ok and "command.max_effort" in text
    assert any("outside the limits [0, 0.04]" in n for n in c.notes(0.05, 1.0))
    mgr.switch([], ["gripper_controller"], STRICT)
    ok, text = c.submit("g1", 0.01, 1.0, 0.0)
    assert not ok and "not running" in text


def test_load_errors():
    finger = IntegratorJoint(name="finger", type_="prismatic", lower=0.0, upper=0.04)
    hw = RobotHWSim({"finger": finger}, simple_transmissions({"finger": "EffortJointInterface"}))
    mgr = ControllerManager(hw, "/g")
    with pytest.raises(ControllerError, match="/g/gc/gains is missing"):
        mgr.load("gc", {"type": "effort_controllers/GripperActionController", "joint": "finger"})
    with pytest.raises(ControllerError, match="/g/gc/joint is missing"):
        mgr.load("gc", {"type": "effort_controllers/GripperActionController"})
    with pytest.raises(ControllerError, match="not hardware_interface/PositionJointInterface"):
        mgr.load("gc", {"type": "position_controllers/GripperActionController", "joint": "finger"})
