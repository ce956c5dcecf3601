"""Controller YAML in ros_control's format; gains obey the stability and saturation rules."""
import math

import pytest
import yaml

from modrob_build import gains
from modrob_build.build import RobotSpec, build_robot_set
from modrob_build.module_database import load_database
from modrob_build.order import validate_order
from modrob_build.robot_model import build_robot_model

SEED_6DOF = [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5]


@pytest.fixture(scope="module")
def db():
    return load_database()


def test_yaml_format(db):
    result = build_robot_set([RobotSpec([59, 3, 55, 63, 57, 5]), RobotSpec(SEED_6DOF)], gripper=True, db=db)
    cfg = yaml.safe_load(result.files["modrob1_controllers.yaml"])
    assert list(cfg) == ["modrob1"]
    c = cfg["modrob1"]
    assert c["joint_state_controller"] == {"type": "joint_state_controller/JointStateController",
                                           "publish_rate": 50}
    for k in range(1, 7):
        jc = c["joint%d_position_controller" % k]
        assert jc["type"] == "effort_controllers/JointPositionController"
        assert jc["joint"] == "joint%d" % k
        assert set(jc["pid"]) >= {"p", "i", "d", "i_clamp"}
        for key in ("p", "i", "d", "i_clamp"):
            assert math.isfinite(jc["pid"][key]) and jc["pid"][key] >= 0
    assert c["gripper_finger1_position_controller"]["joint"] == "gripper_finger1_joint"
    # finger 2 is a <mimic> joint: like ros_control, it gets no controller of its own
    assert not any("finger2" in name for name in c)


def test_gains_respect_limits(db):
    robot = build_robot_model(validate_order(SEED_6DOF, db), SEED_6DOF)
    for load in gains.joint_loads(robot, gains.GRIPPER_PAYLOAD):
        g = gains.pid_from_load(load)
        assert load.j_min > 0 and load.j_max >= load.j_min
        assert (g.d + load.damping) * gains.TIME_STEP / load.j_min <= gains.KAPPA + 1e-9, load.joint
        assert g.p * gains.ARM_E_SAT <= load.effort + 1e-9, load.joint
        assert g.i_clamp <= load.effort
        # Routh: J s^3 + (Kd + b) s^2 + Kp s + Ki stable at J_max
        assert (g.d + load.damping) * g.p > load.j_max * g.i


def test_shoulder_sees_more_inertia_and_gravity_than_wrist(db):
    robot = build_robot_model(validate_order(SEED_6DOF, db), SEED_6DOF)
    loads = {lo.joint: lo for lo in gains.joint_loads(robot)}
    assert loads["joint2"].j_max > loads["joint5"].j_max > 0
    assert loads["joint2"].gravity_torque > loads["joint5"].gravity_torque > 0
    assert loads["joint6"].gravity_torque == 0.0     # inline wrist at the straight chain's end
    assert loads["joint2"].gravity_torque < db[63].effort   # the shoulder can hold the arm


def test_finger_gains_saturate_at_grip_force():
    g = gains.finger_gains(gains.finger_load("gripper_finger1_joint", 3.0))
    assert g.p * gains.FINGER_E_SAT <= 3.0 + 1e-9
    assert g.i_clamp == 3.0
