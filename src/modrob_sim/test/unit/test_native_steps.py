"""The World's native stretches between the due times of its hooks (World.step on the native
backend, mr_run_steps) give exactly the steps of calling every hook at every step: the same
states, efforts, actuator internals and published samples, bit for bit, with commands and gains
changing mid-run, an effort PID with antiwindup, a forward effort controller, a
joint_state_controller and a schedule of after-step work; and the stretches do run the steps."""
import math
import os

import pytest

from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import actuators as A
from modrob_sim.physics import native as native_mod
from modrob_sim.physics.world import next_time
from modrob_sim.ros_control.manager import STRICT

physics = pytest.importorskip("modrob_sim.physics")
FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
PERIOD = 0.01           # the "state publisher": every 10 ms of simulated time
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


class Rig(ControlRig):
    """A 3-joint effort arm with ros_control, the node's hooks reduced to what matters here."""

    def __init__(self, fast, first_state=0.0, states_wanted=True):
        with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
            super(Rig, self).__init__(f.read().replace("PositionJointInterface", "EffortJointInterface"))
        self.next_t = first_state
        self.ctl = {"jsc": self.joint_state_controller(publish_rate=50)}
        for name, params in (
                ("yaw", {"type": "effort_controllers/JointPositionController", "joint": "yaw",
                         "pid": {"p": 80.0, "i": 30.0, "d": 4.0, "i_clamp": 5.0, "antiwindup": True}}),
                ("shoulder", {"type": "effort_controllers/JointPositionController", "joint": "shoulder",
                              "pid": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0}}),
                ("elbow", {"type": "effort_controllers/JointEffortController", "joint": "elbow"})):
            self.ctl[name] = self.mgr.load(name, params)
            self.adapter(name, after_update=self._state_logger(name))
            if not states_wanted and hasattr(self.ctl[name], "state_wanted"):
                self.ctl[name].state_wanted = lambda: False
        assert self.mgr.switch(list(self.ctl), [], STRICT)[0]
        self.start(fast, batch_after_due=lambda: self.next_t, after=self.after)

    def _state_logger(self, name):
        def after_update(t):
            c = self.ctl[name]
            data, c.pending = c.pending, None
            if data is not None:
                self.log.append(("state", name, t, data))
        return after_update

    def after(self, t, dt):
        if t + 1e-12 >= self.next_t:
            self.next_t = t + PERIOD
            joints = [j for j in self.model.joints_in_order if j.ode_joint is not None]
            self.log.append(("states", t, [(j.position, j.velocity, j.effort) for j in joints]))

    def snapshot(self):
        acts = [(a.pid_state(), a.last, a.command, a.gains.as_dict()) for a in self.world.actuators]
        joints = [(j.position, j.velocity, j.effort) for j in self.model.joints_in_order]
        return (self.world.time, self.world.iterations, self.world.state_digest(), acts, joints)


def run(fast, guard_speed=None, first=10, first_state=0.0):
    """1200 steps in passes of 10 (the first of ``first``), commands changed after steps 200, 600
    and 900."""
    rig = Rig(fast, first_state)
    if guard_speed is not None:             # the guard restores the arm again and again
        rig.world.set_physics_params(guard_max_angular_velocity=guard_speed)
    events = [200, 600, 900, 1200]
    n = first
    while rig.world.iterations < 1200:
        i = rig.world.iterations
        if i == 200:
            rig.ctl["yaw"].set_command(1.2)
            rig.ctl["shoulder"].set_command(-0.7)
        if i == 600:
            rig.ctl["yaw"].set_command(-2.0)
            rig.ctl["elbow"].set_command(3.0)
        if i == 900:
            gains = type(rig.ctl["shoulder"].pid.gains)(150.0, 20.0, 8.0, 4.0, -4.0)
            rig.ctl["shoulder"].pid.set_gains(gains)
        n = min(n, min(e for e in events if e > i) - i)
        rig.step(n)
        n = 10
    return rig


@needs_c
def test_batched_steps_equal_python_steps_bit_for_bit():
    ref, fast = run(False), run(True)
    assert fast.world.native
    # the steps in Python: the updates with a state message (every 10th), a joint_states sample
    # (every 20th), a command or a gain change; all others in the C loop's batches
    assert fast.world.native_steps > 0.85 * fast.world.iterations, "the batches ran %d of %d steps" % (
        fast.world.native_steps, fast.world.iterations)
    assert len(ref.log) == len(fast.log) > 300
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    assert sum(1 for e in ref.log if e[0] == "state") == 2 * 120
    q = ref.model.joints["yaw"].position
    assert abs(q + 2.0) < 0.3, "the yaw joint did not follow its command (%g)" % q


@needs_c
@pytest.mark.parametrize("first", [10, 3, 9])
@pytest.mark.parametrize("first_state", [0.0, PERIOD])
def test_passes_of_any_phase_give_the_same_steps(first, first_state):
    """As the node's loop runs them, in passes of 10 steps: whatever the first pass's phase
    against the publishers' schedule, the steps give the every-hook-every-step results bit for
    bit."""
    ref = run(False, first_state=first_state)
    fast = run(True, first=first, first_state=first_state)
    assert fast.world.iterations == 1200
    assert ref.log == fast.log and ref.snapshot() == fast.snapshot()


@needs_c
def test_guard_restorations_in_batches_equal_the_python_path():
    ref, fast = run(False, guard_speed=1.0), run(True, guard_speed=1.0)
    events = ref.world.pop_events()
    assert len(events) > 3, "the guard never fired"
    assert events == fast.world.pop_events()
    assert ref.log == fast.log and ref.snapshot() == fast.snapshot()
    assert fast.world.native_steps > 0.5 * fast.world.iterations


@needs_c
def test_updates_run_in_python_only_when_due():
    rig = Rig(True, states_wanted=False)
    rig.next_t = 1e9
    rig.step(1)                               # the first update: every controller starts its schedule
    assert rig.world.native_steps == 0 and rig.world.iterations == 1
    rig.step(18)                              # nothing due until the joint_states sample at 20 ms
    assert rig.world.native_steps == 18 and rig.world.iterations == 19
    rig.ctl["yaw"].set_command(0.4)           # a command waits: the next step is an update
    rig.step(1)
    assert rig.world.native_steps == 18
    rig.step(10)
    assert rig.world.native_steps == 18 + 9           # the joint_states sample at 20 ms is in Python
    rig.ctl["yaw"].state_wanted = lambda: True   # a subscriber: every 10th update in Python
    rig.step(40)                # Python: the state updates at 30, 40, 50, 60 ms (joint_states at 40, 60)
    assert rig.world.native_steps == 27 + 40 - 4, rig.world.native_steps
    calls = []
    rig.world.add_step_hook(after=lambda t, dt: calls.append(t))   # no due time: every step
    rig.step(20)
    # each step is made in C (but the two state updates) and the new hook runs after every one
    assert rig.world.native_steps == 63 + 18 and rig.world.iterations == 90 and len(calls) == 20


@needs_c
def test_the_step_observer_sees_every_native_step():
    """World.set_step_observer: the C function is called after every step the World makes
    natively (also one whose before-hooks ran in Python first), with that step's time (the node's
    /clock through roscpp), never for a step made in Python (whose hooks run instead)."""
    import ctypes
    seen = []
    proto = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_double)
    fn = proto(lambda _user, t: seen.append(t))
    rig = Rig(True, states_wanted=False)
    rig.next_t = 1e9
    rig.world.set_step_observer(ctypes.cast(fn, ctypes.c_void_p).value, None)
    times = []
    rig.world.add_step_hook(after=lambda t, dt: times.append(t), after_due=lambda: float("inf"))
    rig.step(95)
    # the first update and the joint_states samples (20, 40, .. ms) run their hooks in Python and
    # their physics in C; the rest in C alone
    assert rig.world.iterations == 95 and rig.world.native_steps == 95 - 5 and rig.world.hooked_steps == 5
    assert len(seen) == 95 and len(set(seen)) == len(seen)
    expected, t = [], 0.0
    for _ in range(95):
        t = next_time(t, rig.world.time_step)
        expected.append(t)
    assert set(seen) <= set(expected) and seen == sorted(seen)
    assert len(set(seen) | set(times)) == 95      # every step: observed natively or its hooks ran
    rig.model.joints["yaw"].set_effort(0.0)      # an effort for the next step: made in C as well
    rig.step(1)
    assert rig.world.iterations - rig.world.native_steps - rig.world.hooked_steps == 0
    assert len(seen) == 96
    # a wrench for one step: the World makes that step in Python
    rig.model.links["l1"].add_wrench((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), duration=0.5 * rig.world.time_step)
    rig.step(1)
    assert rig.world.iterations - rig.world.native_steps - rig.world.hooked_steps == 1
    assert len(seen) == 96 and abs(times[-1] - 0.097) < 1e-9
    rig.world.set_step_observer(None, None)
    rig.step(10)
    assert len(seen) == 96


@needs_c
def test_a_wake_while_the_due_times_are_asked_is_not_lost():
    """A ROS callback that stores work and wakes the World while the loop thread asks the due
    times (after the hook's due time was read): the stretch that follows ends at once, and the hook
    takes the work at the next step, not after the n steps the stretch would have run."""
    world = physics.World(time_step=0.001, native=True)
    work, taken, asked = [], [], []

    def before_due():
        asked.append(world.time)
        if len(asked) == 1:         # read as "nothing to do", then the callback comes
            work.append("command")
            world.wake()
            return math.inf
        return world.time if work else math.inf

    def before(t, dt):
        if work:
            taken.append(round(t, 6))
            del work[:]
    world.add_step_hook(before=before, before_due=before_due)
    world.step(50)
    assert world.iterations == 50 and taken == [0.0], taken


TABLE = """<robot name="table"><link name="top">
  <collision><origin xyz="0.6 0.6 0.3"/><geometry><box size="0.6 0.6 0.05"/></geometry></collision></link>
  <gazebo><static>true</static></gazebo></robot>"""
CAN = """<robot name="can"><link name="can">
  <inertial><mass value="0.2"/>
    <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.0001"/></inertial>
  <collision><geometry><cylinder radius="0.03" length="0.1"/></geometry></collision></link></robot>"""


def efforts_run(native):
    """A PD hook that gives every joint an effort with set_effort at every step, as the physics
    core benchmark's: revolute joints beyond their effort limit at first, prismatic fingers (one
    given two add_effort calls a step, their sum beyond its limit), the elbow with an actuator of
    its own (its efforts go to the actuator); a can dropped on a table falls asleep. Then no hook:
    an effort given between step() calls, for a stretch of 20 steps or a single step. Returns the
    world, what was seen after each step and the steps that were made in Python."""
    w = physics.World(time_step=0.001, seed=5, native=native)
    with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
        arm = w.add_urdf("arm", f.read().replace("PositionJointInterface", "EffortJointInterface"))
    with open(os.path.join(FIX, "gripper_parallel.urdf")) as f:
        grip = w.add_urdf("gripper", f.read(), pose=((-0.8, 0.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    w.add_urdf("table", TABLE)
    w.add_urdf("can", CAN, pose=((0.6, 0.6, 0.38), (0.0, 0.0, 0.0, 1.0)))
    yaw, shoulder, elbow = (arm.joints[n] for n in ("yaw", "shoulder", "elbow"))
    f1, f2 = grip.joints["finger_joint1"], grip.joints["finger_joint2"]
    a_el = w.add_actuator(elbow, A.EFFORT, effort_limit=5.0)
    a_el.command = 2.0
    joints = (yaw, shoulder, elbow, f1, f2)
    hold = ((yaw, 1.2), (shoulder, -0.8), (elbow, 0.6))

    def pd(t, _dt):
        for j, q in hold:
            j.set_effort(300.0 * (q - j.position) - 6.0 * j.velocity)
        f1.set_effort(30.0 if t < 0.2 else -3.0)
        f2.add_effort(8.0)
        f2.add_effort(15.0 if t < 0.3 else -12.0)

    def seen():
        return ([(j.position, j.velocity, j.effort) for j in joints], a_el.last, w.time, w.state_digest())
    log, python_steps = [], []

    def step(n):
        before = w.iterations - w.native_steps - w.hooked_steps
        w.step(n)
        python_steps.append(w.iterations - w.native_steps - w.hooked_steps - before)
        log.append(seen())
    hook = w.add_step_hook(before=pd)
    for _ in range(600):
        step(1)
    w.remove_step_hook(hook)
    for k in range(6):
        yaw.set_effort(-20.0)
        elbow.set_effort(1.0)
        f1.add_effort(4.0)
        step(20 if k % 2 else 1)
    return w, log, python_steps


@needs_c
def test_set_effort_steps_are_native_and_equal_the_python_steps_bit_for_bit():
    """Efforts queued with set_effort/add_effort no longer keep a step in Python on the native
    backend: its first native step applies them (after the model actuators, as World._apply_forces:
    the same states, reported efforts and actuator outputs as the pure-Python backend, bit for
    bit), and the efforts last one step, also within a longer stretch."""
    wp, pure, _ = efforts_run(False)
    wn, nat, python_steps = efforts_run(True)
    assert not wp.native and wn.native
    assert len(pure) == len(nat) == 606
    for k, (a, b) in enumerate(zip(pure, nat)):
        assert a == b, "after step() call %d: %r != %r" % (k, a, b)
    assert sum(python_steps) == 0, "steps made in Python: %d" % sum(python_steps)
    assert wn.hooked_steps == 600 and wn.native_steps == wn.iterations - 600
    # what the run did: the arm held near its targets, the can asleep on the table (still, no
    # contacts made), the efforts reported for one step only
    assert abs(wn.models["arm"].joints["yaw"].position - 1.2) < 0.05
    can = wn.models["can"].links["can"]
    assert can.pose[0][2] > 0.3 and can.twist == ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)) and not wn.contacts()
    first = [e for _p, _v, e in nat[0][0]]                      # clamped to the joints' limits
    assert first == [50.0, -50.0, 50.0, 20.0, 20.0], first
    assert [e for _p, _v, e in nat[599][0]][3:] == [-3.0, -4.0]
    after = [[e for _p, _v, e in s[0]] for s in nat[600:]]
    assert [e[0] for e in after] == [-20.0, 0.0] * 3 and [e[3] for e in after] == [4.0, 0.0] * 3
    assert [e[2] for e in after] == [3.0, 2.0] * 3              # the elbow's actuator: 2 + 1, then 2
