"""The joint group controllers (position_/velocity_/effort_controllers JointGroup*Controller) on
integrator joints: interfaces, starting values, commands of the wrong length, limits, the PID of
effort_controllers/JointGroupPositionController."""
import pytest

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import STRICT, ControllerManager
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions

JOINTS = ["a", "b", "c"]


def rig(iface):
    joints = [IntegratorJoint(name=n, inertia=0.05, damping=0.1, lower=-1.0, upper=1.0, effort_limit=10.0,
                              velocity_limit=2.0, position=0.1 * k) for k, n in enumerate(JOINTS)]
    hw = RobotHWSim({j.name: j for j in joints}, simple_transmissions({n: iface for n in JOINTS}))
    return joints, ControllerManager(hw, "/arm"), IntegratorModel(joints)


def start(mgr, type_, **extra):
    params = {"type": type_, "joints": JOINTS}
    params.update(extra)
    c = mgr.load("group", params)
    ok, msg = mgr.switch(["group"], [], STRICT)
    assert ok, msg
    return c


@pytest.mark.parametrize("type_, iface", [
    ("position_controllers/JointGroupPositionController", "PositionJointInterface"),
    ("velocity_controllers/JointGroupVelocityController", "VelocityJointInterface"),
    ("effort_controllers/JointGroupEffortController", "EffortJointInterface"),
])
def test_each_type_claims_its_interface_and_starts_as_ros_controllers(type_, iface):
    joints, mgr, model = rig(iface)
    c = start(mgr, type_)
    assert c.claimed_resources == [("hardware_interface::" + iface, JOINTS)]
    expected = [0.0, 0.1, 0.2] if "Position" in iface else [0.0, 0.0, 0.0]
    assert c.command.read() == pytest.approx(expected)


def test_position_group_moves_every_joint_and_clamps_to_the_limits():
    joints, mgr, model = rig("PositionJointInterface")
    c = start(mgr, "position_controllers/JointGroupPositionController")
    res = c.set_command([0.5, -0.3, 1.7])
    assert res.accepted and res.value == [0.5, -0.3, 1.0]
    assert "1.7 is outside the limits [-1, 1] of joint 'c'" in res.reason
    model.run(mgr, 1.0)                      # kinematic, at most 2 rad/s
    assert [j.position for j in joints] == pytest.approx([0.5, -0.3, 1.0], abs=1e-9)


def test_a_command_of_the_wrong_length_or_with_nan_changes_nothing():
    joints, mgr, model = rig("EffortJointInterface")
    c = start(mgr, "effort_controllers/JointGroupEffortController")
    res = c.set_command([1.0, 2.0])
    assert not res.accepted
    assert "Dimension of command (2) does not match number of joints (3: a, b, c)" in res.reason
    res = c.set_command([1.0, float("nan"), 2.0])
    assert not res.accepted and "joint 'b'" in res.reason and "not finite" in res.reason
    assert c.command.read() == [0.0, 0.0, 0.0]
    res = c.set_command([1.0, -20.0, 2.0])
    assert res.value == [1.0, -10.0, 2.0] and "beyond the effort limit 10 of joint 'b'" in res.reason
    model.run(mgr, 0.002)
    assert [j.effort for j in joints] == [1.0, -10.0, 2.0]


def test_velocity_group_drives_the_joint_motors():
    joints, mgr, model = rig("VelocityJointInterface")
    c = start(mgr, "velocity_controllers/JointGroupVelocityController")
    c.set_command([0.5, -0.5, 3.0])          # 3 rad/s is beyond the 2 rad/s limit
    model.run(mgr, 0.2)
    assert [j.velocity for j in joints] == pytest.approx([0.5, -0.5, 2.0], rel=0.02)


def test_effort_group_position_controller_runs_a_pid_per_joint():
    joints, mgr, model = rig("EffortJointInterface")
    pids = {n: {"pid": {"p": 40.0, "d": 3.0}} for n in JOINTS}
    c = start(mgr, "effort_controllers/JointGroupPositionController", **pids)
    assert c.command.read() == pytest.approx([0.0, 0.1, 0.2])
    c.set_command([0.4, -0.4, 0.7])
    model.run(mgr, 3.0)
    assert [j.position for j in joints] == pytest.approx([0.4, -0.4, 0.7], abs=0.01)
    assert c.pid_namespaces == ["/arm/group/a/pid", "/arm/group/b/pid", "/arm/group/c/pid"]


def test_load_errors_name_the_parameter():
    joints, mgr, model = rig("EffortJointInterface")
    with pytest.raises(ControllerError, match="/arm/g/joints is missing"):
        mgr.load("g", {"type": "effort_controllers/JointGroupEffortController"})
    with pytest.raises(ControllerError, match="/arm/g/joints is empty"):
        mgr.load("g", {"type": "effort_controllers/JointGroupEffortController", "joints": []})
    with pytest.raises(ControllerError, match="/arm/g/b/pid is missing"):
        mgr.load("g", {"type": "effort_controllers/JointGroupPositionController", "joints": JOINTS,
                       "a": {"pid": {"p": 1.0}}})
    with pytest.raises(ControllerError, match="not hardware_interface/PositionJointInterface"):
        mgr.load("g", {"type": "position_controllers/JointGroupPositionController", "joints": JOINTS})
