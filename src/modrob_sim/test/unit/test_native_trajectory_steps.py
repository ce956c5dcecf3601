"""An effort JointTrajectoryController whose joints' SEGMENT_PID actuators carry its trajectory
through the C loop's batches between its due updates (segment ends, state and feedback samples,
goals): the steps, actuator internals, goal outcomes, state and feedback samples are those of
updating at every step bit for bit, through goals of every spline order (linear, cubic, quintic),
a continuous joint taking the short way, a partial goal, a goal with path tolerances, a preemption,
a cancel that decelerates over stop_trajectory_duration and goals past their end (their goal checks
in Python); and most steps do run in the batches. A goal's path tolerances are watched by the
actuators (bands on their tracking errors): a goal that exceeds one part of the way is aborted at
the step of an update at every step (the effort, velocity and position types, both backends, and
against the controller's own checks and PIDs in Python), one that keeps them stops the World as
often as a goal without them; a motion of many short segments needs no more updates than a hold
(the pieces queued in the actuators take over in turn). Also: Trajectory.piece describes sample()
exactly over the times it claims, and the pieces that follow it, taken in turn, are piece(t)."""
import collections
import math
import os
import random
import types

import pytest

from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.controllers.joint_trajectory import TrajectoryPoint
from modrob_sim.ros_control.manager import STRICT
from modrob_sim.ros_control.trajectory import ABSOLUTE, HOLD, RELATIVE, PreparedTrajectory, State, Trajectory

physics = pytest.importorskip("modrob_sim.physics")
FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
JOINTS = ["yaw", "shoulder", "elbow"]
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


class Rig(ControlRig):
    """The 3-joint effort arm (yaw continuous) with a joint_state_controller and an effort
    trajectory controller; the adapter records what the ROS layer would publish. ``velocity``:
    velocity joints and velocity_controllers/JointTrajectoryController instead (its PIDs' outputs
    the joints' motor velocities); ``position``: position joints (no pid_gains) and
    position_controllers/JointTrajectoryController (the joints set kinematically);
    ``python_pids`` makes it run in Python at every update, writing the joints' commands, as it
    does where the joints cannot take its actuators (and the hardware sets position joints
    itself)."""

    def __init__(self, fast, gripper=False, velocity=False, python_pids=False, position=False, native=None):
        iface = "VelocityJointInterface" if velocity else "EffortJointInterface"
        if position:
            iface = "PositionJointInterface"
        with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
            xml = f.read().replace("PositionJointInterface", iface)
        if gripper:     # yaw with limits beyond +-pi (soft limits), two fingers, one a mimic
            xml = xml.replace('<limit lower="-3" upper="3" effort="50"',
                              '<limit lower="-4.5" upper="4.5" effort="50"')
            xml = xml.replace("</robot>", GRIPPER + "</robot>")
        else:
            xml = xml.replace('name="yaw" type="revolute"', 'name="yaw" type="continuous"')
        super(Rig, self).__init__(xml, native=native)
        self.joint_state_controller(publish_rate=50)
        gains = {"yaw": {"p": 80.0, "i": 30.0, "d": 4.0, "i_clamp": 5.0, "antiwindup": True},
                 "shoulder": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0},
                 "elbow": {"p": 120.0, "d": 6.0}}
        ff = {"shoulder": 0.5}
        if velocity:    # rad/s per rad; the desired velocity fed forward
            ff = {j: 1.0 for j in JOINTS}
            gains = {"yaw": {"p": 12.0, "i": 2.0, "i_clamp": 0.5, "antiwindup": True},
                     "shoulder": {"p": 20.0, "i": 4.0, "d": 0.05, "i_clamp": 0.5},
                     "elbow": {"p": 15.0}}
        if python_pids:
            for res in self.hw.joints.values():
                res.can_drive = lambda output: False
                res.hardware_actuator()
        family = "position" if position else "velocity" if velocity else "effort"
        self.jtc = self.mgr.load("arm_controller", {
            "type": "%s_controllers/JointTrajectoryController" % family,
            "joints": JOINTS, "gains": gains,
            "velocity_ff": ff, "stop_trajectory_duration": 0.15,
            "state_publish_rate": 25.0, "action_monitor_rate": 10.0, "allow_partial_joints_goal": True,
            "constraints": {"goal_time": 0.5, "stopped_velocity_tolerance": 0.2, "elbow": {"goal": 0.05}}})
        if gripper:
            self.finger = self.mgr.load("finger", {"type": "effort_controllers/JointPositionController",
                                                   "joint": "finger1", "pid": {"p": 400.0, "d": 2.0}})
            self.adapter("finger")
            assert self.mgr.switch(["finger"], [], STRICT)[0]
        self.inbox = collections.deque()
        self.adapter("arm_controller", waiting=lambda: bool(self.inbox), before_update=self.jtc_before_update,
                     after_update=self.jtc_after_update)
        assert self.mgr.switch(["jsc", "arm_controller"], [], STRICT)[0]
        self.start(fast)

    def jtc_before_update(self, t):
        while self.inbox:
            kind, args = self.inbox.popleft()
            if kind == "goal":
                self.log.append(("submit", t, self.jtc.submit(*args[:2], start_time=0.0, now=t, **args[2])))
            else:
                self.log.append(("cancel", t, self.jtc.cancel(args, t)))

    def jtc_after_update(self, t):
        c = self.jtc
        self.log.extend(("event", t) + e for e in c.events)
        del c.events[:]
        fb, c.pending_feedback = c.pending_feedback, None
        if fb is not None:
            self.log.append(("feedback", t, fb))
        data, c.pending = c.pending, None
        if data is not None:
            self.log.append(("state", t, data))

    def snapshot(self):
        c = self.jtc
        acts = [(a.pid_state(), a.last) for a in self.world.actuators]
        joints = [(j.position, j.velocity, j.effort) for j in self.model.joints_in_order]
        return (self.world.time, self.world.iterations, self.world.state_digest(), acts, joints,
                c._next_state, c._next_feedback, c.goal and c.goal.goal_id)


INERTIA = '<inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/>'
FINGER_LINK = ('<link name="%s"><inertial><mass value="0.05"/>' + INERTIA + '</inertial>'
               '<collision><geometry><box size="0.01 0.01 0.03"/></geometry></collision></link>')
GRIPPER = (FINGER_LINK % "f1") + (FINGER_LINK % "f2") + """
  <joint name="finger1" type="prismatic"><parent link="l3"/><child link="f1"/><origin xyz="0.3 0.03 0"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.03" effort="20" velocity="0.5"/></joint>
  <joint name="finger2" type="prismatic"><parent link="l3"/><child link="f2"/><origin xyz="0.3 -0.03 0"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="0.03" effort="20" velocity="0.5"/>
    <mimic joint="finger1" multiplier="1" offset="0.002"/></joint>
  <transmission name="finger1_trans">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="finger1">
      <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface></joint>
    <actuator name="finger1_motor"><mechanicalReduction>1</mechanicalReduction></actuator>
  </transmission>
"""


def _points(kind, scale, n=6, dt=0.06, joints=3):
    pts = []
    for k in range(1, n + 1):
        pos = [scale * math.sin(0.4 * k + j) for j in range(joints)]
        vel = [scale * 0.4 / dt * math.cos(0.4 * k + j) * 0.2 for j in range(joints)] if kind >= 3 else None
        acc = [0.3 * scale * math.sin(k - j) for j in range(joints)] if kind == 5 else None
        pts.append(TrajectoryPoint(pos, vel, acc, k * dt))
    return pts


def run(fast, **rig_kw):
    rig = Rig(fast, **rig_kw)

    def goal(gid, names, pts, **kw):
        rig.inbox.append(("goal", (names, pts, dict(goal_id=gid, **kw))))
    script = {
        5: lambda: goal("cubic", JOINTS, _points(3, 0.8)),
        60: lambda: goal("quintic", JOINTS, _points(5, -0.6)),                  # after the cubic's end
        95: lambda: goal("linear", JOINTS, _points(1, 1.1, n=8)),
        100: lambda: goal("preempts", ["shoulder", "yaw"], _points(3, 0.5, joints=2)),   # partial
        130: lambda: goal("path_tol", JOINTS, _points(3, 0.3, n=4),
                          path_tolerance=[types.SimpleNamespace(name="elbow", position=2.0, velocity=0.0)]),
        160: lambda: goal("wrap", JOINTS, [TrajectoryPoint([6.0, 0.2, -0.3], [0.0] * 3, None, 0.4)]),
        185: lambda: goal("canceled", JOINTS, _points(3, -0.9, n=10)),
        192: lambda: rig.inbox.append(("cancel", "canceled")),
    }
    for chunk in range(260):
        if chunk in script:
            script[chunk]()
        if chunk == 185:
            rig.yaw_after_wrap = rig.model.joints["yaw"].position
        rig.step(10)
    return rig


@needs_c
def test_trajectory_controller_batches_equal_python_steps_bit_for_bit():
    ref, fast = run(False), run(True)
    assert fast.world.native
    assert len(ref.log) == len(fast.log) > 200
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    events = [e for e in ref.log if e[0] == "event"]
    outcomes = {e[2]: e[3] for e in events}
    assert outcomes["linear"] == "preempted" and outcomes["canceled"] == "canceled"
    assert sum(1 for e in ref.log if e[0] == "feedback") > 10
    assert all(e[2][0] for e in ref.log if e[0] == "submit"), "a goal was rejected"
    # most steps ran in C: the Python updates are those with a goal past its end or with path
    # tolerances, with a goal waiting, a segment ending, a state or feedback sample due
    assert fast.world.native_steps > 0.65 * fast.world.iterations, "%d of %d steps batched" % (
        fast.world.native_steps, fast.world.iterations)
    q = ref.yaw_after_wrap
    assert abs(math.remainder(q - 6.0, 2 * math.pi)) < 0.2, "yaw did not follow the short way to 6.0 (%g)" % q


@needs_c
def test_velocity_trajectory_controller_batches_equal_python_steps_bit_for_bit():
    ref, fast = run(False, velocity=True), run(True, velocity=True)
    assert len(ref.log) == len(fast.log) > 200
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    outcomes = {e[2]: e[3] for e in ref.log if e[0] == "event"}
    assert outcomes["linear"] == "preempted" and outcomes["canceled"] == "canceled", outcomes
    # the PIDs are the joints' actuators: most steps in C, as for the effort controller
    assert fast.world.native_steps > 0.65 * fast.world.iterations, "%d of %d steps batched" % (
        fast.world.native_steps, fast.world.iterations)
    q = ref.yaw_after_wrap
    assert abs(math.remainder(q - 6.0, 2 * math.pi)) < 0.2, "yaw did not follow the short way to 6.0 (%g)" % q


@needs_c
def test_velocity_trajectory_actuators_equal_the_controllers_python_pids_bit_for_bit():
    # the same controller running its PIDs in Python at every update and writing the hardware's
    # velocity commands (the motor set by the hardware's write) gives the same steps
    python, fast = run(False, velocity=True, python_pids=True), run(True, velocity=True)
    assert python.world.actuators == () and len(fast.world.actuators) == 3
    assert python.world.native_steps == 0
    assert len(python.log) == len(fast.log) > 200
    for a, b in zip(python.log, fast.log):
        assert a == b
    assert python.world.state_digest() == fast.world.state_digest()
    assert ([(j.position, j.velocity) for j in python.model.joints_in_order]
            == [(j.position, j.velocity) for j in fast.model.joints_in_order])


@needs_c
def test_position_trajectory_controller_batches_equal_python_steps_bit_for_bit():
    ref, fast = run(False, position=True), run(True, position=True)
    assert len(ref.log) == len(fast.log) > 200
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    # the joints are set by their actuators (OUT_POSITION), not by a Python update at every step
    assert fast.world.native_steps > 0.75 * fast.world.iterations, "%d of %d steps batched" % (
        fast.world.native_steps, fast.world.iterations)
    outcomes = {e[2]: e[3] for e in ref.log if e[0] == "event"}
    assert outcomes["cubic"] == "succeeded" and outcomes["canceled"] == "canceled", outcomes


@needs_c
def test_position_trajectory_actuators_set_the_joints_as_the_hardware_did():
    # the controller writing the joints' commands at every update and the hardware setting them
    # (Model.set_configuration) give the same motion: the same outcomes at the same times, the
    # same samples to rounding (the actuator turns the links below a joint about its axis where
    # set_configuration places the whole model from its joint positions)
    python, fast = run(False, position=True, python_pids=True), run(True, position=True)
    assert python.world.actuators == () and len(fast.world.actuators) == 3
    assert python.world.native_steps == 0
    assert len(python.log) == len(fast.log) > 200
    for a, b in zip(python.log, fast.log):
        assert a[:2] == b[:2]
        if a[0] in ("state", "feedback"):
            data_a, data_b = (a[2], b[2]) if a[0] == "state" else (a[2][1], b[2][1])
            assert data_a["desired"] == data_b["desired"]
            for x, y in zip(data_a["actual"][0], data_b["actual"][0]):
                assert abs(x - y) < 1e-6, (a, b)
        elif a[0] == "joint_states":
            assert a[2][1] == b[2][1] and max(abs(x - y) for x, y in zip(a[2][2], b[2][2])) < 1e-6, (a, b)
        else:
            assert a == b
    assert abs(python.yaw_after_wrap - fast.yaw_after_wrap) < 1e-6


#: per controller family: the path tolerances (joint: (position, velocity)) that a slow goal of 1 s
#: exceeds part of the way (yaw's largest tracking error, 0.15 s in: effort 0.0114 rad, velocity
#: 0.00042 rad; the position family's joints are set kinematically, at rest relative to their
#: parents at each step's start: yaw's velocity error up to 1.2 rad/s half way), and tolerances it
#: keeps (the shoulder's 0.020 rad under gravity with the effort type's gains included)
PATH_TOLERANCES = {
    "effort": ({"yaw": (0.008, 0.0)}, {j: (0.05, 0.5) for j in JOINTS}),
    "velocity": ({"yaw": (0.0003, 0.0)}, {j: (0.01, 0.1) for j in JOINTS}),
    "position": ({"yaw": (0.0, 1.0)}, {j: (0.01, 2.0) for j in JOINTS}),
}


def _tolerances(by_joint):
    return [types.SimpleNamespace(name=j, position=p, velocity=v) for j, (p, v) in by_joint.items()]


def run_path_goals(fast, family, native=None, python_pids=False, tolerances=True):
    """A slow goal of 1 s that exceeds its path tolerances part of the way (aborted), then one back
    that keeps them (succeeded); ``tolerances`` False: the same goals without path tolerances."""
    rig = Rig(fast, velocity=family == "velocity", position=family == "position", native=native,
              python_pids=python_pids)
    exceeded, kept = PATH_TOLERANCES[family] if tolerances else ({}, {})
    rig.goal_steps = None
    for chunk in range(280):
        if chunk == 30:
            rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([0.8, -0.6, 0.9], [0.0] * 3, None, 1.0)],
                                       dict(goal_id="exceeded", path_tolerance=_tolerances(exceeded)))))
        if chunk == 150:
            rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([-0.4, 0.3, -0.2], [0.0] * 3, None, 1.0)],
                                       dict(goal_id="kept", path_tolerance=_tolerances(kept)))))
            stops0 = rig.world.stops
        if chunk == 250:        # the kept goal's second s: its trajectory (1 s) and the settling
            rig.goal_stops = rig.world.stops - stops0
        rig.step(10)
    return rig


@pytest.mark.parametrize("family", ["effort", "velocity", "position"])
@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_path_tolerances_abort_at_the_step_of_an_update_at_every_step_bit_for_bit(family, native):
    """The joints' actuators watch the goal's path tolerances as bands (Actuator.watch_band): the
    World ends its native stretch at the step at which one is exceeded, where the update in Python
    aborts the goal with PATH_TOLERANCE_VIOLATED, as the check at every update does (the
    pure-Python backend updates at every step: its controller's check reads the actuators' errors
    there too)."""
    ref, fast = run_path_goals(False, family, native), run_path_goals(True, family, native)
    assert fast.world.native is native
    assert len(ref.log) == len(fast.log) > 100
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    events = [e[1:] for e in fast.log if e[0] == "event"]
    assert [e[1:4] for e in events] == [("exceeded", "aborted", -4), ("kept", "succeeded", 0)], events
    # exceeded part of the way (0.057 - 0.086 s after the goal's arrival at 0.3 s, between the state
    # samples), not at its arrival nor at the trajectory's end
    assert 0.31 < events[0][0] < 1.3, events[0]
    assert "path tolerance violated: joint '%s'" % list(PATH_TOLERANCES[family][0])[0] in events[0][4]
    if native:
        # the kept goal's second: the Python updates are a hold's (the state and joint_states samples
        # at 25 and 50 Hz, with the feedback) and the piece's end, not the 1000 of a check at every step
        assert fast.goal_stops < 100, fast.goal_stops


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
@pytest.mark.parametrize("which", ["path_tolerance", "goal_tolerance"])
@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_goal_with_a_tolerance_that_is_no_finite_number_is_rejected_by_name(bad, which, native):
    """A NaN or infinite tolerance (position or velocity) is refused at the goal's submission, naming
    the tolerance and the joint, and changes nothing: the watched goal in progress goes on and
    succeeds, the World steps on (a NaN or infinite path tolerance, accepted, had the actuators'
    band refuse it inside the update: the loop's step raised at every step from then on)."""
    rig = Rig(True, native=native)
    ok = types.SimpleNamespace(name="elbow", position=2.0, velocity=0.0)
    rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([0.3, -0.2, 0.4], [0.0] * 3, None, 0.5)],
                               dict(goal_id="watched", path_tolerance=[ok]))))
    rig.step(100)
    assert rig.jtc.acts and rig.jtc.acts[2].band == (2.0, 0.0)
    for field in ("position", "velocity"):
        tol = dict(name="shoulder", position=0.1, velocity=0.5)
        tol[field] = bad
        rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([-0.3, 0.2, -0.4], [0.0] * 3, None, 0.5)],
                                   {"goal_id": "bad", which: [ok, types.SimpleNamespace(**tol)]})))
        rig.step(10)
        submit = [e for e in rig.log if e[0] == "submit"][-1]
        accepted, code, text = submit[2]
        assert (accepted, code) == (False, -1), submit
        assert "%s of joint 'shoulder'" % which in text and "%s %r" % (field, bad) in text, text
    rig.step(1000)
    events = [e[2:4] for e in rig.log if e[0] == "event"]
    assert events == [("watched", "succeeded")], events
    assert abs(rig.model.joints["shoulder"].position + 0.2) < 0.05


@pytest.mark.parametrize("reset", ["reset", "reset_world"])
@pytest.mark.parametrize("native", [False, pytest.param(True, marks=needs_c)])
def test_a_goal_in_progress_at_a_reset_is_aborted_at_once(reset, native):
    """reset_simulation / reset_world (the World reset, then the control loop's: the running
    controllers started again, holding where the joints are) while a watched goal runs: the goal is
    aborted at the next update, naming the reset, and the controller holds. (It had stayed active
    against the hold until its old end time - 6 s later after reset_simulation, whose clock starts
    again from 0 - and then succeeded, the arm back at its spawn pose, far from the goal.)"""
    rig = Rig(True, native=native)
    rig.step(3000)
    tol = types.SimpleNamespace(name="elbow", position=2.0, velocity=0.0)
    rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([0.6, -0.5, 0.7], [0.0] * 3, None, 1.0)],
                               dict(goal_id="watched", path_tolerance=[tol]))))
    rig.step(500)
    assert rig.jtc.goal is not None and rig.jtc.acts[2].band == (2.0, 0.0)
    getattr(rig.world, reset)()
    rig.loop.reset()
    rig.step(20)
    events = [e[1:] for e in rig.log if e[0] == "event"]
    assert [e[1:4] for e in events] == [("watched", "aborted", -1)], events
    assert "reset" in events[0][4]
    assert rig.jtc.goal is None and all(a.band is None for a in rig.jtc.acts)
    rig.step(2000)
    assert len([e for e in rig.log if e[0] == "event"]) == 1
    assert abs(rig.model.joints["shoulder"].position + 0.5) > 0.3      # held, not at the goal


@needs_c
@pytest.mark.parametrize("family", ["effort", "velocity"])
def test_path_tolerance_bands_equal_the_controllers_python_checks_bit_for_bit(family):
    """The same goals checked by the controller in Python at every update, with its own error rule
    on the trajectory's sample and its PIDs in Python (no actuators, no bands): the same steps, the
    same outcomes at the same steps, the same messages."""
    python, fast = run_path_goals(False, family, python_pids=True), run_path_goals(True, family)
    assert python.jtc.acts == [] and python.world.native_steps == 0    # the hardware's actuators only
    assert len(fast.jtc.acts) == 3
    assert len(python.log) == len(fast.log) > 100
    for a, b in zip(python.log, fast.log):
        assert a == b
    assert python.world.state_digest() == fast.world.state_digest()


@needs_c
def test_a_goal_with_path_tolerances_stops_the_world_as_one_without():
    """With its path tolerances watched by the actuators a goal makes the World stop for Python as
    often as the same goal without path tolerances (the state and feedback samples, joint_states,
    the pieces' ends), where a check at every update stopped it at every step."""
    banded = run_path_goals(True, "effort")
    free = run_path_goals(True, "effort", tolerances=False)
    assert [e[3] for e in free.log if e[0] == "event"] == ["succeeded", "succeeded"]
    assert banded.goal_stops <= free.goal_stops + 1 and banded.goal_stops < 100, (
        banded.goal_stops, free.goal_stops)


@needs_c
def test_a_motion_needs_no_more_python_updates_than_a_hold():
    # the action feedback comes with a state sample (joint_trajectory._samples), and the pieces of
    # the trajectory (a point every 10 ms here, as a planner's) are queued in the actuators, which
    # take them in turn: during a motion the updates in Python are those of a hold (the state
    # samples, joint_states), not one more per segment
    rig = Rig(True)
    rig.step(30)

    def python_updates(steps):
        n0, s0 = rig.world.iterations, rig.world.native_steps
        for _ in range(steps // 10):
            rig.step(10)
        return (rig.world.iterations - n0) - (rig.world.native_steps - s0)
    hold = python_updates(400)
    rig.inbox.append(("goal", (JOINTS, _points(3, 0.4, n=45, dt=0.01), dict(goal_id="g"))))
    rig.step(10)                # the goal's arrival: one step in Python
    motion = python_updates(400)
    assert rig.jtc.goal is not None
    assert sum(1 for e in rig.log if e[0] == "feedback") >= 4
    assert hold <= 30 and motion <= hold + 2, (
        "%d updates in Python in a motion of 45 segments, %d while holding" % (motion, hold))


def _pieces_in_turn(traj, t0, times):
    """What the actuators make of ``traj.pieces(t0, n)``: at each step start the first piece that
    holds (actuators.piece_at), checked against traj.piece(t) there."""
    pieces = traj.pieces(t0, 12)

    def holds(p, t):
        return t < p.abs_until and t - p.base < p.rel_until
    k = 0
    for t in times:
        if t < t0:
            continue
        while k + 1 < len(pieces) and not holds(pieces[k], t):
            k += 1
        if not holds(pieces[k], t):
            return
        want, got = traj.piece(t), pieces[k]
        assert (got.kind, got.segment, got.base, got.offsets, got.abs_until, got.rel_until) == \
            (want.kind, want.segment, want.base, want.offsets, want.abs_until, want.rel_until), (t0, t)


def _check_pieces(traj, times):
    for t in times:
        pc = traj.piece(t)
        for t2 in times:
            if t2 < t or not (t2 < pc.abs_until and t2 - pc.base < pc.rel_until):
                continue
            want = traj.sample(t2)
            if pc.kind == HOLD:
                got_pos, got_vel = list(pc.positions), [0.0] * len(pc.positions)
            else:
                s = t2 - pc.base if pc.kind == RELATIVE else t2
                pos, vel, _acc = pc.segment.sample(s)
                got_pos = pos if pc.offsets is None else [p + o for p, o in zip(pos, pc.offsets)]
                got_vel = vel
            assert (got_pos, got_vel) == (want[0], want[1]), (t, t2)
        assert pc.kind in (ABSOLUTE, RELATIVE, HOLD)


def test_a_piece_samples_as_the_trajectory_does_for_as_long_as_it_claims():
    rng = random.Random(3)
    times = [0.7 + 0.001 * k for k in range(700)]
    for order in (1, 3, 5):
        for offsets in ([0.0, 0.0], [0.25, -6.283185307179586]):
            pts = sorted(rng.uniform(0.05, 0.5) for _ in range(5))
            states = [State([rng.uniform(-1, 1), rng.uniform(-1, 1)],
                            [rng.uniform(-1, 1), 0.3] if order >= 3 else None,
                            [0.1, rng.uniform(-1, 1)] if order == 5 else None) for _ in range(6)]
            prep = PreparedTrajectory([0.0] + pts, states)
            placed = prep.activate(0.75, 0.8, State([0.1, 0.2], [0.0, 0.1]), offsets)
            _check_pieces(placed, times)
            for t0 in times[::37]:
                _pieces_in_turn(placed, t0, times)
            plain = Trajectory(0.8, State([0.1, 0.2], [0.0, 0.1]),
                               [(0.8 + p, st) for p, st in zip(pts, states)])
            _check_pieces(plain, times)
            for t0 in times[::37]:
                _pieces_in_turn(plain, t0, times)


@needs_c
def test_mimic_joints_and_soft_limits_in_batches_equal_python_steps_bit_for_bit():
    """The mimic finger's coupling (also at its stop, where its force is bounded by what reaches
    the target velocity) and a revolute joint with limits beyond +-pi whose stops move with its
    turns, in the C loop's steps."""
    def go(fast):
        rig = Rig(fast, gripper=True)
        assert [j.name for j in rig.model.joints_in_order if j.mimic] == ["finger2"]
        at_stop = 0
        for chunk in range(150):
            if chunk == 2:
                rig.inbox.append(("goal", (JOINTS, [TrajectoryPoint([4.5, 0.3, 0.2], [0.0] * 3, None, 0.9)],
                                           dict(goal_id="past_pi"))))   # to its stop at 4.5 (beyond: refused)
            if chunk == 10:
                rig.finger.set_command(0.03)         # the mimic finger (offset 0.002) meets its stop
            if chunk == 100:
                rig.finger.set_command(0.01)
            rig.step(10)
            f2 = rig.model.joints["finger2"]
            at_stop += f2.position >= f2.upper
        return rig, at_stop
    (ref, ref_stop), (fast, fast_stop) = go(False), go(True)
    assert ref.log == fast.log and ref.snapshot() == fast.snapshot()
    assert ref_stop == fast_stop > 5, "the mimic finger never reached its stop"
    yaw = ref.model.joints["yaw"]
    assert 4.3 < yaw.position < 4.52 and yaw.turn_state[0] == 1, "yaw passed pi to %g, not to its stop" % (
        yaw.position)
    assert fast.world.native_steps > 0.6 * fast.world.iterations, "%d of %d steps batched" % (
        fast.world.native_steps, fast.world.iterations)
