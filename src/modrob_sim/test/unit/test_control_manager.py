"""controller_manager semantics: load / switch / stop / unload / list, conflicts, errors."""
import pytest

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import BEST_EFFORT, STRICT, ControllerManager
from modrob_sim.ros_control.testing import IntegratorJoint, simple_transmissions

POS = {"type": "effort_controllers/JointPositionController", "joint": "j1", "pid": {"p": 10.0}}
EFF = {"type": "effort_controllers/JointEffortController", "joint": "j1"}
JSC = {"type": "joint_state_controller/JointStateController", "publish_rate": 50}


@pytest.fixture
def mgr():
    joints = {n: IntegratorJoint(name=n, effort_limit=5.0) for n in ("j1", "j2")}
    hw = RobotHWSim(joints, simple_transmissions({"j1": "EffortJointInterface",
                                                  "j2": "EffortJointInterface"}))
    return ControllerManager(hw, "/robot")


def states(mgr):
    return {c.name: c.state for c in mgr.list_controllers()}


def test_load_start_stop_unload_round_trip(mgr):
    mgr.load("pos", POS)
    mgr.load("jsc", JSC)
    assert states(mgr) == {"pos": "initialized", "jsc": "initialized"}
    assert mgr.switch(["pos", "jsc"], [], STRICT) == (True, "")
    assert states(mgr) == {"pos": "running", "jsc": "running"}
    with pytest.raises(ControllerError, match="still running"):
        mgr.unload("pos")
    assert mgr.switch([], ["pos"], STRICT)[0]
    assert states(mgr)["pos"] == "stopped"
    mgr.unload("pos")
    assert list(states(mgr)) == ["jsc"]
    assert mgr.get("jsc").claimed_resources == [("hardware_interface::JointStateInterface", [])]


def test_strict_fails_on_unknown_or_not_running_best_effort_skips(mgr):
    mgr.load("pos", POS)
    ok, msg = mgr.switch(["pos", "ghost"], [], STRICT)
    assert not ok and "ghost" in msg and states(mgr)["pos"] == "initialized"
    ok, msg = mgr.switch(["pos", "ghost"], ["other"], BEST_EFFORT)
    assert ok and states(mgr)["pos"] == "running"
    ok, msg = mgr.switch(["pos"], [], STRICT)
    assert not ok and "already running" in msg
    ok, msg = mgr.switch([], ["jsc"], STRICT)
    assert not ok


def test_strictness_zero_defaults_to_best_effort_with_a_warning(mgr):
    logs = []
    mgr.log = lambda level, msg: logs.append((level, msg))
    mgr.load("pos", POS)
    assert mgr.switch(["pos", "ghost"], [], 0)[0]
    assert logs[0][0] == "warn" and "BEST_EFFORT" in logs[0][1]


def test_resource_conflict_is_refused_and_a_swap_in_one_switch_works(mgr):
    mgr.load("pos", POS)
    mgr.load("eff", EFF)
    assert mgr.switch(["pos"], [], STRICT)[0]
    ok, msg = mgr.switch(["eff"], [], BEST_EFFORT)
    assert not ok and "Resource conflict" in msg and "'j1'" in msg
    assert states(mgr) == {"pos": "running", "eff": "initialized"}
    assert mgr.switch(["eff"], ["pos"], STRICT)[0]
    assert states(mgr) == {"pos": "stopped", "eff": "running"}
    assert mgr.get("eff").claimed_resources == [("hardware_interface::EffortJointInterface", ["j1"])]


def test_restart_in_one_switch(mgr):
    mgr.load("pos", POS)
    mgr.switch(["pos"], [], STRICT)
    assert mgr.switch(["pos"], ["pos"], STRICT)[0]
    assert states(mgr)["pos"] == "running"


def test_load_errors_say_what_to_do(mgr):
    with pytest.raises(ControllerError) as err:
        mgr.load("arm", None)
    assert "type was not specified" in str(err.value) and "'/robot/arm'" in str(err.value)
    with pytest.raises(ControllerError) as err:
        mgr.load("arm", {"type": "effort_controllers/JointPositionControler", "joint": "j1"})
    text = str(err.value)
    assert "'effort_controllers/JointPositionControler'" in text and "does not exist" in text
    assert "effort_controllers/JointPositionController" in text
    assert "joint_state_controller/JointStateController" in text
    mgr.load("pos", POS)
    with pytest.raises(ControllerError, match="already loaded"):
        mgr.load("pos", POS)
    with pytest.raises(ControllerError, match="no controller with this name"):
        mgr.unload("nothing")


def test_update_runs_only_running_controllers(mgr):
    c = mgr.load("eff", EFF)
    c.set_command(2.0)
    mgr.update(0.0, 0.001)
    assert mgr.hw.joints["j1"].sim._effort == 0.0
    mgr.switch(["eff"], [], STRICT)
    c.set_command(2.0)
    mgr.update(0.001, 0.001)
    assert mgr.hw.joints["j1"].sim._effort == 2.0


def test_stop_all(mgr):
    mgr.load("pos", POS)
    mgr.load("jsc", JSC)
    mgr.switch(["pos", "jsc"], [], STRICT)
    assert sorted(mgr.stop_all()) == ["jsc", "pos"]
    assert set(states(mgr).values()) == {"stopped"}
