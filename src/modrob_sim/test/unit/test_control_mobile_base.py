"""diff_drive_controller/DiffDriveController and ackermann_steering_controller/AckermannSteeringController:
parameters and their errors, the speed limiter, odometry integration, timeouts (on pure-Python
joints), then diffbot driven on the ODE World: distance, turn and odometry against ground truth."""
import math
import os

import pytest
import yaml

from modrob_sim.errors import ControllerError
from modrob_sim.ros_control.controllers.mobile_base import Odometry, SpeedLimiter
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import STRICT, ControllerManager
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions
from modrob_sim.ros_control.transmissions import parse_transmissions

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
COV = [0.001, 0.001, 1e6, 1e6, 1e6, 0.03]
DD = "diff_drive_controller/DiffDriveController"
ACK = "ackermann_steering_controller/AckermannSteeringController"


def dd_params(**over):
    p = {"type": DD, "left_wheel": ["fl", "rl"], "right_wheel": ["fr", "rr"], "wheel_separation": 0.5,
         "wheel_radius": 0.1, "pose_covariance_diagonal": COV, "twist_covariance_diagonal": COV}
    p.update(over)
    return p


def four_wheels():
    joints = [IntegratorJoint(n, "continuous", inertia=0.01, velocity_limit=30.0, effort_limit=50.0)
              for n in ("fl", "rl", "fr", "rr")]
    plant = IntegratorModel(joints)
    hw = RobotHWSim(plant.joints, simple_transmissions({n: "VelocityJointInterface" for n in plant.joints}))
    return plant, hw, ControllerManager(hw, "/bot")


def start(mgr, name, params):
    c = mgr.load(name, params)
    ok, msg = mgr.switch([name], [], STRICT)
    assert ok, msg
    return c


# -- parameters ---------------------------------------------------------------------------------
def test_wheel_lists_and_single_names_claim_every_wheel():
    plant, hw, mgr = four_wheels()
    c = start(mgr, "base", dd_params())
    assert c.claimed_resources == [("hardware_interface::VelocityJointInterface", ["fl", "rl", "fr", "rr"])]
    plant2, hw2, mgr2 = four_wheels()
    c2 = start(mgr2, "base", dd_params(left_wheel="fl", right_wheel="fr"))
    assert c2.joint_names == ["fl", "fr"]


@pytest.mark.parametrize("over, words", [
    ({"left_wheel": ["fl"]}, ["#left wheels (1) != #right wheels (2)"]),
    ({"left_wheel": []}, ["/bot/base/left_wheel", "non-empty list"]),
    ({"left_wheel": 3}, ["/bot/base/left_wheel", "joint name"]),
    ({"right_wheel": ["fr", "nope"]}, ["'nope'", "known joints"]),
    ({"pose_covariance_diagonal": [1, 2, 3]}, ["/bot/base/pose_covariance_diagonal", "6 finite numbers"]),
    ({"twist_covariance_diagonal": None}, ["/bot/base/twist_covariance_diagonal", "6 finite numbers"]),
    ({"wheel_radius": -0.1}, ["/bot/base/wheel_radius", "> 0"]),
    ({"publish_rate": 0}, ["/bot/base/publish_rate", "> 0"]),
    ({"linear": {"x": {"has_velocity_limits": "yes"}}}, ["/bot/base/linear/x/has_velocity_limits"]),
])
def test_bad_parameters_are_refused_naming_the_parameter(over, words):
    plant, hw, mgr = four_wheels()
    with pytest.raises(ControllerError) as err:
        mgr.load("base", dd_params(**over))
    for w in words:
        assert w in str(err.value)


def test_missing_covariance_says_what_to_write():
    plant, hw, mgr = four_wheels()
    p = dd_params()
    del p["pose_covariance_diagonal"]
    with pytest.raises(ControllerError, match="pose_covariance_diagonal is missing.*6 numbers"):
        mgr.load("base", p)


def test_unknown_parameters_are_ignored_as_ros_controllers_does():
    plant, hw, mgr = four_wheels()
    start(mgr, "base", dd_params(k_l=0.1, k_r=0.1))


def test_separation_and_radius_without_a_model_ask_for_the_parameter():
    plant, hw, mgr = four_wheels()
    p = dd_params()
    del p["wheel_radius"]
    with pytest.raises(ControllerError, match="set wheel_radius"):
        mgr.load("base", p)


# -- pure pieces --------------------------------------------------------------------------------
def test_speed_limiter_velocity_acceleration_jerk():
    lim = SpeedLimiter(has_velocity_limits=True, max_velocity=1.0, has_acceleration_limits=True,
                       max_acceleration=2.0, min_acceleration=-4.0)
    assert lim.min_velocity == -1.0
    assert lim.limit(5.0, 0.0, 0.0, 0.1) == pytest.approx(0.2)       # 2 m/s^2 for 0.1 s
    assert lim.limit(-5.0, 0.5, 0.5, 0.1) == pytest.approx(0.1)      # braking at 4 m/s^2
    assert lim.limit(5.0, 0.95, 0.9, 0.1) == pytest.approx(1.0)      # the speed limit
    jerk = SpeedLimiter(has_jerk_limits=True, max_jerk=10.0)
    # the acceleration's change per step is bounded by jerk * 2 dt^2 (ros_controllers' formula)
    assert jerk.limit(1.0, 0.0, 0.0, 0.1) == pytest.approx(10.0 * 2 * 0.01)
    free = SpeedLimiter()
    assert free.limit(123.0, 0.0, 0.0, 0.001) == 123.0


def test_speed_limiter_reads_the_nested_yaml():
    p = Params({"has_velocity_limits": True, "max_velocity": 2, "min_velocity": -0.5}, "/b/linear/x")
    lim = SpeedLimiter.from_params(p)
    assert (lim.has_velocity_limits, lim.max_velocity, lim.min_velocity) == (True, 2.0, -0.5)


def test_odometry_exact_arc_closes_a_circle():
    odo = Odometry(window=3)
    odo.restart(0.0)
    n = 1000
    r = 2.0
    for k in range(1, n + 1):            # a full circle of radius 2 in 1000 steps
        odo.update(2 * math.pi * r / n, 2 * math.pi / n, k * 0.01)
    assert (odo.x, odo.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    assert odo.heading == pytest.approx(2 * math.pi)
    assert odo.linear == pytest.approx(2 * math.pi * r / n / 0.01)
    assert odo.angular == pytest.approx(2 * math.pi / n / 0.01)


# -- behaviour on pure joints -------------------------------------------------------------------
def test_wheel_speeds_odometry_and_timeout_on_integrator_joints():
    plant, hw, mgr = four_wheels()
    c = start(mgr, "base", dd_params(cmd_vel_timeout=0.5))
    assert c.set_command(0.2, 0.4).accepted
    plant.run(mgr, 0.3)
    # left (0.2 - 0.4 * 0.25) / 0.1 = 1 rad/s, right 3 rad/s, on both wheels of a side
    speeds = [plant.joints[n].velocity for n in ("fl", "rl", "fr", "rr")]
    assert speeds == pytest.approx([1, 1, 3, 3], abs=1e-6)
    assert c.odometry.linear == pytest.approx(0.2, abs=1e-3)
    assert c.odometry.angular == pytest.approx(0.4, abs=1e-3)
    plant.run(mgr, 0.3)                  # 0.6 s after the command: stale, the wheels stop
    assert [plant.joints[n].velocity for n in ("fl", "rl", "fr", "rr")] == pytest.approx([0] * 4, abs=1e-6)
    assert c.odometry.heading == pytest.approx(0.4 * 0.5, abs=2e-3)


def test_nan_command_is_ignored_and_the_last_one_kept():
    plant, hw, mgr = four_wheels()
    c = start(mgr, "base", dd_params())
    c.set_command(0.1, 0.0)
    res = c.set_command(float("nan"), 0.0)
    assert not res.accepted and "not finite" in res.reason
    plant.run(mgr, 0.1)
    assert plant.joints["fl"].velocity == pytest.approx(1.0, abs=1e-6)


def test_limits_shape_the_command_and_cmd_out_reports_it():
    plant, hw, mgr = four_wheels()
    limits = {"has_velocity_limits": True, "max_velocity": 0.5, "has_acceleration_limits": True,
              "max_acceleration": 1.0}
    c = start(mgr, "base", dd_params(linear={"x": limits}))
    c.set_command(2.0, 0.0)
    plant.run(mgr, 0.2)
    assert c.cmd_out[1] == pytest.approx(0.2, abs=2e-3)          # 1 m/s^2 for 0.2 s
    plant.run(mgr, 0.25)
    assert c.cmd_out[1] == pytest.approx(0.45, abs=2e-3)
    c.set_command(2.0, 0.0)
    plant.run(mgr, 0.2)
    assert c.cmd_out[1] == pytest.approx(0.5)


def test_multipliers_scale_commands_and_odometry():
    plant, hw, mgr = four_wheels()
    c = start(mgr, "base", dd_params(wheel_radius_multiplier=2.0, wheel_separation_multiplier=1.5))
    c.set_command(0.2, 0.0)
    plant.run(mgr, 0.2)
    assert plant.joints["fl"].velocity == pytest.approx(0.2 / 0.2, abs=1e-6)
    assert c.odometry.linear == pytest.approx(0.2, abs=1e-3)
    c.set_command(0.0, 1.0)
    plant.run(mgr, 0.2)
    assert plant.joints["fr"].velocity == pytest.approx(1.0 * 0.75 / 2 / 0.2, abs=1e-6)
    assert c.odometry.angular == pytest.approx(1.0, abs=1e-3)


def test_odometry_publishes_at_publish_rate_and_stops_brake():
    plant, hw, mgr = four_wheels()
    c = start(mgr, "base", dd_params(publish_rate=20.0))
    stamps = []

    def take(t):
        if c.pending is not None:
            stamps.append(c.pending["stamp"])
            c.pending = None
    plant.run(mgr, 1.0, record=take)            # updates at 0, 0.001 .. 0.999
    assert stamps == pytest.approx([0.05 * k for k in range(1, 20)])
    c.set_command(0.3, 0.0)
    plant.run(mgr, 0.1)
    mgr.switch([], ["base"], STRICT)
    assert all(hw.joints[n].command == 0.0 for n in hw.order)


def test_ackermann_commands_the_steering_angle_and_rear_wheel_speed():
    joints = [IntegratorJoint("rear", "continuous", inertia=0.01, effort_limit=50.0),
              IntegratorJoint("steer", "revolute", inertia=0.01, lower=-0.6, upper=0.6, velocity_limit=10.0)]
    plant = IntegratorModel(joints)
    hw = RobotHWSim(plant.joints, simple_transmissions({"rear": "VelocityJointInterface",
                                                        "steer": "PositionJointInterface"}))
    mgr = ControllerManager(hw, "/car")
    c = start(mgr, "ack", {"type": ACK, "rear_wheel": "rear", "front_steer": "steer",
                           "wheel_separation_h": 1.5,
                           "wheel_radius": 0.3, "pose_covariance_diagonal": COV,
                           "twist_covariance_diagonal": COV})
    assert c.claimed_resources == [("hardware_interface::VelocityJointInterface", ["rear"]),
                                   ("hardware_interface::PositionJointInterface", ["steer"])]
    c.set_command(0.6, 0.3)
    plant.run(mgr, 0.3)
    assert plant.joints["rear"].velocity == pytest.approx(2.0, abs=1e-6)
    assert plant.joints["steer"].position == pytest.approx(0.3, abs=1e-6)
    assert c.odometry.linear == pytest.approx(0.6, abs=1e-3)
    assert c.odometry.angular == pytest.approx(0.6 * math.tan(0.3) / 1.5, abs=1e-3)


def test_ackermann_needs_its_interfaces():
    joints = [IntegratorJoint("rear_wheel_joint", "continuous"),
              IntegratorJoint("front_steer_joint", "continuous")]
    plant = IntegratorModel(joints)
    hw = RobotHWSim(plant.joints, simple_transmissions({"rear_wheel_joint": "VelocityJointInterface",
                                                        "front_steer_joint": "VelocityJointInterface"}))
    with pytest.raises(ControllerError, match="front_steer_joint.*PositionJointInterface"):
        ControllerManager(hw, "/car").load("ack", {"type": ACK, "wheel_separation_h": 1.0,
                                                   "wheel_radius": 0.3,
                                                   "pose_covariance_diagonal": COV,
                                                   "twist_covariance_diagonal": COV})


# -- diffbot on ODE -----------------------------------------------------------------------------
physics = pytest.importorskip("modrob_sim.physics")


def diffbot(**over):
    """diffbot resting on the ground plane, its DiffDriveController (parameters from
    diffbot_control.yaml, the separation and radius read from the model) running."""
    with open(os.path.join(FIX, "diffbot.urdf")) as f:
        xml = f.read()
    with open(os.path.join(FIX, "diffbot_control.yaml")) as f:
        params = yaml.safe_load(f)["diffbot_velocity_controller"]
    params.update(over)
    world = physics.World(time_step=0.001)
    world.add_sdf(GROUND)
    model = world.add_urdf("diffbot", xml, pose=((0.0, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0)))
    hw = RobotHWSim(model.joints, parse_transmissions(model.source_xml))
    mgr = ControllerManager(hw, "/")
    world.add_step_hook(before=mgr.update)
    c = start(mgr, "diffbot_velocity_controller", params)
    world.step(500)                       # settle on the ground
    return world, model, c


GROUND = """<sdf version="1.6"><world name="default"><include><uri>model://ground_plane</uri></include>
</world></sdf>"""


def yaw_of(q):
    x, y, z, w = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def drive(world, c, linear, angular, seconds):
    """Command (linear, angular) every 0.1 s (as a teleop does) for ``seconds``."""
    for _ in range(int(round(seconds / 0.1))):
        c.set_command(linear, angular)
        world.step(100)


def test_diffbot_reads_its_dimensions_from_the_model():
    world, model, c = diffbot()
    assert c.wheel_separation == pytest.approx(0.4)
    assert c.wheel_radius == pytest.approx(0.1)
    assert model.links["base_link"].pose[0][2] == pytest.approx(0.1, abs=0.005)


def test_a_wheel_without_collision_asks_for_wheel_radius():
    with open(os.path.join(FIX, "wheels.urdf")) as f:
        model = physics.World().add_urdf("wheels", f.read())
    hw = RobotHWSim(model.joints, parse_transmissions(model.source_xml))
    with pytest.raises(ControllerError, match="wheel link 'wheel_v_link' has no collision.*set wheel_radius"):
        ControllerManager(hw, "/wheels").load("base", {
            "type": DD, "left_wheel": "wheel_v", "right_wheel": "wheel_v", "wheel_separation": 0.6,
            "pose_covariance_diagonal": COV,
            "twist_covariance_diagonal": COV})


def test_diffbot_moves_half_a_metre_in_five_seconds_and_odometry_agrees():
    world, model, c = diffbot()
    start_pose = model.links["base_link"].pose
    odo0 = (c.odometry.x, c.odometry.y)
    drive(world, c, 0.1, 0.0, 5.0)
    end = model.links["base_link"].pose
    moved = math.hypot(end[0][0] - start_pose[0][0], end[0][1] - start_pose[0][1])
    assert moved == pytest.approx(0.5, rel=0.03)
    odo = math.hypot(c.odometry.x - odo0[0], c.odometry.y - odo0[1])
    assert abs(odo - moved) < 0.02 * moved


def test_diffbot_turns_two_and_a_half_radians_and_odometry_agrees():
    world, model, c = diffbot()
    yaw0 = yaw_of(model.links["base_link"].pose[1])
    h0 = c.odometry.heading
    drive(world, c, 0.0, 0.5, 5.0)
    turned = yaw_of(model.links["base_link"].pose[1]) - yaw0
    assert turned == pytest.approx(2.5, rel=0.03)
    assert c.odometry.heading - h0 == pytest.approx(turned, rel=0.02)


def test_diffbot_stops_when_the_commands_stop():
    world, model, c = diffbot()
    drive(world, c, 0.3, 0.0, 1.0)
    world.step(1000)                      # cmd_vel_timeout 0.25 s, then braking at 3 m/s^2
    x = model.links["base_link"].pose[0][0]
    world.step(500)
    assert model.links["base_link"].pose[0][0] == pytest.approx(x, abs=1e-3)


def test_a_wall_stops_diffbot_its_wheels_slip_nothing_tunnels():
    """A wall 1 m ahead: commanded 0.3 m/s for 5 s the robot stops at it and keeps pushing (in
    contact, its body still), its wheels turning at the commanded speed (slipping), and it does
    not pass it; its wheel odometry runs on past the wall."""
    world, model, c = diffbot()
    world.add_sdf('<sdf version="1.6"><model name="wall"><static>true</static><pose>1.0 0 0.25 0 0 0</pose>'
                  '<link name="l"><collision name="c"><geometry><box><size>0.1 2 0.5</size></box></geometry>'
                  '</collision></link></model></sdf>')
    drive(world, c, 0.3, 0.0, 5.0)
    front = model.links["base_link"].pose[0][0] + 0.25          # the box's front face
    assert 0.90 < front < 0.951, front                          # the wall's face is at x = 0.95
    assert abs(model.twist[0][0]) < 0.01
    assert any("wall" in (k[0], k[2]) for k in world.contacts())
    assert model.joints["left_wheel"].velocity * 0.1 == pytest.approx(0.3, rel=0.05)
    assert c.odometry.x > 1.2
    drive(world, c, 0.3, 0.0, 2.0)
    assert model.links["base_link"].pose[0][0] + 0.25 < 0.951


def ackbot():
    """ackbot resting on the ground plane, its AckermannSteeringController running with the
    default joint names and the wheelbase and radius read from the model. The steering joint is
    driven through the physics by gazebo_ros_control's pid_gains, as car models do (a position
    joint without gains is set kinematically: that leaned ackbot 4 degrees onto a side ball and
    it turned 30 % less than the bicycle model)."""
    with open(os.path.join(FIX, "ackbot.urdf")) as f:
        xml = f.read()
    world = physics.World(time_step=0.001)
    world.add_sdf(GROUND)
    model = world.add_urdf("ackbot", xml, pose=((0.0, 0.0, 0.1), (0.0, 0.0, 0.0, 1.0)))
    gains = Params({"front_steer_joint": {"p": 100.0, "d": 1.0}}, "/ackbot/gazebo_ros_control/pid_gains")
    hw = RobotHWSim(model.joints, parse_transmissions(model.source_xml), gains)
    mgr = ControllerManager(hw, "/ackbot")
    world.add_step_hook(before=mgr.update)
    c = start(mgr, "ackermann_controller", {"type": ACK, "pose_covariance_diagonal": COV,
                                            "twist_covariance_diagonal": COV})
    world.step(500)
    return world, model, c


def test_ackbot_reads_its_wheelbase_and_radius_from_the_model():
    world, model, c = ackbot()
    assert (c.wheel_separation_h, c.wheel_radius) == pytest.approx((0.4, 0.1))
    assert model.links["base_link"].pose[0][2] == pytest.approx(0.1, abs=0.005)


def test_ackbot_follows_the_bicycle_model_and_its_odometry_agrees():
    world, model, c = ackbot()
    p0 = model.links["base_link"].pose
    yaw0, h0, o0 = yaw_of(p0[1]), c.odometry.heading, (c.odometry.x, c.odometry.y)
    drive(world, c, 0.5, 0.3, 4.0)              # 0.5 m/s, steering angle 0.3 rad
    p1 = model.links["base_link"].pose
    turned = yaw_of(p1[1]) - yaw0
    moved = math.hypot(p1[0][0] - p0[0][0], p1[0][1] - p0[0][1])
    # heading rate v tan(steer) / wheelbase for 4 s, less the first steps' steering and speed ramps
    assert turned == pytest.approx(0.5 * math.tan(0.3) / 0.4 * 4.0, rel=0.05)
    assert c.odometry.heading - h0 == pytest.approx(turned, rel=0.03)
    odo = math.hypot(c.odometry.x - o0[0], c.odometry.y - o0[1])
    assert odo == pytest.approx(moved, rel=0.03)
