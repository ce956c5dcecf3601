"""Several command interfaces on one joint: which ones a joint offers, the controller choosing the
one it claims, switch_controller activating it, and resource conflicts across interfaces."""
import pytest

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import POSITION_PID, RobotHWSim
from modrob_sim.ros_control.manager import BEST_EFFORT, STRICT, ControllerManager
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel
from modrob_sim.ros_control.transmissions import EFFORT, POSITION, VELOCITY, parse_transmissions

# j1: three transmissions (franka_description's style), j2: one transmission with two interfaces,
# j3: one interface
URDF = """<robot name="r">
  <transmission name="j1_pos"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j1"><hardwareInterface>hardware_interface/PositionJointInterface</hardwareInterface></joint>
    <actuator name="j1_m1"/></transmission>
  <transmission name="j1_vel"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j1"><hardwareInterface>hardware_interface/VelocityJointInterface</hardwareInterface></joint>
    <actuator name="j1_m2"/></transmission>
  <transmission name="j1_eff"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j1"><hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface></joint>
    <actuator name="j1_m3"/></transmission>
  <transmission name="j2_trans"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j2"><hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
      <hardwareInterface>hardware_interface/PositionJointInterface</hardwareInterface></joint>
    <actuator name="j2_m"/></transmission>
  <transmission name="j3_trans"><type>transmission_interface/SimpleTransmission</type>
    <joint name="j3"><hardwareInterface>EffortJointInterface</hardwareInterface></joint>
    <actuator name="j3_m"/></transmission>
</robot>"""

EFF_POS = {"type": "effort_controllers/JointPositionController", "joint": "j1", "pid": {"p": 40.0, "d": 4.0}}
POS = {"type": "position_controllers/JointPositionController", "joint": "j1"}
VEL = {"type": "velocity_controllers/JointVelocityController", "joint": "j1"}


def rig(pid_gains=None):
    joints = {n: IntegratorJoint(name=n, inertia=0.05, damping=0.05, lower=-2.0, upper=2.0, effort_limit=20.0,
                                 velocity_limit=2.0) for n in ("j1", "j2", "j3")}
    warnings = []
    hw = RobotHWSim(joints, parse_transmissions(URDF),
                    Params(pid_gains, "/gazebo_ros_control/pid_gains") if pid_gains else None,
                    warn=warnings.append)
    return joints, hw, ControllerManager(hw, "/r"), IntegratorModel(list(joints.values())), warnings


def test_a_joint_offers_every_interface_its_transmissions_name_once():
    joints, hw, mgr, model, warnings = rig()
    assert hw.order == ["j1", "j2", "j3"]
    assert hw.joints["j1"].interfaces == (POSITION, VELOCITY, EFFORT)
    assert hw.joints["j2"].interfaces == (EFFORT, POSITION)
    assert hw.joints["j3"].interfaces == (EFFORT,)
    # the first declared is active until a controller claims another
    assert [hw.joints[n].interface for n in hw.order] == [POSITION, EFFORT, EFFORT]
    assert warnings == []


def test_an_interface_declared_twice_is_kept_once_with_a_warning():
    urdf = URDF.replace("hardware_interface/PositionJointInterface</hardwareInterface></joint>\n    "
                        "<actuator name=\"j2_m\"/>",
                        "hardware_interface/EffortJointInterface</hardwareInterface></joint>\n    "
                        "<actuator name=\"j2_m\"/>")
    joints = {n: IntegratorJoint(name=n) for n in ("j1", "j2", "j3")}
    warnings = []
    hw = RobotHWSim(joints, parse_transmissions(urdf), warn=warnings.append)
    assert hw.joints["j2"].interfaces == (EFFORT,)
    assert len(warnings) == 1 and "j2" in warnings[0] and "declared twice" in warnings[0]


def test_the_controller_claims_the_interface_its_type_needs():
    joints, hw, mgr, model, _ = rig()
    for name, params, iface in (("a", EFF_POS, EFFORT), ("b", POS, POSITION), ("c", VEL, VELOCITY)):
        c = mgr.load(name, params)
        assert c.claimed_resources == [("hardware_interface::" + iface, ["j1"])]
    with pytest.raises(ControllerError) as err:
        mgr.load("d", {"type": "position_controllers/JointPositionController", "joint": "j3"})
    text = str(err.value)
    assert "'d'" in text and "'j3'" in text and "hardware_interface/EffortJointInterface" in text
    assert "not hardware_interface/PositionJointInterface" in text


def test_starting_a_controller_activates_its_interface_and_it_moves_the_joint():
    joints, hw, mgr, model, _ = rig()
    j1 = joints["j1"]
    eff = mgr.load("eff", EFF_POS)
    pos = mgr.load("pos", POS)
    vel = mgr.load("vel", VEL)
    assert mgr.switch(["eff"], [], STRICT)[0]
    assert hw.joints["j1"].interface == EFFORT and hw.joints["j1"].method == EFFORT
    eff.set_command(0.8)
    model.run(mgr, 3.0)
    assert j1.position == pytest.approx(0.8, abs=0.01)
    assert j1.effort != 0.0                                   # driven by an effort
    # swap to the position interface in one switch: it starts holding where the joint is
    assert mgr.switch(["pos"], ["eff"], STRICT)[0]
    assert hw.joints["j1"].interface == POSITION
    model.run(mgr, 0.2)
    assert j1.position == pytest.approx(0.8, abs=0.01)
    pos.set_command(-0.4)
    model.run(mgr, 1.0)                                       # kinematic, 2 rad/s velocity limit
    assert j1.position == pytest.approx(-0.4, abs=1e-9) and j1.effort == 0.0
    # and to the velocity interface (ODE motor without pid_gains)
    assert mgr.switch(["vel"], ["pos"], STRICT)[0]
    assert hw.joints["j1"].interface == VELOCITY
    vel.set_command(0.5)
    model.run(mgr, 0.5)
    assert j1.velocity == pytest.approx(0.5, rel=0.02)
    # back to effort: the command starts at 0, the PID holds the new position
    assert mgr.switch(["eff"], ["vel"], STRICT)[0]
    assert hw.joints["j1"].interface == EFFORT and hw.joints["j1"].command == 0.0
    here = j1.position
    model.run(mgr, 2.0)
    assert j1.position == pytest.approx(here, abs=0.05)


def test_two_controllers_on_one_joint_conflict_whatever_their_interfaces():
    joints, hw, mgr, model, _ = rig()
    mgr.load("eff", EFF_POS)
    mgr.load("pos", POS)
    assert mgr.switch(["eff"], [], STRICT)[0]
    ok, msg = mgr.switch(["pos"], [], BEST_EFFORT)
    assert not ok
    assert "Resource conflict for resource 'j1'" in msg
    assert "'eff' (hardware_interface::EffortJointInterface)" in msg
    assert "'pos' (hardware_interface::PositionJointInterface)" in msg
    # refused: nothing changed
    assert hw.joints["j1"].interface == EFFORT
    assert {c.name: c.state for c in mgr.list_controllers()} == {"eff": "running", "pos": "initialized"}
    ok, msg = mgr.switch(["eff", "pos"], [], STRICT)
    assert not ok


def test_a_stopped_controller_leaves_the_interface_and_the_pid_gains_follow_the_interface():
    gains = {"j1": {"p": 50.0, "d": 4.0}}
    joints, hw, mgr, model, _ = rig(pid_gains=gains)
    res = hw.joints["j1"]
    assert res.method == POSITION_PID                          # first interface, with pid_gains
    mgr.load("eff", EFF_POS)
    assert mgr.switch(["eff"], [], STRICT)[0]
    assert res.method == EFFORT                                # the PID is not used for efforts
    assert mgr.switch([], ["eff"], STRICT)[0]
    assert res.interface == EFFORT                             # nobody claims it: stays
    mgr.load("pos", POS)
    assert mgr.switch(["pos"], [], STRICT)[0]
    assert res.method == POSITION_PID
