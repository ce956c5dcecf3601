"""The due times of the group, gripper, mobile-base, velocity and kinematic position controllers
(docs/controllers.md, "When controllers run"): stepped as the node steps them (natively between
their due times) they give the steps of calling every update at every step -- the same states,
efforts, actuator internals and messages, bit for bit (the mobile base's odometry pose to
rounding: it integrates the travel since its last update along one arc) -- and most steps are
made in C."""
import math
import os

import pytest

from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics.due import IDLE_LOOK
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.manager import STRICT

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


def fixture(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


def snapshot(rig):
    acts = [(a.pid_state(), a.last, a.command, a.gains.as_dict()) for a in rig.world.actuators]
    joints = [(j.position, j.velocity, j.effort) for j in rig.model.joints_in_order]
    return (rig.world.time, rig.world.iterations, rig.world.state_digest(), acts, joints)


def run(rig, steps, events):
    """``steps`` steps in passes of 10 (as the node's loop), ``events[i](rig)`` called before
    step ``i``."""
    marks = sorted(events) + [steps]
    while rig.world.iterations < steps:
        i = rig.world.iterations
        if i in events:
            events[i](rig)
        n = min(10, min(m for m in marks if m > i) - i)
        rig.step(n)
    return rig


class GroupArm(ControlRig):
    """The 3-joint arm on effort joints: an effort_controllers/JointGroupPositionController on
    yaw and shoulder (PIDs in the joints' actuators), a JointGroupEffortController on the elbow."""

    def __init__(self, fast):
        super(GroupArm, self).__init__(fixture("arm_3dof.urdf").replace("PositionJointInterface",
                                                                        "EffortJointInterface"))
        self.joint_state_controller(publish_rate=50)
        self.pos = self.mgr.load("pos", {
            "type": "effort_controllers/JointGroupPositionController", "joints": ["yaw", "shoulder"],
            "yaw": {"pid": {"p": 80.0, "i": 30.0, "d": 4.0, "i_clamp": 5.0, "antiwindup": True}},
            "shoulder": {"pid": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0}}})
        self.eff = self.mgr.load("eff", {"type": "effort_controllers/JointGroupEffortController",
                                         "joints": ["elbow"]})
        self.adapter("pos")
        self.adapter("eff")
        assert self.mgr.switch(["jsc", "pos", "eff"], [], STRICT)[0]
        self.start(fast)


def _new_gains(rig):
    rig.pos.pids[1].set_gains(type(rig.pos.pids[1].gains)(150.0, 20.0, 8.0, 4.0, -4.0))


GROUP_EVENTS = {
    100: lambda r: r.pos.set_command([1.2, -0.7]),
    400: lambda r: r.eff.set_command([3.0]),
    600: lambda r: r.pos.set_command([-2.0, 0.3]),
    800: _new_gains,
    900: lambda r: r.mgr.switch([], ["eff"], STRICT),       # the elbow keeps its last effort
}


@needs_c
def test_group_controllers_step_natively_and_equal_every_update_bit_for_bit():
    ref = run(GroupArm(False), 1200, GROUP_EVENTS)
    fast = run(GroupArm(True), 1200, GROUP_EVENTS)
    assert ref.log == fast.log and len(ref.log) == 60
    assert snapshot(ref) == snapshot(fast)
    # Python: the joint_states samples (every 20th step) and the updates that take a command
    assert fast.world.native_steps > 0.9 * fast.world.iterations, fast.world.native_steps
    assert abs(fast.model.joints["yaw"].position + 2.0) < 0.2, "the group did not follow its command"
    assert fast.model.joints["elbow"].effort == 3.0


@needs_c
def test_a_control_period_of_one_step_steps_natively_as_without_one():
    """franka_description's <controlPeriod>0.001</controlPeriod> at 1 ms steps: gazebo_ros_control
    updates before every step, as without a period, so the controllers' due times hold as well;
    the period made every step an update in Python (the Panda at 1000 per simulated second)."""
    def arm(fast, period):
        rig = GroupArm(fast)
        rig.loop.control_period = period
        return run(rig, 1200, GROUP_EVENTS)
    ref = arm(False, None)
    fast = arm(True, 0.001)
    assert ref.log == fast.log and len(ref.log) == 60
    assert snapshot(ref) == snapshot(fast)
    assert fast.world.native_steps > 0.9 * fast.world.iterations, fast.world.native_steps


def _record_updates(rig, controller):
    """(the times of the control loop's updates, the times at which ``controller`` updated)."""
    loops, updates = [], []
    read, update = rig.hw.read, controller.update

    def counted_read():
        loops.append(rig.mgr.time)      # once per update of the loop, after its time is set
        read()

    def counted_update(t, dt):
        updates.append(t)
        update(t, dt)
    rig.hw.read, controller.update = counted_read, counted_update
    return loops, updates


@needs_c
def test_a_controller_that_is_not_due_is_left_out_where_the_world_stops_for_another():
    """Standing, the arm's loop updates only for the joint_state_controller's samples (50 Hz):
    there the group position controller, with no new command or gains, is not due and does not
    update (the steps are those of an update at every step: the tests above); a mobile base, whose
    odometry sums one arc per update, updates wherever the loop does (update_at_every_stop)."""
    arm = run(GroupArm(True), 1200, GROUP_EVENTS)
    loops, updates = _record_updates(arm, arm.pos)
    arm.step(1000)
    assert len(loops) == 50, loops
    assert updates == []
    arm.pos.set_command([0.5, -0.5])
    arm.step(100)
    assert len(updates) == 1, updates       # the command's update

    bot = DiffBot(True)
    bot.joint_state_controller(publish_rate=30)     # on another phase than the odometry's 50 Hz
    assert bot.mgr.switch(["jsc"], [], STRICT)[0]
    bot.step(100)
    loops, updates = _record_updates(bot, bot.c)
    bot.step(1000)
    samples = [e[1] for e in bot.log if isinstance(e, tuple) and e[1] >= loops[0]]
    # 20 of the 30 samples here fall outside the odometry's own updates: without its declaration
    # the base would skip them
    assert updates == loops
    assert samples and set(samples) <= set(updates)


class Gripper(ControlRig):
    """The parallel gripper's effort_controllers/GripperActionController (its PID in the finger's
    actuator; ``position``: position_controllers/GripperActionController, the finger set
    kinematically by the hardware); the goals' outcomes go to ``log``."""

    def __init__(self, fast, position=False):
        super(Gripper, self).__init__(fixture("gripper_parallel.urdf"), name="gripper")
        params = {"type": "effort_controllers/GripperActionController", "joint": "finger_joint1",
                  "goal_tolerance": 0.002, "stall_timeout": 0.3,
                  "gains": {"finger_joint1": {"p": 100.0, "d": 5.0}}}
        if position:
            params["type"] = "position_controllers/GripperActionController"
            del params["gains"]
        self.c = self.mgr.load("gc", params)
        self.adapter("gc", after_update=self._events)
        assert self.mgr.switch(["gc"], [], STRICT)[0]
        self.start(fast)

    def _events(self, t):
        self.log.extend((t,) + e for e in self.c.events)
        del self.c.events[:]


def _goal(position, max_effort):
    return lambda r: r.c.submit("g%g" % position, position, max_effort, r.world.time)


GRIPPER_EVENTS = {50: _goal(0.03, 10.0), 700: _goal(0.01, 5.0),
                  1000: _goal(0.06, 10.0)}          # beyond the finger's limit 0.04: it stalls there


@needs_c
@pytest.mark.parametrize("position", [False, True])
def test_gripper_action_steps_natively_and_equals_every_update_bit_for_bit(position):
    ref = run(Gripper(False, position), 1500, GRIPPER_EVENTS)
    fast = run(Gripper(True, position), 1500, GRIPPER_EVENTS)
    # the goals end at the same steps: the joint's actuator watches for the goal's checks
    assert ref.log == fast.log
    assert [e[2] for e in fast.log] == ["succeeded", "succeeded", "aborted"], fast.log
    assert fast.log[-1][3]["stalled"] and abs(fast.log[-1][3]["position"] - 0.04) < 1e-3
    assert snapshot(ref) == snapshot(fast)
    # Python: a goal's arrival and its outcome; the finger moves, holds and stalls natively
    assert fast.world.native_steps > 0.98 * fast.world.iterations, fast.world.native_steps


class DiffBot(ControlRig):
    """diffbot on a DiffDriveController (velocity wheels: ODE motors) with acceleration limits,
    a 0.25 s command timeout and a rolling window of 4; its odometry messages go to ``log``.
    ``per_update``: with ``publish_cmd`` and ``publish_wheel_joint_controller_state``, whose
    messages go to ``sent`` while ``listening[0]`` (as the adapter publishes them while its topics
    have subscribers; the controller is told by ``per_update_wanted``)."""

    def __init__(self, fast, window=4, per_update=False):
        super(DiffBot, self).__init__(fixture("diffbot.urdf"), name="diffbot")
        self.c = self.mgr.load("base", {
            "type": "diff_drive_controller/DiffDriveController", "left_wheel": ["left_wheel"],
            "right_wheel": "right_wheel", "publish_rate": 50, "cmd_vel_timeout": 0.25,
            "velocity_rolling_window_size": window, "publish_cmd": per_update,
            "publish_wheel_joint_controller_state": per_update,
            "pose_covariance_diagonal": [0.001] * 6, "twist_covariance_diagonal": [0.001] * 6,
            "linear": {"x": {"has_acceleration_limits": True, "max_acceleration": 3.0}},
            "angular": {"z": {"has_acceleration_limits": True, "max_acceleration": 6.0}}})
        self.listening = [True]
        self.sent = []
        self.c.per_update_wanted = lambda: self.listening[0]
        self.adapter("base", after_update=self._odom)
        assert self.mgr.switch(["base"], [], STRICT)[0]
        self.start(fast)

    def _odom(self, t):
        data, self.c.pending = self.c.pending, None
        if data is not None:
            self.log.append(data)
        out, wheels = self.c.cmd_out, self.c.wheel_state
        self.c.cmd_out = self.c.wheel_state = None
        if self.listening[0] and out is not None:
            self.sent.append((out, wheels))


DRIVE_EVENTS = {
    30: lambda r: r.c.set_command(0.4, 0.0),
    300: lambda r: r.c.set_command(0.3, 1.0),       # kept up until the timeout brakes it
    800: lambda r: r.c.set_command(0.2, -0.5),
    900: lambda r: r.c.set_command(0.2, -0.5),       # the same command again: its timeout restarts
}


@needs_c
def test_diff_drive_controller_steps_natively_and_equals_every_update():
    ref = run(DiffBot(False), 1500, DRIVE_EVENTS)
    fast = run(DiffBot(True), 1500, DRIVE_EVENTS)
    # the wheels got the same commands at the same steps: the same physics, bit for bit
    assert snapshot(ref) == snapshot(fast)
    assert len(ref.log) == len(fast.log) == 74         # 50 Hz over 1.5 s, the first at 20 ms
    for a, b in zip(ref.log, fast.log):
        assert a["stamp"] == b["stamp"]
        # the twist averages the same per-step speeds; the pose sums one arc instead of several
        assert a["linear"] == pytest.approx(b["linear"], rel=1e-9, abs=1e-12)
        assert a["angular"] == pytest.approx(b["angular"], rel=1e-9, abs=1e-12)
        for k in ("x", "y", "heading"):
            assert abs(a[k] - b[k]) < 1e-9, (k, a, b)
    moved = fast.log[-1]
    assert math.hypot(moved["x"], moved["y"]) > 0.2, "the robot did not drive"
    # Python: the ramps of the acceleration limits after each command and at the brake (about 600
    # steps here), 4 + 2 updates before each odometry message (6 of 20 steps)
    assert fast.world.native_steps > 0.35 * fast.world.iterations, fast.world.native_steps
    steady = fast.world.native_steps
    fast.step(200)                            # standing: only the odometry's updates
    assert fast.world.native_steps - steady >= 200 * 14 // 20 - 1, fast.world.native_steps - steady


def _listen(on):
    def event(rig):
        rig.listening[0] = on
    return event


@needs_c
def test_diff_drive_per_update_messages_are_due_at_every_step_only_while_listened():
    """publish_cmd and publish_wheel_joint_controller_state (Husky's and Jackal's control.yaml): an
    update at every step while someone listens to their topics; while nobody does, a look for a
    listener every IDLE_LOOK of simulated time, and the World steps natively in between."""
    rig = DiffBot(True, per_update=True)
    w, c, dt = rig.world, rig.c, rig.world.time_step
    rig.step(300)                               # standing, listened to
    assert c.update_due(w.time, w.iterations, dt) == w.time
    native = w.native_steps
    rig.step(90)
    assert w.native_steps == native             # every step's update in Python
    rig.listening[0] = False
    # the update of this step looks: nobody (at 0.39 s, between two odometry messages: they go out
    # at the first update after each 20 ms, 0.381, 0.401, .., as diff_drive_controller's strict test
    # of whole nanoseconds puts them)
    rig.step(1)
    looked = w.time - dt
    due = c.update_due(w.time, w.iterations, dt)
    assert w.time < due <= looked + IDLE_LOOK + 1e-9, (w.time, due)
    native = w.native_steps
    rig.step(1000)
    # only the odometry's updates (4 + 2 of every 20 steps) and the looks in Python
    assert w.native_steps - native >= 1000 * 14 // 20 - 1, w.native_steps - native
    assert all(out[0] <= looked + 1e-9 for out, _ in rig.sent), "a message while nobody listened"
    rig.listening[0] = True
    came = w.time
    rig.step(200)
    first = next(out[0] for out, _ in rig.sent if out[0] > came)
    assert first <= came + IDLE_LOOK + 1e-9, (came, first)
    assert c.update_due(w.time, w.iterations, dt) == w.time


LISTEN_EVENTS = dict(DRIVE_EVENTS)
LISTEN_EVENTS.update({0: _listen(False), 320: _listen(True), 700: _listen(False), 1250: _listen(True)})


@needs_c
def test_diff_drive_per_update_messages_once_listened_are_those_of_every_update():
    """Stepped natively while nobody listens, the robot drives as at every update, and from the
    update that finds a listener (at most IDLE_LOOK after it came) the messages are those of an
    update at every step, one per step, the same stamps and values bit for bit (the wheels'
    desired positions integrate the speeds of the updates made natively as those updates would
    have)."""
    ref = run(DiffBot(False, per_update=True), 1600, DRIVE_EVENTS)
    fast = run(DiffBot(True, per_update=True), 1600, LISTEN_EVENTS)
    assert snapshot(ref) == snapshot(fast)
    assert len(ref.sent) == 1600
    for came, left in ((0.320, 0.700), (1.250, 1.600)):
        got = [m for m in fast.sent if came - 1e-9 <= m[0][0] <= left + 1e-9]
        assert got and got[0][0][0] <= came + IDLE_LOOK + 1e-9, (came, got[:1])
        last = got[-1][0][0]
        assert last >= left - 2e-3, (left, last)
        assert got == [m for m in ref.sent if got[0][0][0] - 1e-9 <= m[0][0] <= last + 1e-9], came
        assert any(m[0][1] != 0.0 for m in got) or came > 1.0, "the robot did not drive"
    assert fast.world.native_steps > 0.2 * fast.world.iterations, fast.world.native_steps


class PidGainsArm(ControlRig):
    """The 3-joint arm on position joints with gazebo_ros_control's pid_gains (the hardware's
    PIDs in the actuators), position_controllers/JointPositionController on each."""

    def __init__(self, fast):
        from modrob_sim.ros_control.pid import Pid, PidGains
        super(PidGainsArm, self).__init__(fixture("arm_3dof.urdf"))
        for name in ("yaw", "shoulder", "elbow"):
            self.hw.joints[name].set_pid(Pid(PidGains(150.0, 10.0, 8.0, 3.0, -3.0)),
                                         "/arm/gazebo_ros_control/pid_gains/" + name)
            self.mgr.load(name, {"type": "position_controllers/JointPositionController", "joint": name})
            self.adapter(name)
        assert self.mgr.switch(["yaw", "shoulder", "elbow"], [], STRICT)[0]
        self.start(fast)


PID_GAINS_EVENTS = {
    100: lambda r: r.mgr.get("yaw").set_command(1.5),        # 0.5 s at the velocity limit 3 rad/s
    700: lambda r: r.mgr.get("shoulder").set_command(-0.4),
    701: lambda r: r.mgr.get("elbow").set_command(0.8),
}


@needs_c
def test_pid_gains_position_joints_step_natively_once_the_rate_limit_reaches_the_command():
    ref = run(PidGainsArm(False), 1200, PID_GAINS_EVENTS)
    fast = run(PidGainsArm(True), 1200, PID_GAINS_EVENTS)
    assert snapshot(ref) == snapshot(fast)
    # Python: the yaw command's 500 rate-limited steps, the others' ~130; the holds natively
    assert 0.3 * 1200 < fast.world.native_steps < 0.6 * 1200, fast.world.native_steps
    assert abs(fast.model.joints["yaw"].position - 1.5) < 0.05


class VelocityPositionArm(ControlRig):
    """The 3-joint arm on velocity joints, velocity_controllers/JointPositionController on each
    (the PID's output the joint's motor velocity: an OUT_VELOCITY actuator); ``python_pids``: the
    controllers run their PIDs in Python and write the hardware's velocity commands, as where a
    joint cannot take that actuator. The state messages go to ``log``."""

    def __init__(self, fast, python_pids=False):
        super(VelocityPositionArm, self).__init__(fixture("arm_3dof.urdf").replace("PositionJointInterface",
                                                                                   "VelocityJointInterface"))
        if python_pids:
            for res in self.hw.joints.values():
                res.can_drive = lambda output: False
        gains = {"yaw": {"p": 6.0, "d": 0.02}, "shoulder": {"p": 10.0, "d": 0.05},
                 "elbow": {"p": 8.0, "i": 2.0, "i_clamp": 0.5, "antiwindup": True}}
        for name in ("yaw", "shoulder", "elbow"):
            c = self.mgr.load(name, {"type": "velocity_controllers/JointPositionController", "joint": name,
                                     "pid": gains[name]})
            self.adapter(name, after_update=lambda t, c=c: self._state(c))
        assert self.mgr.switch(["yaw", "shoulder", "elbow"], [], STRICT)[0]
        self.start(fast)

    def _state(self, c):
        data, c.pending = c.pending, None
        if data is not None:
            self.log.append((c.name, data))


VELOCITY_POSITION_EVENTS = {
    100: lambda r: r.mgr.get("yaw").set_command(1.5),        # 0.5 s at the velocity limit 3 rad/s
    400: lambda r: r.mgr.get("shoulder").set_command(-0.6),
    401: lambda r: r.mgr.get("elbow").set_command(0.9),
    700: lambda r: r.mgr.get("elbow").pid.set_gains(type(r.mgr.get("elbow").pid.gains)(4.0)),
    900: lambda r: r.mgr.switch([], ["shoulder"], STRICT),   # its joint keeps the last velocity
}


@needs_c
def test_velocity_position_controllers_step_natively_and_equal_their_python_pids_bit_for_bit():
    ref = run(VelocityPositionArm(False), 1200, VELOCITY_POSITION_EVENTS)
    fast = run(VelocityPositionArm(True), 1200, VELOCITY_POSITION_EVENTS)
    python = run(VelocityPositionArm(False, python_pids=True), 1200, VELOCITY_POSITION_EVENTS)
    assert snapshot(ref) == snapshot(fast)
    assert ref.log == fast.log == python.log and len(fast.log) > 300
    joints = [(j.position, j.velocity, j.effort) for j in python.model.joints_in_order]
    assert joints == snapshot(fast)[4] and python.world.state_digest() == fast.world.state_digest()
    assert python.world.actuators == () and len(fast.world.actuators) == 2
    # the PIDs run in the actuators: Python only for commands, new gains and the state messages
    # (every 10th step; a stand-in adapter always wants them)
    assert fast.world.native_steps > 0.85 * fast.world.iterations, fast.world.native_steps
    m = fast.model.joints
    # (the elbow, on p alone after 0.7 s, sags under gravity by what the motor's softness gives)
    assert abs(m["yaw"].position - 1.5) < 0.01 and abs(m["elbow"].position - 0.9) < 0.03


class KinematicArm(ControlRig):
    """The 3-joint arm on position joints without pid_gains (set kinematically at every step, as
    Gazebo's writeSim does: the joints' OUT_POSITION actuators),
    position_controllers/JointPositionController on each; ``python_pids``: the hardware sets the
    joints itself at every update (Model.set_configuration), as for a joint without an actuator."""

    def __init__(self, fast, python_pids=False):
        super(KinematicArm, self).__init__(fixture("arm_3dof.urdf"))
        if python_pids:
            for res in self.hw.joints.values():
                res.can_drive = lambda output: False
                res.hardware_actuator()
        self.joint_state_controller(publish_rate=50)
        for name in ("yaw", "shoulder", "elbow"):
            self.mgr.load(name, {"type": "position_controllers/JointPositionController", "joint": name})
            self.adapter(name)
        assert self.mgr.switch(["jsc", "yaw", "shoulder", "elbow"], [], STRICT)[0]
        self.start(fast)


KINEMATIC_EVENTS = {
    100: lambda r: r.mgr.get("yaw").set_command(1.5),        # 0.5 s at the velocity limit 3 rad/s
    300: lambda r: r.mgr.get("elbow").set_command(3.0),      # beyond the limit 2.5: clamped
    400: lambda r: r.mgr.get("shoulder").set_command(-0.6),
    800: lambda r: r.mgr.switch([], ["shoulder"], STRICT),   # its joint keeps the last command
}


@needs_c
def test_kinematic_position_joints_step_natively_and_move_as_the_hardware_moved_them():
    ref = run(KinematicArm(False), 1200, KINEMATIC_EVENTS)
    fast = run(KinematicArm(True), 1200, KINEMATIC_EVENTS)
    python = run(KinematicArm(False, python_pids=True), 1200, KINEMATIC_EVENTS)
    assert snapshot(ref) == snapshot(fast) and ref.log == fast.log
    # Python: the commands and the joint_states samples (every 20th step); the joints are set in C
    assert fast.world.native_steps > 0.9 * fast.world.iterations, fast.world.native_steps
    assert python.world.native_steps == 0 and python.world.actuators == ()
    m = fast.model.joints
    assert abs(m["yaw"].position - 1.5) < 1e-3 and abs(m["elbow"].position - 2.5) < 1e-3
    assert abs(m["shoulder"].position + 0.6) < 1e-3
    # the same motion as the hardware setting the joints (the whole model placed from its joint
    # positions) to rounding
    assert len(python.log) == len(fast.log) == 60
    for a, b in zip(python.log, fast.log):
        assert a[1] == b[1] and max(abs(x - y) for x, y in zip(a[2][2], b[2][2])) < 1e-6, (a, b)
