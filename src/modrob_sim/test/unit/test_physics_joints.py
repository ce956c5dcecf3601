"""Tier 1: joints of the physics core: limits, continuous, damping, effort clamp, fixed-joint
lumping, mimic, floating, velocity motor, configuration teleports."""
import importlib.util
import math
import os

import pytest

from modrob_sim.physics import World

_FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "physics")
_spec = importlib.util.spec_from_file_location("physics_helpers", os.path.join(_FIX, "physics_helpers.py"))
H = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(H)


def slider_urdf(lower, upper, effort=100.0):
    """A 1 kg block on a vertical prismatic joint (axis z) fixed to the world at z = 1."""
    return H.robot("slider", '<link name="world"/>' + H.box_link("base", 1.0, (0.1, 0.1, 0.1)) +
                   '<joint name="fix" type="fixed"><parent link="world"/><child link="base"/>'
                   '<origin xyz="0 0 1"/></joint>' + H.box_link("block", 1.0, (0.05, 0.05, 0.05)) +
                   H.joint("lift", "prismatic", "base", "block", "0.3 0 0", axis="0 0 1",
                           limit=(lower, upper, effort, 1.0)))


def test_prismatic_joint_stops_at_its_lower_limit_under_gravity():
    world = World()
    m = world.add_urdf("s", slider_urdf(-0.2, 0.2))
    j = m.joints["lift"]
    world.step(1500)
    assert j.position == pytest.approx(-0.2, abs=2e-3)
    assert abs(j.velocity) < 1e-3
    # the block's link frame is where the joint says
    assert m.links["block"].pose[0] == pytest.approx((0.3, 0.0, 1.0 - 0.2), abs=2e-3)


def test_prismatic_effort_pushes_to_the_upper_limit_and_holds():
    world = World()
    m = world.add_urdf("s", slider_urdf(-0.2, 0.2))
    j = m.joints["lift"]
    for _ in range(1500):
        j.set_effort(30.0)  # > m g
        world.step()
    assert j.position == pytest.approx(0.2, abs=3e-3)
    assert j.effort == 30.0


def pendulum_urdf(lower, upper, effort=10.0, damping=0.0, jtype="revolute", axis="0 1 0"):
    rod = H.inertial(1.0, 0.0208667, 0.0208667, 0.0000667, "0 0 -0.25")
    lim = (lower, upper, effort, 10.0) if jtype == "revolute" else (0.0, 0.0, effort, 10.0)
    return H.robot("p", '<link name="world"/>' + H.box_link("pivot", 0.5, (0.05, 0.05, 0.05)) +
                   '<joint name="fix" type="fixed"><parent link="world"/><child link="pivot"/>'
                   '<origin xyz="0 0 1.5"/></joint>' + '<link name="rod">%s</link>' % rod +
                   H.joint("swing", jtype, "pivot", "rod", axis=axis, limit=lim,
                           dynamics=(damping, 0.0)))


def test_revolute_limit_holds_against_gravity_and_effort():
    world = World()
    m = world.add_urdf("p", pendulum_urdf(-0.5, 0.5), joint_positions={"swing": 0.4})
    j = m.joints["swing"]
    peak = 0.0
    for _ in range(2000):
        j.set_effort(8.0)
        world.step()
        peak = max(peak, j.position)
    assert peak < 0.5 + 0.01
    assert j.position == pytest.approx(0.5, abs=0.01)
    j2 = m.joints["swing"]
    for _ in range(2000):
        j2.set_effort(-8.0)
        world.step()
    assert j2.position == pytest.approx(-0.5, abs=0.01)


def wheel_urdf(damping=0.0, effort=5.0, jtype="continuous"):
    """A 2 kg disc (r = 0.1 m) on a vertical continuous joint: I = m r^2 / 2 = 0.01 kg m^2."""
    disc = H.inertial(2.0, 0.0055, 0.0055, 0.01)
    return H.robot("w", '<link name="world"/>' + H.box_link("hub", 1.0, (0.05, 0.05, 0.05)) +
                   '<joint name="fix" type="fixed"><parent link="world"/><child link="hub"/>'
                   '<origin xyz="0 0 1"/></joint>' +
                   '<link name="disc">%s<collision><geometry><cylinder radius="0.1" length="0.02"/>'
                   '</geometry></collision></link>' % disc +
                   H.joint("spin", jtype, "hub", "disc", "0 0 0.1", axis="0 0 1",
                           limit=(0.0, 0.0, effort, 100.0), dynamics=(damping, 0.0)))


def test_continuous_joint_accumulates_past_pi():
    world = World()
    m = world.add_urdf("w", wheel_urdf())
    j = m.joints["spin"]
    last = j.position
    for _ in range(3000):
        j.set_effort(0.05)  # alpha = 5 rad/s^2 -> 22.5 rad after 3 s
        world.step()
        assert j.position >= last - 1e-9  # monotonic: no wrap at +-pi
        last = j.position
    assert j.position == pytest.approx(0.5 * 5.0 * 3.0 ** 2, rel=0.01)
    assert j.velocity == pytest.approx(15.0, rel=0.01)
    # teleporting to a multi-turn position keeps it
    j.set_position(-9.0)
    assert j.position == pytest.approx(-9.0, abs=1e-9)
    assert j.velocity == pytest.approx(0.0, abs=1e-9)
    world.step()
    assert j.position == pytest.approx(-9.0, abs=1e-3)


def test_damping_slows_a_joint_exponentially():
    d, inertia = 0.02, 0.01  # time constant I/d = 0.5 s
    world = World()
    m = world.add_urdf("w", wheel_urdf(damping=d))
    j = m.joints["spin"]
    m.links["disc"].set_twist(((0, 0, 0), (0, 0, 10.0)))
    assert j.velocity == pytest.approx(10.0)
    world.step(1000)
    assert j.velocity == pytest.approx(10.0 * math.exp(-d / inertia * 1.0), rel=0.02)
    # and without damping it keeps turning
    world2 = World()
    m2 = world2.add_urdf("w", wheel_urdf(damping=0.0))
    m2.links["disc"].set_twist(((0, 0, 0), (0, 0, 10.0)))
    world2.step(1000)
    assert m2.joints["spin"].velocity == pytest.approx(10.0, rel=1e-3)


def test_effort_is_clamped_to_the_limit():
    world = World()
    m = world.add_urdf("w", wheel_urdf(effort=0.05))
    j = m.joints["spin"]
    for _ in range(1000):
        j.set_effort(100.0)
        world.step()
    assert j.effort == 0.05
    # alpha = 0.05 / 0.01 = 5 rad/s^2 -> 5 rad/s after 1 s (not 10000)
    assert j.velocity == pytest.approx(5.0, rel=0.01)
    world.step()
    assert j.effort == 0.0  # set_effort lasts one step


def test_set_effort_clamps_every_number_and_refuses_what_is_not_a_finite_one():
    """set_effort's checks, for a float (its fast path) and for everything else: the limit, the
    last call of a step wins, NaN / infinity / not a number / a fixed joint refused by name with
    the command left as it was."""
    import numpy
    world = World()
    m = world.add_urdf("w", wheel_urdf(effort=5.0))
    j = m.joints["spin"]
    for given, applied in ((7.0, 5.0), (-7.0, -5.0), (2.5, 2.5), (3, 3.0), (numpy.float64(9.0), 5.0),
                           (-1e300, -5.0)):
        j.set_effort(123.0)
        j.set_effort(given)             # the last one of the step wins
        world.step()
        assert j.effort == applied, given
    j.effort_limit = None               # no limit
    j.set_effort(20.0)
    world.step()
    assert j.effort == 20.0
    j.effort_limit = 5.0
    for bad, text in ((float("nan"), "not finite"), (float("inf"), "not finite"),
                      (-float("inf"), "not finite"), ("x", "not a number"), (None, "not a number")):
        j.set_effort(1.5)
        with pytest.raises(ValueError, match="joint 'spin' of model 'w': effort .*%s" % text):
            j.set_effort(bad)
        world.step()
        assert j.effort == 1.5, bad     # the command before the refused one stays
    fixed = world.add_urdf("f", H.robot("f", '<link name="world"/>' + H.box_link("a", 1.0, (0.1, 0.1, 0.1)) +
                                        '<joint name="weld" type="fixed"><parent link="world"/>'
                                        '<child link="a"/></joint>'))
    with pytest.raises(ValueError, match="joint 'weld' of model 'f' is fixed: it takes no effort"):
        fixed.joints["weld"].set_effort(1.0)


def test_fixed_joint_child_keeps_its_own_frame():
    body = ('<link name="world"/>' + H.box_link("base", 1.0, (0.1, 0.1, 0.1)) +
            '<joint name="fix" type="fixed"><parent link="world"/><child link="base"/>'
            '<origin xyz="0 0 1"/></joint>' +
            H.box_link("arm", 1.0, (0.5, 0.05, 0.05), xyz="0.25 0 0") +
            H.joint("shoulder", "revolute", "base", "arm", axis="0 0 1", limit=(-3.0, 3.0, 10.0, 5.0)) +
            H.box_link("tool", 0.2, (0.05, 0.05, 0.05)) +
            '<link name="camera_frame"/>' +
            H.joint("tool_mount", "fixed", "arm", "tool", "0.5 0 0", rpy="0 0 1.5707963267948966") +
            H.joint("camera_mount", "fixed", "tool", "camera_frame", "0 0 0.1", rpy="0 0.3 0"))
    world = World()
    m = world.add_urdf("arm", H.robot("arm", body))
    assert set(m.links) == {"base", "arm", "tool", "camera_frame"}
    assert len(m.bodies) == 1  # arm + tool + camera_frame lumped into one body
    assert m.links["tool"].mass == 0.2
    m.set_configuration(["shoulder"], [0.7])
    world.step(10)
    q = m.joints["shoulder"].position
    c, s = math.cos(q), math.sin(q)
    from modrob_sim.physics.transforms import pose_mul, quat_from_rpy
    tool_pose = m.links["tool"].pose
    # exactly the arm frame composed with the fixed joint origins (the joint itself sags a little
    # under gravity, ~2e-5 m, which is ODE's constraint compliance)
    expect = pose_mul(m.links["arm"].pose, ((0.5, 0, 0), quat_from_rpy(0, 0, math.pi / 2)))
    assert tool_pose[0] == pytest.approx(expect[0], abs=1e-9)
    assert tool_pose[1] == pytest.approx(expect[1], abs=1e-9)
    assert tool_pose[0] == pytest.approx((0.5 * c, 0.5 * s, 1.0), abs=1e-4)
    yaw = q + math.pi / 2
    assert tool_pose[1] == pytest.approx((0, 0, math.sin(yaw / 2), math.cos(yaw / 2)), abs=1e-4)
    cam_pose = m.links["camera_frame"].pose
    expect = pose_mul(tool_pose, ((0, 0, 0.1), quat_from_rpy(0, 0.3, 0)))
    assert cam_pose[0] == pytest.approx(expect[0], abs=1e-9)
    assert cam_pose[1] == pytest.approx(expect[1], abs=1e-9)
    assert cam_pose[0] == pytest.approx((0.5 * c, 0.5 * s, 1.1), abs=1e-4)
    # the lumped inertia: the COM of arm (1 kg at 0.25) + tool (0.2 kg at 0.5)
    com_x = (1.0 * 0.25 + 0.2 * 0.5) / 1.2
    body_pos = m.links["arm"]._body.getPosition()
    assert body_pos == pytest.approx((com_x * c, com_x * s, 1.0), abs=1e-4)


def test_mimic_joint_follows_its_master():
    body = ('<link name="world"/>' + H.box_link("base", 1.0, (0.1, 0.1, 0.1)) +
            '<joint name="fix" type="fixed"><parent link="world"/><child link="base"/>'
            '<origin xyz="0 0 1"/></joint>' +
            H.box_link("finger_l", 0.05, (0.02, 0.02, 0.08)) +
            H.box_link("finger_r", 0.05, (0.02, 0.02, 0.08)) +
            H.joint("left", "prismatic", "base", "finger_l", "0 0.05 0.1", axis="0 1 0",
                    limit=(-0.04, 0.04, 20.0, 0.5)) +
            H.joint("right", "prismatic", "base", "finger_r", "0 -0.05 0.1", axis="0 1 0",
                    limit=(-0.04, 0.04, 20.0, 0.5), mimic=("left", -1.0, 0.001)))
    world = World()
    m = world.add_urdf("g", H.robot("g", body))
    left, right = m.joints["left"], m.joints["right"]
    assert right.mimic == ("left", -1.0, 0.001)
    for i in range(1500):
        left.set_effort(0.5 if i < 800 else -0.5)
        world.step()
        if i in (400, 799, 1499):
            assert right.position == pytest.approx(-left.position + 0.001, abs=1.5e-3), i
    assert abs(left.position) > 0.02
    m.set_configuration(["left"], [0.03])
    assert right.position == pytest.approx(-0.029, abs=1e-9)


def test_floating_joint_child_falls_freely_at_g():
    body = (H.box_link("base", 1.0, (0.1, 0.1, 0.1)) + H.box_link("drone", 0.5, (0.1, 0.1, 0.02)) +
            H.joint("free", "floating", "base", "drone", "0 0 2"))
    world = World()
    m = world.add_urdf("f", H.robot("f", body), pose=((0, 0, 100.0), (0, 0, 0, 1)))
    assert len(m.bodies) == 2 and not m.articulated
    n, dt = 400, world.time_step
    world.step(n)
    t = world.time
    for ln, z0 in (("base", 100.0), ("drone", 102.0)):
        # ODE's semi-implicit Euler: z_n = z0 - g dt^2 n (n + 1) / 2 (= g t^2 / 2 + g dt t / 2)
        assert m.links[ln].pose[0][2] == pytest.approx(z0 - 9.81 * dt * dt * n * (n + 1) / 2, abs=1e-9)
        assert m.links[ln].pose[0][2] == pytest.approx(z0 - 0.5 * 9.81 * t * t, abs=3e-3)
        assert m.links[ln].twist[0][2] == pytest.approx(-9.81 * t, rel=1e-6)


def test_velocity_target_motor_and_velocity_limit():
    world = World()
    m = world.add_urdf("w", wheel_urdf())
    j = m.joints["spin"]
    j.set_velocity_target(3.0, 1.0)
    world.step(500)
    assert j.velocity == pytest.approx(3.0, abs=1e-3)
    j.set_velocity_target(1000.0, 1.0)  # clamped to the URDF velocity limit (100)
    world.step(2000)
    assert j.velocity == pytest.approx(100.0, abs=0.5)
    j.set_velocity_target(0.0, 0.0)  # motor off: coasts
    v = j.velocity
    world.step(100)
    assert j.velocity == pytest.approx(v, rel=1e-3)


def test_joint_friction_holds_below_and_slips_above():
    world = World()
    xml = wheel_urdf().replace('damping="0.0" friction="0.0"', 'damping="0.0" friction="0.2"')
    m = world.add_urdf("w", xml)
    j = m.joints["spin"]
    assert j.friction == 0.2
    for _ in range(500):
        j.set_effort(0.15)
        world.step()
    assert abs(j.position) < 1e-3
    for _ in range(500):
        j.set_effort(0.3)
        world.step()
    # net 0.1 N m on 0.01 kg m^2: 10 rad/s^2 -> 5 rad/s after 0.5 s
    assert j.velocity == pytest.approx(5.0, rel=0.03)


def test_set_configuration_while_running_teleports_and_zeroes_velocity():
    world = World()
    m = world.add_urdf("p", pendulum_urdf(-3.0, 3.0), joint_positions={"swing": 1.0})
    j = m.joints["swing"]
    world.step(200)
    assert abs(j.velocity) > 0.5
    m.set_configuration(["swing"], [-0.3])
    assert j.position == pytest.approx(-0.3, abs=1e-9)
    assert j.velocity == pytest.approx(0.0, abs=1e-9)
    world.step(1)
    assert j.position == pytest.approx(-0.3, abs=1e-4)
    with pytest.raises(ValueError, match="no joint 'elbow'"):
        m.set_configuration(["elbow"], [0.0])
    with pytest.raises(ValueError, match="not finite"):
        m.set_configuration(["swing"], [float("nan")])


def test_revolute_limits_beyond_pi_hold_across_the_wrap():
    world = World()
    m = world.add_urdf("w", wheel_urdf(jtype="revolute").replace(
        'lower="0.0" upper="0.0"', 'lower="-4.0" upper="4.0"'))
    j = m.joints["spin"]
    assert (j.lower, j.upper) == (-4.0, 4.0)
    for _ in range(3000):
        j.set_effort(0.02)
        world.step()
    assert j.position == pytest.approx(4.0, abs=0.02)  # past +pi, stopped at the limit
    for _ in range(4000):
        j.set_effort(-0.02)
        world.step()
    assert j.position == pytest.approx(-4.0, abs=0.02)


def _squeezing_pair(effort):
    """Two fingers on prismatic joints (finger 2's frame turned by pi, so both close with q
    falling), finger 2 mimicking finger 1 (multiplier 1), around a free 60 mm, 50 g box."""
    body = ('<link name="world"/>' + H.box_link("base", 0.3, (0.05, 0.1, 0.05)) +
            '<joint name="fix" type="fixed"><parent link="world"/><child link="base"/>'
            '<origin xyz="0 0 1"/></joint>' +
            H.box_link("f1", 0.05, (0.05, 0.02, 0.05), gazebo_mu=1.0, xyz="0 0.01 0") +
            H.box_link("f2", 0.05, (0.05, 0.02, 0.05), gazebo_mu=1.0, xyz="0 0.01 0") +
            H.joint("finger1", "prismatic", "base", "f1", "0 0 0.1", axis="0 1 0",
                    limit=(0.01, 0.05, effort, 0.1)) +
            H.joint("finger2", "prismatic", "base", "f2", "0 0 0.1", rpy="0 0 3.141592653589793",
                    axis="0 1 0", limit=(0.01, 0.05, effort, 0.1), mimic=("finger1", 1.0, 0.0)))
    world = World(time_step=0.001, gravity=(0.0, 0.0, 0.0))
    m = world.add_urdf("g", H.robot("g", body), joint_positions={"finger1": 0.05})
    obj = world.add_urdf("obj", H.robot("obj", H.box_link("box", 0.05, (0.06, 0.06, 0.06), gazebo_mu=1.0)),
                         pose=((0.0, 0.003, 1.1), (0, 0, 0, 1)))
    return world, m, obj


@pytest.mark.parametrize("effort", [3.0, 7.0])
def test_mimic_finger_pair_squeezing_an_object_keeps_the_coupling(effort):
    """The mimic coupling is a linkage, not a second force-limited actuator: under the full grip
    force (finger 1's effort limit) and a sideways shove on the object, q2 stays m*q1 + o within
    0.5 mm and the object is centred between the fingers."""
    world, m, obj = _squeezing_pair(effort)
    f1, f2 = m.joints["finger1"], m.joints["finger2"]
    worst = 0.0
    for i in range(3000):
        # a PD towards 20 mm (past the object) that saturates at the effort limit: the grip force
        f1.set_effort(-effort / 0.005 * (f1.position - 0.02) - 10.0 * f1.velocity)
        if 1000 <= i < 2000:                  # a shove of 3 N towards finger 2, then 3 N back
            obj.links["box"].add_wrench((0.0, -3.0 if i < 1500 else 3.0, 0.0), (0.0, 0.0, 0.0),
                                        duration=0.001)
        world.step()
        if i > 300:
            worst = max(worst, abs(f2.position - f1.position))
    assert world.pop_events() == []
    assert worst < 0.0005
    assert f1.position == pytest.approx(0.03, abs=0.001)     # resting on the 60 mm box
    assert abs(f1.effort) == pytest.approx(effort, rel=1e-6)
    assert abs(obj.links["box"].pose[0][1]) < 0.001          # centred between the fingers
