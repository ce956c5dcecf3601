"""FrankaGripperSim on a real World (no ROS): a Franka-style hand over a table (test/fixtures/
hand.urdf) under the ros_control update as gazebo_ros_control's plugin runs it. Its state machine
(move, a grasp that holds a 3 cm cube while the hand lifts it, a grasp outside its epsilon, a
blocked move, stop, interruptions), as franka_gazebo's FrankaGripperSim behaves; and its steps:
with IDLE and HOLDING run by the fingers' actuators natively, stepped as the node steps it, the
same steps bit for bit as franka_gazebo's rule run in Python at every update (a copy of it here,
``EveryStepGripperSim``), on both physics backends, with about 30 updates in Python per simulated
second while idle or holding instead of 1000."""
import math
import os
import threading

import pytest

from franka_sim.gripper import GRASPING, HOLDING, IDLE, MAX_WIDTH, MOVING, FrankaGripperSim, Request
from modrob_sim.errors import ControllerError, InputError
from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import actuators
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.controllers.base import Controller
from modrob_sim.ros_control.manager import STRICT
from modrob_sim.ros_control.params import Params
from modrob_sim.ros_control.pid import Pid, PidGains
from modrob_sim.ros_control.transmissions import EFFORT

FIX = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures")
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")
BACKENDS = [False, pytest.param(True, marks=needs_c)]
GAINS = {"p": 100, "i": 0, "d": 1.0}        # franka_gazebo's config/franka_hw_sim.yaml
PARAMS = {"arm_id": "panda", "finger1": {"gains": GAINS}, "finger2": {"gains": GAINS}}


def fixture(name):
    with open(os.path.join(FIX, name)) as f:
        return f.read()


class EveryStepGripperSim(Controller):
    """franka_gazebo's FrankaGripperSim rule as it ran before the fingers' actuators took IDLE and
    HOLDING over: a Python PID per finger at every update, the effort written to the hardware (test
    only: the reference of the bit-for-bit comparisons)."""
    TYPE = "franka_sim_test/EveryStepGripperSim"
    INTERFACE = EFFORT

    def __init__(self, name, hw, params):
        super(EveryStepGripperSim, self).__init__(name, hw, params)
        self.joint_names = ["panda_finger_joint1", "panda_finger_joint2"]
        self.fingers = [hw.joint(n, EFFORT, controller=name) for n in self.joint_names]
        self.pids = [Pid(PidGains.from_params(params.child(f).child("gains")))
                     for f in ("finger1", "finger2")]
        self.publish_rate, self.tolerance_move = 30.0, 0.001
        self.resting_threshold, self.resting_samples = 0.003, 10
        self._lock = threading.Lock()
        self.mode, self.request, self._still, self._last_publish = IDLE, None, 0, None

    def width(self):
        return self.fingers[0].position + self.fingers[1].position

    def command(self, state, width, speed, force=0.0, inner=None, outer=None):
        inner = self.tolerance_move if inner is None else inner
        outer = self.tolerance_move if outer is None else outer
        req = Request(state, width, speed, force, inner, outer)
        with self._lock:
            self._interrupt("interrupted")
            if state == GRASPING:
                current = self.width()
                req.target = 0.0 if width < current else MAX_WIDTH
                req.force = math.copysign(force, width - current)
            else:
                req.target = width
            self.request, self.mode, self._still = req, state, 0
        return req

    def stop(self):
        with self._lock:
            self._interrupt("stopped")
            self.mode = IDLE

    def _interrupt(self, why):
        if self.request is not None and not self.request.done.is_set():
            self.request.finish(self.mode, self.width(), interrupted=why)
        self.request = None

    def release(self):
        with self._lock:
            if self.mode == HOLDING:
                self.mode = IDLE
            self.request = None

    def starting(self, t):
        for pid in self.pids:
            pid.reset()
        self._last_publish = t - 1.0 / self.publish_rate

    def update(self, t, dt):
        f1, f2 = self.fingers
        if self._last_publish is None or t >= self._last_publish + 1.0 / self.publish_rate - 1e-9:
            self._last_publish = t
            self.pending = (t, list(self.joint_names), [f1.position, f2.position],
                            [f1.velocity, f2.velocity], [f1.effort, f2.effort])
        with self._lock:
            mode, req = self.mode, self.request
            width = f1.position + f2.position
            if mode == IDLE or req is None:
                self._drive(f1.position, f2.position, 0.0, 0.0, dt, mode=IDLE)
                return
            if mode == HOLDING:
                self._drive(f1.position, f2.position, 0.0, req.force / 2.0, dt, mode=HOLDING)
                return
            dw = req.speed * math.copysign(1.0, req.target - width)
            self._drive(f1.position + 0.5 * dw * dt, f2.position + 0.5 * dw * dt, 0.5 * dw, 0.0, dt, mode)
            if mode == MOVING and req.target - req.inner < width < req.target + req.outer:
                self.mode = IDLE
                req.finish(IDLE, width)
                return
            speed = f1.velocity + f2.velocity
            self._still = self._still + 1 if abs(speed) <= self.resting_threshold else 0
            if self._still >= self.resting_samples:
                self._still = 0
                self.mode = HOLDING if mode == GRASPING else IDLE
                req.finish(self.mode, width)
                if mode != GRASPING:
                    self.request = None

    def _drive(self, q1_d, q2_d, dq_d, force, dt, mode):
        f1, f2 = self.fingers
        if mode in (IDLE, HOLDING):
            q1_d, q2_d = f2.position, f1.position
        for finger, pid, q_d in ((f1, self.pids[0], q1_d), (f2, self.pids[1], q2_d)):
            finger.command = pid.compute(q_d - finger.position, dt, error_dot=dq_d - finger.velocity) + force

    def pid_states(self):
        return [pid.state() for pid in self.pids]


class Hand(ControlRig):
    """The hand under ``franka_gripper`` (FrankaGripperSim, or with ``every_step`` the copy of the
    rule above), started at once; the lift joint held by a position PID of the test. ``fast``: the
    World steps natively between the hooks' due times, as the node; ``native``: the backend. The
    gripper's joint states go to ``log``, with the wake-ups its commands ask for (``wakes``)."""

    def __init__(self, fast, native, every_step=False):
        super(Hand, self).__init__(fixture("hand.urdf"), name="hand", native=native)
        self.mgr.types[EveryStepGripperSim.TYPE] = EveryStepGripperSim
        self.mgr.types[FrankaGripperSim.TYPE] = FrankaGripperSim
        kind = EveryStepGripperSim if every_step else FrankaGripperSim
        values = dict(PARAMS, type=kind.TYPE)
        self.c = self.mgr.load("franka_gripper", values)
        self.wakes = 0
        if not every_step:
            self.c.on_change = self._wake
        self.adapter("franka_gripper", after_update=self._joint_states)
        # (first: the World applies the actuators in their order, and the forces on the hand add
        # up in that order; the rule's copy gets the fingers' actuators from the hardware later)
        self.lift = self.world.add_actuator(self.model.joints["lift"], actuators.POSITION_PID,
                                            gains=actuators.PidGains(2000.0, 0.0, 100.0))
        self.lift.command = 0.0
        assert self.mgr.switch(["franka_gripper"], [], STRICT)[0]
        self.requests = []
        self.cube = None
        self.start(fast)

    def _wake(self):
        self.wakes += 1
        self.world.wake()

    def _joint_states(self, t):
        data, self.c.pending = self.c.pending, None
        if data is not None:
            self.log.append(data)

    def command(self, *args, **kw):
        self.requests.append(self.c.command(*args, **kw))

    def add_cube(self):
        self.cube = self.world.add_urdf("cube", fixture("cube.urdf"), pose=((0.0, 0.0, 0.015), (0, 0, 0, 1)))

    def outcomes(self):
        return [(r.state, r.done.is_set(), r.final_state, r.final_width, bool(r.interrupted))
                for r in self.requests]

    def pid_states(self):
        if isinstance(self.c, EveryStepGripperSim):
            return self.c.pid_states()
        return [a.pid_state() for a in self.c.acts]

    def snapshot(self):
        joints = [(j.position, j.velocity, j.effort) for j in self.model.joints_in_order]
        return (self.world.time, self.world.iterations, self.world.state_digest(), joints, self.pid_states(),
                self.outcomes(), self.c.mode)


def run(rig, steps, events):
    """The rig's steps up to ``steps`` in passes of 10 (as the node's loop), ``events[i](rig)``
    before step ``i``; ``rig.stops_at[i]``: the World's stops for Python before step ``i``."""
    stops = rig.__dict__.setdefault("stops_at", {})
    marks = sorted(events) + [steps]
    while rig.world.iterations < steps:
        i = rig.world.iterations
        stops[i] = rig.world.stops
        if i in events:
            events[i](rig)
        rig.step(min(10, min(m for m in marks if m > i) - i))
    stops[steps] = rig.world.stops
    return rig


def _lift(height):
    def event(rig):
        rig.lift.command = height
    return event


# idle; open to 0.08; a cube put between the fingers; a grasp of it (width 0.03, 20 N) that holds
# it while the hand lifts it 5 cm; a move to 0.08 that lets it go (it drops onto the table); idle
GRASP_EVENTS = {
    100: lambda r: r.command(MOVING, 0.08, 0.1),
    1000: Hand.add_cube,
    1100: lambda r: r.command(GRASPING, 0.03, 0.05, force=20.0, inner=0.005, outer=0.005),
    2600: _lift(0.05),
    4000: lambda r: r.command(MOVING, 0.08, 0.1),
    4600: _lift(0.0),
}
GRASP_STEPS = 5600


@pytest.mark.parametrize("native", BACKENDS)
def test_a_grasp_holds_the_cube_while_the_hand_lifts_it_and_a_move_lets_it_go(native):
    rig = Hand(True, native)
    run(rig, 2600, GRASP_EVENTS)
    move, grasp = rig.requests
    assert move.final_state == IDLE and move.within() and not move.interrupted
    assert grasp.final_state == HOLDING and grasp.within(), grasp.final_width
    assert rig.c.mode == HOLDING and grasp.final_width == pytest.approx(0.03, abs=0.002)
    # holding: each finger pushes with half the force (closing is the negative direction)
    assert [s.output for s in (a.last for a in rig.c.acts)] == pytest.approx([-10.0, -10.0], abs=1.0)
    run(rig, 4000, GRASP_EVENTS)
    cube = rig.cube.pose[0]
    lifted = rig.model.joints["lift"].position
    assert lifted > 0.04 and cube[2] - 0.015 == pytest.approx(lifted, abs=0.002), "the cube stayed behind"
    assert abs(cube[1]) < 0.003
    run(rig, 4600, GRASP_EVENTS)
    assert rig.requests[2].final_state == IDLE and rig.requests[2].within()
    assert rig.cube.pose[0][2] == pytest.approx(0.015, abs=0.002), "the cube did not drop onto the table"


@pytest.mark.parametrize("native", BACKENDS)
def test_idle_and_holding_natively_give_the_steps_of_the_rule_at_every_update_bit_for_bit(native):
    ref = run(Hand(False, native, every_step=True), GRASP_STEPS, GRASP_EVENTS)
    fast = run(Hand(True, native), GRASP_STEPS, GRASP_EVENTS)
    assert [o[:4] for o in fast.outcomes()] == [o[:4] for o in ref.outcomes()]
    assert [o[2] for o in fast.outcomes()] == [IDLE, HOLDING, IDLE]
    # the same joint states at the same times (30 Hz), the same PID states, the same physics
    assert len(ref.log) == len(fast.log) > 150
    assert ref.log == fast.log
    assert fast.snapshot() == ref.snapshot()
    assert fast.wakes == 3


def stops_per_second(rig, a, b):
    return (rig.stops_at[b] - rig.stops_at[a]) / ((b - a) * rig.world.time_step)


@needs_c
def test_idle_and_holding_stop_the_world_for_python_about_30_times_a_simulated_second():
    ref = run(Hand(True, True, every_step=True), GRASP_STEPS, GRASP_EVENTS)    # (it declares no due time)
    fast = run(Hand(True, True), GRASP_STEPS, GRASP_EVENTS)
    # idle before the first command, holding (the hand lifting the cube), idle at the end
    for a, b in ((0, 100), (2600, 4000), (4600, GRASP_STEPS)):
        assert stops_per_second(ref, a, b) == pytest.approx(1000.0)
        assert 25.0 <= stops_per_second(fast, a, b) <= 35.0, (a, b, stops_per_second(fast, a, b))
    # the move and the grasp ran an update at every step, as before
    assert stops_per_second(fast, 100, 400) == pytest.approx(1000.0)
    assert stops_per_second(fast, 1100, 1500) == pytest.approx(1000.0)


@pytest.mark.parametrize("native", BACKENDS)
def test_a_stop_and_a_release_from_holding_drop_the_force_at_the_next_step(native):
    events = {50: lambda r: r.command(MOVING, 0.08, 0.1), 1100: Hand.add_cube,
              1200: lambda r: r.command(GRASPING, 0.03, 0.05, force=20.0, inner=0.005, outer=0.005),
              2700: lambda r: r.c.stop(),
              # a grasp outside its epsilon (on the cube again): released, as the ROS side does
              3000: lambda r: r.command(GRASPING, 0.02, 0.05, force=30.0, inner=0.005, outer=0.005),
              3400: lambda r: r.c.release()}
    ref = run(Hand(False, native, every_step=True), 3600, events)
    fast = run(Hand(True, native), 3600, events)
    assert fast.snapshot() == ref.snapshot()
    assert ref.log == fast.log
    assert [o[2] for o in fast.outcomes()] == [IDLE, HOLDING, HOLDING]
    assert not fast.requests[2].within() and fast.c.mode == IDLE and fast.c.request is None
    assert [a.last.output for a in fast.c.acts] == pytest.approx([0.0, 0.0], abs=1.0)
    assert fast.wakes == 5


@pytest.mark.parametrize("native", BACKENDS)
def test_a_grasp_that_closes_beyond_epsilon_fails(native):
    rig = Hand(True, native)
    events = {0: lambda r: r.command(MOVING, 0.08, 0.1), 800: Hand.add_cube,
              900: lambda r: r.command(GRASPING, 0.05, 0.1, force=10.0, inner=0.002, outer=0.002)}
    run(rig, 2000, events)
    req = rig.requests[1]
    assert req.done.is_set() and req.final_state == HOLDING and not req.within()
    assert req.final_width == pytest.approx(0.03, abs=0.002)      # the cube is smaller


@pytest.mark.parametrize("native", BACKENDS)
def test_a_blocked_move_ends_idle_and_a_new_command_interrupts(native):
    rig = Hand(True, native)
    run(rig, 1500, {0: lambda r: r.command(MOVING, 0.08, 0.1), 800: Hand.add_cube,
                    900: lambda r: r.command(MOVING, 0.0, 0.1)})
    req = rig.requests[1]
    assert req.final_state == IDLE and not req.within()
    assert req.final_width == pytest.approx(0.03, abs=0.002)     # on the cube
    first = rig.c.command(MOVING, 0.08, 0.01)
    second = rig.c.command(MOVING, 0.05, 0.1)
    assert first.done.is_set() and "interrupted" in first.interrupted
    rig.c.stop()
    assert second.done.is_set() and rig.c.mode == IDLE


def test_missing_gains_are_named():
    rig = Hand(True, False)
    params = Params({"arm_id": "panda", "finger1": {"gains": {"p": 1}}}, "/franka_gripper")
    with pytest.raises(ControllerError, match="finger2"):
        FrankaGripperSim("other", rig.hw, params)


def test_commands_from_another_thread_wake_the_world():
    rig = Hand(True, False)
    run(rig, 200, {})
    out = {}
    th = threading.Thread(target=lambda: out.setdefault("req", rig.c.command(MOVING, 0.07, 0.1)))
    th.start()
    th.join()
    assert rig.wakes == 1
    run(rig, 1200, {})
    assert out["req"].done.wait(0) and out["req"].within()


@pytest.mark.parametrize("native", BACKENDS)
def test_stopping_the_controller_leaves_the_last_effort_with_the_hardware(native):
    rig = Hand(True, native)
    run(rig, 2000, {0: lambda r: r.command(MOVING, 0.08, 0.1), 700: Hand.add_cube,
                    800: lambda r: r.command(GRASPING, 0.03, 0.05, force=20.0, inner=0.005, outer=0.005)})
    assert rig.c.mode == HOLDING
    last = [a.last.output for a in rig.c.acts]
    assert rig.mgr.switch([], ["franka_gripper"], STRICT)[0]
    rig.step(10)
    for name, effort in zip(rig.c.joint_names, last):
        res = rig.hw.joints[name]
        assert res.owner is None and res.command == effort
        assert rig.model.joints[name].effort == pytest.approx(effort)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
@pytest.mark.parametrize("native", BACKENDS)
def test_a_command_with_a_number_that_is_not_finite_is_refused_by_name_and_the_grasp_holds_on(native, bad):
    """A move or grasp whose width, speed, force or epsilon is NaN or infinite is refused when it
    is commanded (InputError naming the value), and changes nothing: the grasp in progress keeps
    holding, the World steps on (a NaN or infinite speed or force, accepted, reached the fingers'
    actuators inside the update, which refused it there: the step raised at every step)."""
    rig = Hand(True, native)
    run(rig, 2000, {0: lambda r: r.command(MOVING, 0.08, 0.1), 700: Hand.add_cube,
                    800: lambda r: r.command(GRASPING, 0.03, 0.05, force=20.0, inner=0.005, outer=0.005)})
    assert rig.c.mode == HOLDING
    holding = rig.c.request
    commands = [(MOVING, dict(width=bad, speed=0.1)), (MOVING, dict(width=0.05, speed=bad)),
                (GRASPING, dict(width=0.02, speed=bad, force=10.0)),
                (GRASPING, dict(width=0.02, speed=0.1, force=bad)),
                (GRASPING, dict(width=0.02, speed=0.1, force=10.0, inner=bad)),
                (GRASPING, dict(width=0.02, speed=0.1, force=10.0, outer=bad))]
    for state, kw in commands:
        field = [k for k, v in kw.items() if not math.isfinite(v)][0]
        with pytest.raises(InputError) as exc:
            rig.c.command(state, **kw)
        name = {"inner": "epsilon.inner", "outer": "epsilon.outer"}.get(field, field)
        assert "%s %r" % (name, bad) in str(exc.value) and "franka_gripper" in str(exc.value), str(exc.value)
        run(rig, rig.world.iterations + 50, {})
    assert rig.c.mode == HOLDING and rig.c.request is holding and not holding.interrupted
    assert [a.last.output for a in rig.c.acts] == pytest.approx([-10.0, -10.0], abs=1.0)
