"""The controllers on the real physics core (modrob_sim.physics.World, ODE): the same checks as
the rostests, without ROS: step response of a gravity-loaded arm, wheel speed, the seed's PTRZ
gains, a trajectory on a 3-joint arm with pid_gains."""
import os

import pytest
import yaml

from modrob_sim.ros_control import gain_check
from modrob_sim.ros_control.controllers.joint_trajectory import TrajectoryPoint
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import STRICT, ControllerManager
from modrob_sim.ros_control.params import Params, nest_slash_keys
from modrob_sim.ros_control.transmissions import parse_transmissions

physics = pytest.importorskip("modrob_sim.physics")
FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")


def sim(urdf_name, pid_gains=None, ns="/r"):
    with open(os.path.join(FIX, urdf_name)) as f:
        xml = f.read()
    world = physics.World(time_step=0.001)
    model = world.add_urdf("robot", xml)
    hw = RobotHWSim(model.joints, parse_transmissions(model.source_xml),
                    Params(pid_gains, ns + "/gazebo_ros_control/pid_gains") if pid_gains else None)
    mgr = ControllerManager(hw, ns)
    world.add_step_hook(before=mgr.update)
    return world, model, mgr


def start(mgr, name, params):
    c = mgr.load(name, params)
    assert mgr.switch([name], [], STRICT)[0]
    return c


def step_response(p):
    world, model, mgr = sim("arm_1dof_effort.urdf")
    params = {"type": "effort_controllers/JointPositionController", "joint": "shoulder",
              "pid": {"p": p, "i": 40.0, "d": 6.0, "i_clamp": 10.0}}
    c = start(mgr, "shoulder_controller", params)
    world.step(200)                      # hold the start position against gravity
    c.set_command(0.5)
    t0, rec = world.time, []
    for _ in range(3000):
        world.step(1)
        rec.append((world.time - t0, model.joints["shoulder"].position))
    return rec


def test_gravity_loaded_arm_settles_on_a_half_radian_step():
    rec = step_response(100.0)
    assert abs(rec[-1][1] - 0.5) < 0.01
    assert all(abs(q - 0.5) < 0.01 for t, q in rec if t > 2.5)


def test_higher_p_shortens_the_rise_time_on_ode():
    def rise(rec):
        return next(t for t, q in rec if q >= 0.45)
    assert rise(step_response(200.0)) < 0.9 * rise(step_response(60.0))


def test_velocity_interface_wheel_holds_two_rad_per_s():
    world, model, mgr = sim("wheels.urdf")
    c = start(mgr, "wheel_v_controller", {"type": "velocity_controllers/JointVelocityController",
                                          "joint": "wheel_v"})
    c.set_command(2.0)
    world.step(2000)
    assert model.joints["wheel_v"].velocity == pytest.approx(2.0, rel=0.02)


def test_effort_velocity_controller_wheel_holds_two_rad_per_s():
    world, model, mgr = sim("wheels.urdf")
    c = start(mgr, "wheel_e_controller", {"type": "effort_controllers/JointVelocityController",
                                          "joint": "wheel_e", "pid": {"p": 20.0, "i": 40.0, "i_clamp": 20.0}})
    c.set_command(2.0)
    world.step(4000)
    assert model.joints["wheel_e"].velocity == pytest.approx(2.0, rel=0.02)


def test_ptrz_seed_gains_on_ode_including_the_short_way_across_pi():
    with open(os.path.join(FIX, "ptrz_ok.yaml")) as f:
        cfg = nest_slash_keys(yaml.safe_load(f))["ptrz"]
    world, model, mgr = sim("ptrz_camera.urdf", ns="/ptrz")
    names = list(cfg)
    for n in names:
        mgr.load(n, cfg[n])
    assert mgr.switch(names, [], STRICT)[0]
    mgr.get("pan_position_controller").set_command(3.0)
    mgr.get("tilt_position_controller").set_command(0.3)
    world.step(4000)
    assert model.joints["pan"].position == pytest.approx(3.0, abs=0.02)
    assert model.joints["tilt"].position == pytest.approx(0.3, abs=0.02)
    mgr.get("pan_position_controller").set_command(-3.0)       # +0.28 rad the short way
    track = []
    for _ in range(4000):
        world.step(1)
        track.append(model.joints["pan"].position)
    assert min(track) > 2.9
    assert track[-1] == pytest.approx(2 * 3.141592653589793 - 3.0, abs=0.02)


def test_position_interface_with_pid_gains_and_trajectory_on_three_joints():
    gains = {j: {"p": 400.0, "i": 600.0, "d": 4.0, "i_clamp": 10.0} for j in ("yaw", "shoulder", "elbow")}
    world, model, mgr = sim("arm_3dof.urdf", pid_gains=gains, ns="/arm3")
    assert {r.method for r in mgr.hw.joints.values()} == {"POSITION_PID"}
    c = start(mgr, "arm_controller", {"type": "position_controllers/JointTrajectoryController",
                                      "joints": ["yaw", "shoulder", "elbow"],
                                      "constraints": {"goal_time": 1.0, "stopped_velocity_tolerance": 0.05,
                                                      "yaw": {"goal": 0.02}, "shoulder": {"goal": 0.02},
                                                      "elbow": {"goal": 0.02}}})
    pts = [TrajectoryPoint([0.3, 0.2, -0.3], time_from_start=1.0),
           TrajectoryPoint([0.6, 0.5, -0.6], time_from_start=2.0),
           TrajectoryPoint([0.4, 0.3, -0.2], [0, 0, 0], time_from_start=3.0)]
    ok, code, text = c.submit(["yaw", "shoulder", "elbow"], pts, 0.0, world.time, goal_id="g")
    assert ok, text
    events = []
    for _ in range(5000):
        world.step(1)
        events.extend(c.events)
        del c.events[:]
        if events:
            break
    assert events and events[0][:2] == ("g", "succeeded"), events
    for j, q in zip(("yaw", "shoulder", "elbow"), (0.4, 0.3, -0.2)):
        assert model.joints[j].position == pytest.approx(q, abs=0.02)


def test_gains_that_cannot_run_at_the_step_are_named_once_at_load_time():
    world, model, mgr = sim("arm_1dof_effort.urdf")
    logs = []
    mgr.log = lambda level, msg: logs.append((level, msg))
    mgr.time_step = world.time_step
    inertia = gain_check.effective_inertia(model.joints["shoulder"])
    assert inertia == pytest.approx(model.joints["shoulder"].child_inertia)   # one link beyond it
    d_max = 2.0 * inertia / world.time_step
    ok = {"type": "effort_controllers/JointPositionController", "joint": "shoulder",
          "pid": {"p": 100.0, "d": 0.4 * d_max}}
    mgr.load("calm", ok)
    assert not [m for lvl, m in logs if lvl == "warn"]
    bad = dict(ok, pid={"p": 100.0, "d": 3.0 * d_max})
    mgr.load("shaky", bad)
    warns = [m for lvl, m in logs if lvl == "warn"]
    assert len(warns) == 1
    assert "controller 'shaky' joint 'shoulder'" in warns[0]
    assert "largest stable d is %.3g" % d_max in warns[0]


def test_the_inertia_a_joint_moves_is_everything_beyond_it():
    """ur_gazebo's gains on a UR-like arm: d = 200 on the shoulder moves the whole arm (no warning);
    the same d on the last joint, whose link weighs 0.19 kg, is named."""
    with open(os.path.join(FIX, "arm6_controllers.yaml")) as f:
        cfg = yaml.safe_load(f)
    world, model, mgr = sim("arm6_three_interfaces.urdf", ns="/arm6")
    logs = []
    mgr.log = lambda level, msg: logs.append((level, msg))
    mgr.time_step = world.time_step
    pan, wrist3 = model.joints["shoulder_pan_joint"], model.joints["wrist_3_joint"]
    assert gain_check.effective_inertia(pan) > 20 * pan.child_inertia
    assert gain_check.effective_inertia(wrist3) == pytest.approx(wrist3.child_inertia)
    mgr.load("ur_style", cfg["eff_joint_traj_controller"])
    assert logs == []
    params = dict(cfg["eff_joint_traj_controller"])
    params["gains"] = dict(params["gains"], wrist_3_joint={"p": 10, "d": 200})
    mgr.load("shaky_wrist", params)
    assert len(logs) == 1 and "controller 'shaky_wrist' joint 'wrist_3_joint': d = 200" in logs[0][1]


ARM6 = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
        "wrist_3_joint"]


def _arm6_error(model, target):
    return max(abs(model.joints[j].position - q) for j, q in zip(ARM6, target))


def test_six_joint_arm_with_three_interfaces_switches_between_effort_trajectory_and_position_group():
    with open(os.path.join(FIX, "arm6_controllers.yaml")) as f:
        cfg = yaml.safe_load(f)
    world, model, mgr = sim("arm6_three_interfaces.urdf", ns="/arm6")
    assert {r.interfaces for r in mgr.hw.joints.values()} == {
        ("PositionJointInterface", "VelocityJointInterface", "EffortJointInterface")}
    traj = start(mgr, "eff_joint_traj_controller", cfg["eff_joint_traj_controller"])
    group = mgr.load("joint_group_pos_controller", cfg["joint_group_pos_controller"])
    first = [0.6, -0.7, 1.2, -0.8, 0.5, 0.9]
    ok, _, text = traj.submit(ARM6, [TrajectoryPoint(first, [0.0] * 6, time_from_start=2.0)], 0.0, world.time,
                              goal_id="g1")
    assert ok, text
    world.step(3000)
    assert traj.events[-1][:2] == ("g1", "succeeded")
    assert _arm6_error(model, first) < 0.01
    # hand the joints to the position group controller in one switch: it holds, then moves
    assert mgr.switch(["joint_group_pos_controller"], ["eff_joint_traj_controller"], STRICT)[0]
    assert {r.interface for r in mgr.hw.joints.values()} == {"PositionJointInterface"}
    world.step(200)
    assert _arm6_error(model, first) < 0.01
    second = [-0.5, 0.4, -0.9, 1.0, -0.6, -1.2]
    assert group.set_command(second).accepted
    world.step(1500)
    assert _arm6_error(model, second) < 0.01
    # and back to the effort trajectory controller, which holds there and follows a new goal
    assert mgr.switch(["eff_joint_traj_controller"], ["joint_group_pos_controller"], STRICT)[0]
    assert {r.interface for r in mgr.hw.joints.values()} == {"EffortJointInterface"}
    world.step(1000)
    assert _arm6_error(model, second) < 0.01
    ok, _, text = traj.submit(ARM6, [TrajectoryPoint(first, [0.0] * 6, time_from_start=2.0)], 0.0, world.time,
                              goal_id="g2")
    world.step(3000)
    assert traj.events[-1][:2] == ("g2", "succeeded")
    assert _arm6_error(model, first) < 0.01
    assert world.pop_events() == []


def test_effort_gripper_action_controller_closes_on_a_can_stalls_and_opens_to_reach_its_goal():
    with open(os.path.join(FIX, "gripper_controllers.yaml")) as f:
        cfg = yaml.safe_load(f)
    with open(os.path.join(FIX, "..", "sim", "ground.urdf")) as f:
        ground = f.read()
    with open(os.path.join(FIX, "can.urdf")) as f:
        can_xml = f.read()
    world, model, mgr = sim("gripper_parallel.urdf", ns="/gripper")
    world.add_urdf("ground", ground)
    gripper = start(mgr, "gripper_controller", cfg["gripper_controller"])
    finger = model.joints["finger_joint1"]

    def outcome_of(gid, position, max_effort, steps):
        del gripper.events[:]
        assert gripper.submit(gid, position, max_effort, world.time)[0]
        world.step(steps)
        (event_gid, outcome, result, text), = gripper.events
        assert event_gid == gid
        return outcome, result
    outcome, result = outcome_of("open", 0.04, 5.0, 1000)          # spawned closed
    assert outcome == "succeeded" and result["reached_goal"] and not result["stalled"]
    assert finger.position == pytest.approx(0.04, abs=0.002)
    can = world.add_urdf("can", can_xml)                            # between the open fingers
    outcome, result = outcome_of("close", 0.0, 5.0, 1500)
    assert outcome == "aborted" and result["stalled"] and not result["reached_goal"]
    assert result["position"] == pytest.approx(0.03, abs=0.001)     # the 60 mm can between the pads
    assert model.joints["finger_joint2"].position == pytest.approx(finger.position, abs=1e-3)   # mimic
    assert abs(can.pose[0][0]) < 0.002 and abs(can.pose[0][1]) < 0.002    # squeezed, not pushed away
    assert finger.effort < -1.0                                      # still pressing
    outcome, result = outcome_of("reopen", 0.04, 5.0, 1000)
    assert outcome == "succeeded" and result["reached_goal"]
    assert world.pop_events() == []


def test_an_idle_effort_joint_leaves_the_joint_to_a_model_plugins_actuator():
    # katana_gazebo_plugins' gripper plugin drives the finger joints that the Katana's URDF also
    # gives effort transmissions: the hardware (loaded first) must leave them free while no effort
    # is commanded; a non-zero effort on such a joint is not applied and said once
    world = physics.World(time_step=0.001)
    with open(os.path.join(FIX, "arm_1dof_effort.urdf")) as f:
        model = world.add_urdf("robot", f.read())
    warnings = []
    hw = RobotHWSim(model.joints, parse_transmissions(model.source_xml), warn=warnings.append, world=world)
    mgr = ControllerManager(hw, "/r")
    world.add_step_hook(before=mgr.update)
    joint = model.joints["shoulder"]
    plugin = world.add_actuator(joint, physics.actuators.POSITION_PID,
                                gains=physics.actuators.PidGains(200.0, 50.0, 10.0, 20.0, -20.0))
    plugin.command = 0.3
    world.step(3000)
    assert joint.actuator is plugin
    assert joint.position == pytest.approx(0.3, abs=0.01)
    hw.joints["shoulder"].command = 5.0
    world.step(200)
    assert joint.actuator is plugin
    assert joint.position == pytest.approx(0.3, abs=0.01)
    said = [w for w in warnings if "shoulder" in w and "effort command" in w]
    assert len(said) == 1, warnings
