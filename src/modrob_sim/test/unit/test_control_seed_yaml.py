"""The seeds' own controller YAML files load unchanged (PTRZ ptrz.yaml of seed 002 appendix B.3,
Polaris pid_gains of seed 003), and broken copies are refused with messages naming the problem."""
import math
import os
import xml.etree.ElementTree as ET

import pytest
import yaml

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.hardware import POSITION_PID, RobotHWSim
from modrob_sim.ros_control.manager import STRICT, ControllerManager
from modrob_sim.ros_control.params import Params, nest_slash_keys
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions
from modrob_sim.ros_control.transmissions import parse_transmissions

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")


def load_yaml(name):
    with open(os.path.join(FIX, name)) as f:
        return nest_slash_keys(yaml.safe_load(f))


def joints_from_urdf(xml):
    out = {}
    for j in ET.fromstring(xml).findall("joint"):
        if j.get("type") == "fixed":
            continue
        lim = j.find("limit")
        get = (lambda k: float(lim.get(k)) if lim is not None and lim.get(k) is not None else None)
        out[j.get("name")] = IntegratorJoint(name=j.get("name"), type_=j.get("type"), inertia=0.05,
                                             damping=0.1,
                                             lower=get("lower"), upper=get("upper"),
                                             effort_limit=get("effort"),
                                             velocity_limit=get("velocity"))
    return out


@pytest.fixture
def ptrz():
    with open(os.path.join(FIX, "ptrz_camera.urdf")) as f:
        xml = f.read()
    joints = joints_from_urdf(xml)
    hw = RobotHWSim(joints, parse_transmissions(xml))
    return joints, ControllerManager(hw, "/ptrz")


def test_ptrz_yaml_loads_unchanged_and_moves_the_camera(ptrz):
    joints, mgr = ptrz
    cfg = load_yaml("ptrz_ok.yaml")["ptrz"]
    names = ["joint_state_controller", "roll_position_controller", "tilt_position_controller",
             "pan_position_controller"]
    for n in names:
        mgr.load(n, cfg[n])
    assert mgr.switch(names, [], STRICT)[0]
    assert mgr.get("tilt_position_controller").pid.gains.d == 30.0
    mgr.get("pan_position_controller").set_command(1.0)
    IntegratorModel(list(joints.values())).run(mgr, 3.0)
    assert joints["pan"].position == pytest.approx(1.0, abs=0.01)


def test_ptrz_pan_from_near_pi_to_minus_pi_takes_the_short_way(ptrz):
    joints, mgr = ptrz
    cfg = load_yaml("ptrz_ok.yaml")["ptrz"]
    joints["pan"].position = 3.1
    c = mgr.load("pan_position_controller", cfg["pan_position_controller"])
    mgr.switch(["pan_position_controller"], [], STRICT)
    c.set_command(-3.1)
    track = []
    IntegratorModel([joints["pan"]]).run(mgr, 3.0, record=lambda t: track.append(joints["pan"].position))
    assert min(track) > 3.0 and track[-1] == pytest.approx(2 * math.pi - 3.1, abs=0.01)


def test_ptrz_bad_yaml_messages_name_each_problem(ptrz):
    joints, mgr = ptrz
    cfg = load_yaml("ptrz_bad.yaml")["ptrz"]
    expected = {
        "joint_state_controller": "/ptrz/joint_state_controller/publish_rate",
        "roll_position_controller": "/ptrz/roll_position_controller/pid/p",
        "tilt_position_controller": "effort_controllers/JointPositionControler",
        "pan_position_controller": "/ptrz/pan_position_controller/joint",
    }
    for name, needle in expected.items():
        with pytest.raises(ControllerError) as err:
            mgr.load(name, cfg[name])
        assert needle in str(err.value), str(err.value)
    assert mgr.list_controllers() == []


def polaris_rig(gains_ns_values):
    steer = IntegratorJoint(name="polaris_ranger_ev__front_left_steering_joint", inertia=0.5, damping=1.0,
                            lower=-0.8727, upper=0.8727, effort_limit=1000.0, velocity_limit=1.0)
    hw = RobotHWSim({steer.name: steer}, simple_transmissions({steer.name: "PositionJointInterface"}),
                    Params(gains_ns_values, "/gazebo_ros_control/pid_gains"))
    return steer, hw


def test_polaris_pid_gains_load_unchanged_and_steer():
    cfg = load_yaml("polaris_pid_gains_ok.yaml")
    steer, hw = polaris_rig(cfg["gazebo_ros_control"]["pid_gains"])
    res = hw.joints[steer.name]
    assert res.method == POSITION_PID and (res.pid.gains.p, res.pid.gains.i, res.pid.gains.d) == (1000,
                                                                                                  100, 10)
    mgr = ControllerManager(hw, "/")
    c = mgr.load("front_left_steering_position_controller", cfg["front_left_steering_position_controller"])
    mgr.switch([c.name], [], STRICT)
    c.set_command(0.7)                       # the seed's steering input
    IntegratorModel([steer]).run(mgr, 3.0)
    assert steer.position == pytest.approx(0.7, abs=0.01)


def test_polaris_bad_pid_gains_name_the_parameter():
    cfg = load_yaml("polaris_pid_gains_bad.yaml")
    with pytest.raises(ControllerError) as err:
        polaris_rig(cfg["gazebo_ros_control"]["pid_gains"])
    assert "/gazebo_ros_control/pid_gains/polaris_ranger_ev__front_left_steering_joint/p" in str(err.value)


def test_nest_slash_keys_like_rosparam():
    assert nest_slash_keys({"a/b": {"c": 1}, "a": {"d": 2}}) == {"a": {"b": {"c": 1}, "d": 2}}
