"""Tier 1: the gazebo_plugins drives' cores (modrob_sim.drives) on the physics core, with our own
robots in the styles of a TurtleBot3 (diff drive) and a Husky (skid steer): the distances and
angles driven, odometry against ground truth, a wall that stops the robot, the rest pose."""
import math
import os

import pytest

from modrob_sim.errors import PluginError
from modrob_sim.gazebo_ros.plugin_base import ModelPlugin
from modrob_sim.gazebo_ros.plugin_host import PluginHost
from modrob_sim.gazebo_ros.plugins import register_plugin, unregister_plugin
from modrob_sim.physics import World
from modrob_sim.physics.transforms import rpy_from_quat
from modrob_sim.drives.diff_drive import DiffDrive
from modrob_sim.drives.skid_steer import SkidSteer

FIX = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "fixtures", "drives")
GROUND = ('<sdf version="1.6"><world name="w"><include><uri>model://ground_plane</uri></include>'
          '%s</world></sdf>')
WALL = ('<model name="wall"><static>true</static><pose>%r 0 0.25 0 0 0</pose><link name="l">'
        '<collision name="c"><geometry><box><size>0.1 2 0.5</size></box></geometry></collision>'
        '</link></model>')


def fixture(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


class Bot(object):
    """A world with the ground (and props), one robot whose drive plugin is the core under test
    driven by ``command``, and the plugin host stepping it as the /gazebo node does."""

    def __init__(self, urdf, filename, core_class, props="", native=None, edit=None, command=(0.0, 0.0),
                 seed=0, due=False):
        """``due``: the core's update runs at its due times (``core.next_due()``, and at the next
        step after :meth:`send`), as its ROS plugin declares them; else at every step."""
        bot = self

        class CorePlugin(ModelPlugin):
            def load(self, model, spec, context):
                bot.core = core_class(self)

            def before_step(self, t, dt):
                bot.calls += 1
                bot.fresh = False
                if bot.core.update(t, dt, bot.command, *bot.extra) and hasattr(bot.core, "odometry"):
                    bot.readings.append((t, bot.core.odometry()))

            if due:
                def before_due(self):
                    return None if bot.fresh else bot.core.next_due()

        self.command = command
        self.extra = ()
        self.calls = 0
        self.fresh = False
        self.readings = []             # (t, the core's odometry) at the updates that publish
        self.filename = filename
        register_plugin(filename, CorePlugin)
        self.world = World(native=native, seed=seed)
        self.world.add_sdf(GROUND % props)
        text = fixture(urdf)
        if edit:
            text = edit(text)
        self.model = self.world.add_urdf("bot", text)
        self.host = PluginHost(self.world, "/gazebo", lambda uri: uri)
        self.host.load(self.model)
        self.world.add_step_hook(before=self.host.before_step, after=self.host.after_step,
                                 before_due=self.host.before_due, after_due=self.host.after_due)

    def send(self, command, *extra):
        """A new command, as a ROS callback stores it (and wakes the loop)."""
        self.command, self.extra, self.fresh = command, extra, True

    def close(self):
        unregister_plugin(self.filename)

    def drive(self, command, seconds):
        """Drive ``command`` for ``seconds``; returns (distance in the plane, yaw turned)."""
        self.command = command
        (p0, q0) = self.model.pose
        last = rpy_from_quat(q0)[2]
        turned = 0.0
        for _ in range(int(round(seconds / 0.05))):
            self.world.step(50)
            yaw = rpy_from_quat(self.model.pose[1])[2]
            turned += (yaw - last + math.pi) % (2.0 * math.pi) - math.pi
            last = yaw
        (p1, _q1) = self.model.pose
        return math.hypot(p1[0] - p0[0], p1[1] - p0[1]), turned


@pytest.fixture
def diff_bot():
    bots = []

    def make(**kw):
        b = Bot("diff_bot.urdf", "libgazebo_ros_diff_drive.so", DiffDrive, **kw)
        bots.append(b)
        b.world.step(500)
        return b
    yield make
    for b in bots:
        b.close()


@pytest.fixture
def skid_bot():
    bots = []

    def make(**kw):
        b = Bot("skid_bot.urdf", "libgazebo_ros_skid_steer_drive.so", SkidSteer, **kw)
        bots.append(b)
        b.world.step(500)
        return b
    yield make
    for b in bots:
        b.close()


def assert_at_rest(model, height, tol=0.0015):
    (p, q) = model.pose
    (v, w) = model.twist
    roll, pitch, _yaw = rpy_from_quat(q)
    assert abs(roll) < 0.003 and abs(pitch) < 0.003, (roll, pitch)
    assert abs(p[2] - height) < tol, p[2]
    assert math.sqrt(sum(x * x for x in v)) < 2e-3 and math.sqrt(sum(x * x for x in w)) < 1e-2, (v, w)


def test_diff_bot_rests_level_and_still_on_its_wheels(diff_bot):
    """base_footprint on the ground (1 mm minDepth of the wheels), level, not creeping."""
    b = diff_bot()
    b.world.step(1500)
    assert_at_rest(b.model, -0.0005)
    (p0, q0) = b.model.pose
    b.world.step(2000)
    assert math.dist(p0, b.model.pose[0]) < 1e-3
    assert abs(rpy_from_quat(b.model.pose[1])[2] - rpy_from_quat(q0)[2]) < 2e-3


TB3_PHYSICS = ('<physics type="ode"><max_step_size>0.001</max_step_size><ode><solver><type>quick</type>'
               '<iters>150</iters><sor>1.4</sor></solver><constraints><cfm>0.00001</cfm><erp>0.2</erp>'
               '<contact_max_correcting_vel>2000</contact_max_correcting_vel>'
               '<contact_surface_layer>0.01</contact_surface_layer></constraints></ode></physics>')


@pytest.mark.parametrize("native", [None, False])
def test_a_1_cm_surface_layer_does_not_sink_wheels_with_their_own_min_depth(diff_bot, native):
    """turtlebot3_gazebo's worlds set contact_surface_layer 1 cm; its links give minDepth 1 mm. As
    in Gazebo the links' minDepth replaces the layer: the robot stays level on its wheels (the
    layer let the wheels and caster creep 6 mm in, the robot pitched 0.07 rad)."""
    b = diff_bot(native=native, props=TB3_PHYSICS)
    b.drive((0.2, 0.0), 2.0)
    b.drive((0.0, 0.0), 3.0)
    assert_at_rest(b.model, -0.0005)


@pytest.mark.parametrize("native", [None, False])
@pytest.mark.parametrize("v", [0.1, -0.1])
def test_diff_drive_at_0_1_m_s_for_5_s_moves_0_5_m(diff_bot, native, v):
    b = diff_bot(native=native)
    distance, turned = b.drive((v, 0.0), 5.0)
    assert distance == pytest.approx(0.5, rel=0.03)
    assert abs(turned) < 0.02


@pytest.mark.parametrize("w", [0.5, -0.5])
def test_diff_drive_at_0_5_rad_s_for_5_s_turns_2_5_rad(diff_bot, w):
    b = diff_bot()
    distance, turned = b.drive((0.0, w), 5.0)
    assert turned == pytest.approx(5.0 * w, rel=0.03)
    assert distance < 0.02


@pytest.mark.parametrize("source", ["world", "encoder"])
def test_diff_drive_odometry_agrees_with_ground_truth(diff_bot, source):
    """An arc of 0.15 m/s and 0.3 rad/s for 6 s: the odometry's pose is within 2 % of the
    distance driven of the robot's true pose (encoder odometry integrates the wheels)."""
    b = diff_bot(edit=lambda s: s.replace("<odometrySource>world</odometrySource>",
                                          "<odometrySource>%s</odometrySource>" % source))
    (p0, q0) = b.model.pose
    distance, _turned = b.drive((0.15, 0.3), 6.0)
    assert distance > 0.6
    odom = b.core.odometry()
    (p1, q1) = b.model.pose
    if source == "encoder":   # it starts at zero where the robot stood when the drive loaded
        (p1, q1) = ((p1[0] - p0[0], p1[1] - p0[1], 0.0), q1)
    assert math.hypot(odom.position[0] - p1[0], odom.position[1] - p1[1]) < 0.02 * 0.15 * 6.0
    yaw_odom = rpy_from_quat(odom.orientation)[2]
    yaw_true = rpy_from_quat(q1)[2] - (rpy_from_quat(q0)[2] if source == "encoder" else 0.0)
    assert abs((yaw_odom - yaw_true + math.pi) % (2 * math.pi) - math.pi) < 0.02
    assert odom.linear[0] == pytest.approx(0.15, rel=0.05)
    assert odom.angular[2] == pytest.approx(0.3, rel=0.05)


def test_encoder_odometry_at_the_updates_matches_integrating_at_every_step(diff_bot):
    """Encoder odometry integrates the wheels' travel along one arc per update (the 30 Hz
    updates: about 31 hook calls per simulated second where it ran 1000). At every update, in
    3.5 s of turning, accelerating and braking: against the same rule at every step the position
    differs by the change of the arc within an update (below 1e-6 m; the heading, a sum, by
    rounding); against gazebo_plugins' rule (the wheels' speeds at each step's start times the
    step) by that rule's lag of about one step (below 5e-4 m and 1e-3 rad)."""
    encoder = dict(edit=lambda s: s.replace("<odometrySource>world</odometrySource>",
                                            "<odometrySource>encoder</odometrySource>"))
    due = diff_bot(due=True, **encoder)
    every = diff_bot(**encoder)
    gazebo = {"x": 0.0, "y": 0.0, "th": 0.0}
    r, b = every.core.radius, every.core.cfg.wheel_separation
    left, right = every.core.joints
    at_updates = []

    def per_step(t, dt):            # gazebo_plugins' UpdateOdometryEncoder, at every step
        if every.readings and every.readings[-1][0] == t:
            at_updates.append((gazebo["x"], gazebo["y"], gazebo["th"]))
        sl, sr = left.velocity * r * dt, right.velocity * r * dt
        heading = gazebo["th"] + (sr - sl) / (2.0 * b)
        gazebo["x"] += 0.5 * (sl + sr) * math.cos(heading)
        gazebo["y"] += 0.5 * (sl + sr) * math.sin(heading)
        gazebo["th"] += (sr - sl) / b
    every.world.add_step_hook(before=per_step)
    for bot in (due, every):
        bot.calls = 0
        bot.readings = []
        for command, seconds in (((0.15, 0.3), 1.5), ((0.2, -0.6), 1.0), ((0.0, 0.0), 1.0)):
            bot.drive(command, seconds)
    assert every.calls == 3500
    if due.world.native:
        assert due.calls <= 31 * 3.5, due.calls
    assert due.model.pose == every.model.pose          # the same physics
    assert [t for t, _ in due.readings] == [t for t, _ in every.readings] and len(at_updates) > 100
    worst = [0.0] * 4
    for (_t, a), (_t2, e), g in zip(due.readings, every.readings, at_updates):
        yaw = rpy_from_quat(a.orientation)[2]
        worst = [max(worst[0], math.dist(a.position[:2], e.position[:2])),
                 max(worst[1], abs(yaw - rpy_from_quat(e.orientation)[2])),
                 max(worst[2], math.dist(a.position[:2], g[:2])), max(worst[3], abs(yaw - g[2]))]
    assert math.hypot(*due.readings[-1][1].position[:2]) > 0.3
    assert worst[0] < 1e-6 and worst[1] < 1e-12, worst      # measured 3.5e-7 m, 3e-16 rad
    assert worst[2] < 5e-4 and worst[3] < 1e-3, worst       # measured 3.0e-4 m, 7.0e-4 rad


def test_a_wall_stops_the_diff_bot_its_wheels_slip_nothing_tunnels(diff_bot):
    """A wall 0.5 m ahead: the robot drives into it at 0.2 m/s and stays in front of it, pushing
    (contacts with the wall) while its wheels keep turning (slip)."""
    b = diff_bot(props=WALL % 0.5)
    b.drive((0.2, 0.0), 5.0)
    front = b.model.links["base_link"].pose[0][0] - 0.030 + 0.065    # the box's front face
    assert 0.40 < front < 0.451, front              # the wall's face is at x = 0.45
    assert abs(b.model.twist[0][0]) < 0.01
    assert any("wall" in (c[0], c[2]) for c in b.world.contacts())
    wheel = b.model.joints["wheel_left_joint"]
    assert wheel.velocity * 0.033 > 0.1, wheel.velocity     # still turning: slipping
    b.drive((0.2, 0.0), 2.0)
    assert b.model.links["base_link"].pose[0][0] - 0.030 + 0.065 < 0.451


def test_wheel_acceleration_limits_the_start(diff_bot):
    """wheelAcceleration 1 m/s^2: 0.1 s after a 0.3 m/s command the robot goes about 0.1 m/s."""
    b = diff_bot()
    b.command = (0.3, 0.0)
    b.world.step(130)          # the next update at 30 Hz comes within 33 ms, then 0.1 s
    assert 0.04 < b.model.twist[0][0] < 0.2
    b.world.step(1000)
    assert b.model.twist[0][0] == pytest.approx(0.3, rel=0.05)


def test_diff_drive_configuration_errors_name_the_tag():
    for edit, text in ((lambda s: s.replace("<leftJoint>wheel_left_joint", "<leftJoint>no_such"),
                        "<leftJoint> 'no_such' is not a joint"),
                       (lambda s: s.replace("<rightJoint>wheel_right_joint", "<rightJoint>caster_joint"),
                        "caster_joint' is a fixed joint"),
                       (lambda s: s.replace("<odometrySource>world", "<odometrySource>gps"),
                        "<odometrySource> 'gps'"),
                       (lambda s: s.replace("<wheelDiameter>0.066", "<wheelDiameter>-1"),
                        "<wheelDiameter> must be positive")):
        loaded = []

        class Probe(ModelPlugin):
            def load(self, model, spec, context):
                try:
                    DiffDrive(self)
                except PluginError as e:
                    loaded.append(str(e))
        register_plugin("libgazebo_ros_diff_drive.so", Probe)
        try:
            w = World()
            m = w.add_urdf("bot", edit(fixture("diff_bot.urdf")))
            PluginHost(w, "/gazebo", lambda u: u).load(m)
        finally:
            unregister_plugin("libgazebo_ros_diff_drive.so")
        assert len(loaded) == 1 and text in loaded[0] and "model 'bot'" in loaded[0], loaded


def test_skid_bot_spawned_at_z_0_rests_level_at_its_wheel_radius(skid_bot):
    """Spawned with its wheels 130 mm in the ground, as such robots' launch files do: pushed out
    at once (Gazebo's split contact correction), then level and still at 130 mm (less the 1 mm
    surface layer)."""
    b = skid_bot()
    b.world.step(1000)
    assert_at_rest(b.model, 0.129)


@pytest.mark.parametrize("v", [0.1, -0.1])
def test_skid_steer_at_0_1_m_s_for_5_s_moves_0_5_m(skid_bot, v):
    b = skid_bot()
    distance, turned = b.drive((v, 0.0), 5.0)
    assert distance == pytest.approx(0.5, rel=0.03)
    assert abs(turned) < 0.02


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("w", [0.5, -0.5])
def test_skid_steer_at_0_5_rad_s_for_5_s_turns_2_5_rad(skid_bot, w, seed):
    """On the spot, the wheels dragged sideways: with Gazebo's contact rules (each wheel's fdir1
    turning with it) the turn depends on the wheels' phase and the solver's row order, within
    +-15 % here at the effective wheelSeparation (docs/drives.md). It is 3 % for the diff drive."""
    b = skid_bot(seed=seed)
    _distance, turned = b.drive((0.0, w), 5.0)
    assert turned == pytest.approx(5.0 * w, rel=0.15)


def test_a_wall_stops_the_skid_bot(skid_bot):
    b = skid_bot(props=WALL % 1.0)
    b.drive((0.3, 0.0), 5.0)
    front = b.model.pose[0][0] + 0.475
    assert 0.90 < front < 0.951, front
    assert abs(b.model.twist[0][0]) < 0.01
    odom = b.core.odometry()
    assert odom.position[0] == pytest.approx(b.model.pose[0][0], abs=1e-9)
    assert odom.position[2] == 0.0


def test_joint_state_publisher_reads_its_comma_separated_joints_at_its_rate(skid_bot):
    from modrob_sim.drives.joint_states import JointStates
    readings = []

    class Probe(ModelPlugin):
        def load(self, model, spec, context):
            self.core = JointStates(self)

        def before_step(self, t, dt):
            r = self.core.update(t)
            if r is not None:
                readings.append((t, r))
    register_plugin("libgazebo_ros_joint_state_publisher.so", Probe)
    try:
        b = skid_bot()
        b.command = (0.2, 0.0)
        b.world.step(1000)
    finally:
        unregister_plugin("libgazebo_ros_joint_state_publisher.so")
    names = [n for n, _p, _v in readings[-1][1]]
    assert names == ["front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"]
    times = [t for t, _r in readings if t > 0.6]
    assert all(abs((b2 - b1) - 0.02) < 1e-6 for b1, b2 in zip(times, times[1:]))     # 50 Hz
    _n, position, velocity = readings[-1][1][0]
    assert velocity == pytest.approx(0.2 / 0.165, rel=0.05) and position > 0.5


def test_joint_state_publisher_names_a_missing_joint():
    errors = []
    from modrob_sim.drives.joint_states import JointStates

    class Probe(ModelPlugin):
        def load(self, model, spec, context):
            try:
                JointStates(self)
            except PluginError as e:
                errors.append(str(e))
    register_plugin("libgazebo_ros_joint_state_publisher.so", Probe)
    try:
        w = World()
        urdf = fixture("skid_bot.urdf").replace("rear_right_wheel</jointName>", "rear_right_whel</jointName>")
        m = w.add_urdf("bot", urdf)
        PluginHost(w, "/gazebo", lambda u: u).load(m)
    finally:
        unregister_plugin("libgazebo_ros_joint_state_publisher.so")
    assert len(errors) == 1 and "rear_right_whel" in errors[0], errors


def test_planar_move_moves_the_base_holonomically_and_times_out():
    """linear.x, linear.y and angular.z move the base in its heading; 0.5 s after the last
    command (cmdTimeout, shortened here from the fixture's 8 s) it stops."""
    from modrob_sim.drives.planar_move import PlanarMove
    b = Bot("planar_bot.urdf", "libgazebo_ros_planar_move.so", PlanarMove, command=(0.0, 0.0, 0.0),
            edit=lambda text: text.replace("<cmdTimeout>8.0</cmdTimeout>", "<cmdTimeout>0.5</cmdTimeout>"))
    try:
        b.world.step(200)
        b.extra = (b.world.time,)          # when the command came
        b.command = (0.2, 0.1, 0.3)
        b.world.step(400)                  # within the timeout
        yaw = rpy_from_quat(b.model.pose[1])[2]
        odom = b.core.odometry()
        assert yaw == pytest.approx(0.3 * 0.4, abs=0.01)
        assert odom.linear[0] == pytest.approx(0.2, abs=0.01)
        assert odom.linear[1] == pytest.approx(0.1, abs=0.01)
        assert odom.angular[2] == pytest.approx(0.3, abs=0.02)
        b.world.step(300)                  # past it: stopped
        assert math.hypot(*b.model.twist[0][:2]) < 0.01
    finally:
        b.close()


class EveryStepPlanarMove(object):
    """The reference: gazebo_plugins' planar move as it ran here before the World's model
    actuator, the base's velocity set from Python before every step (same cmdTimeout rule)."""
    joints = ()

    def __init__(self, plugin):
        self.model = plugin.model

    def update(self, t, dt, command, command_time=None):
        vx, vy, wz = command if command_time is not None and t - command_time <= 0.5 else (0.0, 0.0, 0.0)
        yaw = rpy_from_quat(self.model.pose[1])[2]
        c, s = math.cos(yaw), math.sin(yaw)
        self.model.set_twist(((vx * c - vy * s, vy * c + vx * s, 0.0), (0.0, 0.0, wz)))


@pytest.mark.parametrize("native", [None, False])
def test_planar_move_runs_in_python_at_its_due_times_and_moves_as_at_every_step(native):
    """The World's PLANAR_VELOCITY actuator holds the base's velocity between the plugin's
    updates: the plugin's Python runs at its 20 Hz odometry, at a new command and at the 0.5 s
    cmdTimeout (at most 25 times per simulated second, where it ran 1000; on the native backend),
    and the base moves bit for bit as setting its twist in Python before every step moves it."""
    from modrob_sim.drives.planar_move import PlanarMove
    timeout = dict(edit=lambda text: text.replace("<cmdTimeout>8.0</cmdTimeout>",
                                                  "<cmdTimeout>0.5</cmdTimeout>"),
                   command=(0.0, 0.0, 0.0), native=native)
    due = Bot("planar_bot.urdf", "libgazebo_ros_planar_move.so", PlanarMove, due=True, **timeout)
    due.close()
    ref = Bot("planar_bot.urdf", "libgazebo_ros_planar_move.so", EveryStepPlanarMove, **timeout)
    ref.close()
    for b in (due, ref):
        b.world.step(200)
        b.send((0.2, 0.1, 0.3), b.world.time)
        b.world.step(400)
        b.send((-0.1, 0.2, -0.5), b.world.time)
        b.world.step(1400)           # 0.5 s of it, then stopped by the timeout
    assert ref.calls == 2000
    if due.world.native:           # (the pure-Python backend calls every hook at every step)
        assert due.calls <= 25 * 2.0, due.calls
        assert due.world.native_steps >= 2000 - due.calls
    assert due.model.pose == ref.model.pose and due.model.twist == ref.model.twist
    assert math.hypot(*due.model.twist[0][:2]) < 0.01          # stopped
    assert math.hypot(*due.model.pose[0][:2]) > 0.1            # after moving
    odom = due.core.odometry()
    assert odom.position[:2] == pytest.approx(due.model.pose[0][:2], abs=1e-3)


def test_tricycle_drives_straight_and_turns_on_its_steering_angle():
    from modrob_sim.drives.tricycle import Tricycle
    b = Bot("trike_bot.urdf", "libgazebo_ros_tricycle_drive.so", Tricycle)
    try:
        b.world.step(500)
        distance, turned = b.drive((0.2, 0.0), 3.0)
        assert distance == pytest.approx(0.6, rel=0.05) and abs(turned) < 0.02
        odom = b.core.odometry()           # encoders on the free rear wheels
        assert math.hypot(*odom.position[:2]) == pytest.approx(distance, rel=0.02)
        b.drive((0.2, 0.3), 0.3)
        assert b.core.steering.position == pytest.approx(0.3, abs=0.02)
        _d, turned = b.drive((0.2, 0.3), 3.0)
        # the rear axle turns at v sin(angle) / wheelbase about the turn's centre
        assert turned == pytest.approx(3.0 * 0.2 * math.sin(0.3) / 0.5, rel=0.1)
    finally:
        b.close()


def ramp_pose(angle, along=1.0, up=0.001):
    """base_footprint on a ramp tilted by ``angle`` about y (descending towards +x, its top through
    the origin), ``along`` metres up the slope (clear of the ground plane), facing uphill."""
    from modrob_sim.physics.transforms import quat_from_axis_angle, quat_mul
    n = (math.sin(angle), 0.0, math.cos(angle))
    q = quat_mul(quat_from_axis_angle((0.0, 1.0, 0.0), angle), quat_from_axis_angle((0.0, 0.0, 1.0), math.pi))
    return ((-along * math.cos(angle) + up * n[0], 0.0, along * math.sin(angle) + up * n[2]), q)


@pytest.fixture
def ramp_bot():
    bots = []

    def make(angle, fdir1=True):
        import importlib.util
        spec = importlib.util.spec_from_file_location(
            "physics_helpers", os.path.join(os.path.dirname(FIX), "physics", "physics_helpers.py"))
        helpers = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(helpers)
        b = Bot("diff_bot.urdf", "libgazebo_ros_diff_drive.so", DiffDrive)
        bots.append(b)
        b.world.remove_model("bot")
        b.world.add_urdf("ramp", helpers.ramp(angle, 1.0))
        text = fixture("diff_bot.urdf")
        if not fdir1:
            text = text.replace("<fdir1>1 0 0</fdir1>", "")
        b.model = b.world.add_urdf("bot", text, pose=ramp_pose(angle))
        b.host.load(b.model)
        b.world.step(500)
        return b
    yield make
    for b in bots:
        b.close()


def test_the_wheel_motors_hold_the_robot_on_a_slope_and_drive_it_up(ramp_bot):
    """On a 10 degree ramp the stopped wheels' motors hold the robot (it does not roll down); at
    0.1 m/s it climbs 0.3 m in 3 s, along the slope. The wheels without fdir1: with Gazebo's rule a
    fdir1 that turns with the wheel makes the traction depend on the wheel's angle, and this robot
    then spins its wheels on the slope (the next test)."""
    angle = math.radians(10.0)
    b = ramp_bot(angle, fdir1=False)
    (p0, _q) = b.model.pose
    b.world.step(2000)
    assert math.dist(p0, b.model.pose[0]) < 0.003
    distance, _turned = b.drive((0.1, 0.0), 3.0)
    (p1, _q) = b.model.pose
    assert p1[2] - p0[2] == pytest.approx(math.sin(angle) * 0.3, rel=0.1)      # uphill
    assert math.dist(p0, p1) == pytest.approx(0.3, rel=0.05)


def test_with_gazebos_fdir1_rule_the_wheels_spin_on_a_slope(ramp_bot):
    """The same robot with fdir1 1 0 0 on its wheels, as TurtleBot3's: the first friction row turns
    with the wheel (not projected on the ground, as Gazebo hands it to ODE), the traction falls
    away at some wheel angles and the wheels spin: it climbs far less than commanded."""
    angle = math.radians(10.0)
    b = ramp_bot(angle)
    (p0, _q) = b.model.pose
    b.drive((0.1, 0.0), 3.0)
    assert math.dist(p0, b.model.pose[0]) < 0.2
    assert b.model.joints["wheel_left_joint"].velocity * 0.033 > 0.09
