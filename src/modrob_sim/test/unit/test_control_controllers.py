"""Single-joint controllers and the simulated hardware on a 1-DoF integrator plant."""
import math

import pytest

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import POSITION_PID, VELOCITY_PID, RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions


def rig(iface="EffortJointInterface", pid_gains=None, **joint_kw):
    kw = dict(name="j1", inertia=0.05, damping=0.05, lower=-2.0, upper=2.0, effort_limit=20.0,
              velocity_limit=5.0)
    kw.update(joint_kw)
    joint = IntegratorJoint(**kw)
    hw = RobotHWSim({joint.name: joint}, simple_transmissions({joint.name: iface}),
                    Params(pid_gains, "/gazebo_ros_control/pid_gains") if pid_gains else None)
    return joint, hw, ControllerManager(hw, "/robot"), IntegratorModel([joint])


def start(mgr, name, params):
    c = mgr.load(name, params)
    ok, msg = mgr.switch([name], [], 2)
    assert ok, msg
    return c


def settle_time(samples, target, band):
    """First time after which every sample stays within band of target."""
    t_in = None
    for t, q in samples:
        if abs(q - target) <= band:
            if t_in is None:
                t_in = t
        else:
            t_in = None
    return t_in


def test_effort_position_controller_step_response_settles():
    joint, hw, mgr, model = rig()
    c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                           "pid": {"p": 50.0, "d": 4.0}})
    c.set_command(0.5)
    samples = []
    model.run(mgr, 3.0, record=lambda t: samples.append((t, joint.position)))
    assert abs(joint.position - 0.5) < 0.01
    ts = settle_time(samples, 0.5, 0.01)
    assert ts is not None and ts < 2.0
    assert c.pending["set_point"] == 0.5 and c.pending["p"] == 50.0


def test_higher_p_rises_faster():
    def rise_time(p):
        joint, hw, mgr, model = rig(effort_limit=1000.0)
        c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                               "pid": {"p": p, "d": 2.0}})
        c.set_command(0.5)
        rec = []
        model.run(mgr, 2.0, record=lambda t: rec.append((t, joint.position)))
        return next(t for t, q in rec if q >= 0.45)
    assert rise_time(80.0) < 0.8 * rise_time(20.0)


def test_position_command_beyond_limit_is_clamped():
    joint, hw, mgr, model = rig()
    c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                           "pid": {"p": 50.0, "d": 4.0}})
    res = c.set_command(5.0)
    assert res.accepted and res.value == 2.0 and res.clamped_from == 5.0 and "limits" in res.reason
    model.run(mgr, 3.0)
    assert joint.position == pytest.approx(2.0, abs=0.01)


def test_nan_command_is_ignored():
    joint, hw, mgr, model = rig()
    c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                           "pid": {"p": 50.0, "d": 4.0}})
    c.set_command(0.3)
    res = c.set_command(float("nan"))
    assert not res.accepted and "not finite" in res.reason
    assert c.command.read() == 0.3
    model.run(mgr, 0.1)
    assert all(math.isfinite(v) for v in (joint.position, joint.velocity))


def test_effort_limit_clamps_pid_output():
    joint, hw, mgr, model = rig(effort_limit=1.0)
    c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                           "pid": {"p": 1000.0}})
    c.set_command(1.0)
    model.run(mgr, 0.01)
    assert abs(joint.effort) <= 1.0 + 1e-12


def test_continuous_joint_takes_the_shortest_way():
    joint, hw, mgr, model = rig(type_="continuous", lower=None, upper=None, position=3.0)
    c = start(mgr, "pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                           "pid": {"p": 50.0, "d": 4.0}})
    c.set_command(-3.0)          # 3.0 -> -3.0 is +0.283 rad the short way, -6.0 rad the long way
    rec = []
    model.run(mgr, 3.0, record=lambda t: rec.append(joint.position))
    assert min(rec) > 2.9                       # never went backwards through 0
    assert joint.position == pytest.approx(2 * math.pi - 3.0, abs=0.01)


def test_effort_velocity_controller_holds_speed():
    joint, hw, mgr, model = rig(type_="continuous", lower=None, upper=None, damping=0.5)
    c = start(mgr, "vel", {"type": "effort_controllers/JointVelocityController", "joint": "j1",
                           "pid": {"p": 5.0, "i": 20.0, "i_clamp": 5.0}})
    c.set_command(2.0)
    model.run(mgr, 3.0)
    assert joint.velocity == pytest.approx(2.0, rel=0.02)


def test_effort_forward_controller_and_its_limit():
    joint, hw, mgr, model = rig(effort_limit=3.0)
    c = start(mgr, "eff", {"type": "effort_controllers/JointEffortController", "joint": "j1"})
    res = c.set_command(10.0)
    assert res.value == 3.0 and res.clamped_from == 10.0
    model.run(mgr, 0.002)
    assert joint.effort == 3.0


def test_position_interface_without_gains_is_kinematic_and_rate_limited():
    joint, hw, mgr, model = rig("PositionJointInterface", velocity_limit=1.0)
    assert hw.joints["j1"].method == "PositionJointInterface"
    c = start(mgr, "pp", {"type": "position_controllers/JointPositionController", "joint": "j1"})
    c.set_command(0.5)
    model.run(mgr, 0.1)
    assert joint.position == pytest.approx(0.1, abs=2e-3)     # 1 rad/s for 0.1 s
    model.run(mgr, 0.5)
    assert joint.position == pytest.approx(0.5, abs=1e-9)


def test_position_interface_with_pid_gains_is_driven_by_effort():
    gains = {"j1": {"p": 50.0, "i": 0.0, "d": 4.0}}     # Polaris style pid_gains
    joint, hw, mgr, model = rig("PositionJointInterface", pid_gains=gains, velocity_limit=10.0)
    assert hw.joints["j1"].method == POSITION_PID
    c = start(mgr, "pp", {"type": "position_controllers/JointPositionController", "joint": "j1"})
    c.set_command(0.5)
    model.run(mgr, 0.01)
    assert joint.effort != 0.0                                 # an effort, not a teleport
    model.run(mgr, 3.0)
    assert joint.position == pytest.approx(0.5, abs=0.01)


def test_velocity_interface_motor_and_pid():
    joint, hw, mgr, model = rig("VelocityJointInterface", type_="continuous", lower=None, upper=None,
                                damping=0.5)
    c = start(mgr, "vv", {"type": "velocity_controllers/JointVelocityController", "joint": "j1"})
    c.set_command(2.0)
    model.run(mgr, 0.5)
    assert joint.velocity == pytest.approx(2.0, rel=0.02)
    gains = {"j1": {"p": 5.0, "i": 20.0, "i_clamp": 5.0}}
    joint, hw, mgr, model = rig("VelocityJointInterface", pid_gains=gains, type_="continuous", lower=None,
                                upper=None, damping=0.5)
    assert hw.joints["j1"].method == VELOCITY_PID
    c = start(mgr, "vv", {"type": "velocity_controllers/JointVelocityController", "joint": "j1"})
    c.set_command(2.0)
    model.run(mgr, 3.0)
    assert joint.velocity == pytest.approx(2.0, rel=0.02)


def test_wrong_interface_and_unknown_joint_are_named():
    joint, hw, mgr, model = rig("PositionJointInterface")
    with pytest.raises(ControllerError) as err:
        mgr.load("pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                         "pid": {"p": 1}})
    assert "j1" in str(err.value) and "EffortJointInterface" in str(err.value)
    with pytest.raises(ControllerError, match="joint 'elbow' is not a ros_control joint"):
        mgr.load("pos2", {"type": "position_controllers/JointPositionController", "joint": "elbow"})


def test_missing_joint_and_pid_parameters_name_the_full_path():
    joint, hw, mgr, model = rig()
    with pytest.raises(ControllerError, match="/robot/pos/joint is missing"):
        mgr.load("pos", {"type": "effort_controllers/JointPositionController", "pid": {"p": 1}})
    with pytest.raises(ControllerError, match="/robot/pos/pid is missing"):
        mgr.load("pos", {"type": "effort_controllers/JointPositionController", "joint": "j1"})
    with pytest.raises(ControllerError, match="/robot/pos/pid/p"):
        mgr.load("pos", {"type": "effort_controllers/JointPositionController", "joint": "j1",
                         "pid": {"d": 1}})


def test_joint_state_controller_publishes_at_its_rate_and_requires_it():
    joint, hw, mgr, model = rig()
    with pytest.raises(ControllerError, match="/robot/jsc/publish_rate"):
        mgr.load("jsc", {"type": "joint_state_controller/JointStateController"})
    c = start(mgr, "jsc", {"type": "joint_state_controller/JointStateController", "publish_rate": 50})
    stamps = []

    def grab(t):
        if c.pending is not None:
            stamps.append(c.pending[0])
            c.pending = None
    model.run(mgr, 1.0, record=grab)
    assert len(stamps) in (50, 51)
    assert c.pending is None and len(set(stamps)) == len(stamps)


def test_transmission_on_a_fixed_joint_is_skipped_with_a_warning():
    fixed = IntegratorJoint(name="weld", type_="fixed")
    moving = IntegratorJoint(name="j1")
    notes = []
    hw = RobotHWSim({"weld": fixed, "j1": moving},
                    simple_transmissions({"weld": "EffortJointInterface", "j1": "EffortJointInterface"}),
                    warn=notes.append)
    assert hw.order == ["j1"] and "weld is fixed" in notes[0]


def test_velocity_position_controller_writes_the_pids_velocity():
    """velocity_controllers/JointPositionController: PID(position error) is a velocity command,
    which the hardware's joint motor follows."""
    joint, hw, mgr, model = rig("VelocityJointInterface", damping=0.5)
    c = start(mgr, "vp", {"type": "velocity_controllers/JointPositionController", "joint": "j1",
                          "pid": {"p": 8.0}})
    assert c.claimed_resources == [("hardware_interface::VelocityJointInterface", ["j1"])]
    res = c.set_command(0.6)
    assert res.accepted and res.value == 0.6
    model.run(mgr, 0.001)
    # the joint's actuator: the PID's output is the motor's velocity (rad/s, not N m), with the
    # effort limit as its force, as the hardware's velocity write would set it
    assert joint._motor == (pytest.approx(8.0 * 0.6), 20.0) and joint.effort == 0.0
    model.run(mgr, 2.0)
    assert joint.position == pytest.approx(0.6, abs=0.005)
    mgr.switch([], ["vp"], 2)                  # stopped: the hardware keeps the last velocity
    last = hw.joints["j1"].command
    assert hw.joints["j1"].actuator is None and abs(last) < 0.05 and joint._motor == (last, 20.0)
    assert c.set_command(3.0).value == 2.0                              # clamped to the joint limits
    with pytest.raises(ControllerError, match="not hardware_interface/VelocityJointInterface"):
        rig()[2].load("vp", {"type": "velocity_controllers/JointPositionController", "joint": "j1",
                             "pid": {"p": 8.0}})
