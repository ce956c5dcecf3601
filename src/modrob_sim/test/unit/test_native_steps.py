"""The /gazebo node's batches of native steps (gazebo_ros.fast_steps, physics.native_batch,
ros_control.native_control) give exactly the steps of the Python path: the same states, efforts,
PID internals and published samples, bit for bit, with commands changing mid-run, an effort PID
with antiwindup, a forward effort controller, a joint without controller, a joint_state_controller
and a schedule of after-step work; and the batches do run the steps (all of them, here)."""
import os
import types

import pytest

from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import native_batch
from modrob_sim.ros_control.manager import STRICT

physics = pytest.importorskip("modrob_sim.physics")
FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures", "control")
PERIOD = 0.01           # the "state publisher": every 10 ms of simulated time


class Rig(ControlRig):
    """A 3-joint effort arm with ros_control, the node's hooks reduced to what matters here."""

    def __init__(self, fast, first_state=0.0):
        with open(os.path.join(FIX, "arm_3dof.urdf")) as f:
            super(Rig, self).__init__(f.read().replace("PositionJointInterface", "EffortJointInterface"))
        self.next_t = first_state
        self.ctl = {"jsc": self.joint_state_controller(publish_rate=50)}
        for name, params in (
                ("yaw", {"type": "effort_controllers/JointPositionController", "joint": "yaw",
                         "pid": {"p": 80.0, "i": 30.0, "d": 4.0, "i_clamp": 5.0, "antiwindup": True}}),
                ("shoulder", {"type": "effort_controllers/JointPositionController", "joint": "shoulder",
                              "pid": {"p": 200.0, "i": 50.0, "d": 10.0, "i_clamp": 8.0}})):
            self.ctl[name] = self.mgr.load(name, params)
            self.adapter(name)
        assert self.mgr.switch(list(self.ctl), [], STRICT)[0]
        self.start(fast, batch_after_due=lambda: self.next_t, after=self.after)

    def after(self, t, dt):
        if t + 1e-12 >= self.next_t:
            self.next_t = t + PERIOD
            joints = [j for j in self.model.joints_in_order if j.ode_joint is not None]
            self.log.append(("states", t, [(j.position, j.velocity, j.effort) for j in joints]))

    def snapshot(self):
        pids = [(c.pid.p_error_last, c.pid.i_error, c.pid.d_error, c.pid.cmd, c.pid.terms, c._count,
                 c.last_effort) for c in (self.ctl["yaw"], self.ctl["shoulder"])]
        hw = [(r.position, r.velocity, r.effort, r.command) for r in self.hw.joints.values()]
        return (self.world.time, self.world.iterations, self.world.state_digest(), pids, hw, self.mgr.time)


def run(fast, guard_speed=None, whole=True, first=10, first_state=0.0):
    """1200 steps in passes of 10 (the first of ``first``), commands changed after steps 200, 600
    and 900; ``whole`` False: a pass may end early, as the simulation loop's do (the next pass
    starts there)."""
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
            rig.hw.joints["elbow"].command = 3.0       # the joint without a controller
        if i == 900:
            gains = type(rig.ctl["shoulder"].pid.gains)(150.0, 20.0, 8.0, 4.0, -4.0)
            rig.ctl["shoulder"].pid.set_gains(gains)
        n = min(n, min(e for e in events if e > i) - i)
        assert 0 < rig.step(n, whole=whole) <= n
        n = 10
    return rig


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
def test_batched_steps_equal_python_steps_bit_for_bit():
    ref, fast = run(False), run(True)
    assert fast.fast.batcher is not None
    # every step: the after-step work and the joint_state_controller's samples are done in Python
    # from what the batch's steps read
    assert fast.fast.steps == fast.world.iterations, "the batches ran %d of %d steps" % (
        fast.fast.steps, fast.world.iterations)
    assert len(ref.log) == len(fast.log) > 100
    for a, b in zip(ref.log, fast.log):
        assert a == b
    assert ref.snapshot() == fast.snapshot()
    q = ref.model.joints["yaw"].position
    assert abs(q + 2.0) < 0.3, "the yaw joint did not follow its command (%g)" % q


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
@pytest.mark.parametrize("first", [10, 3, 9])
@pytest.mark.parametrize("first_state", [0.0, PERIOD])
def test_passes_fall_in_step_with_the_publishers(first, first_state):
    """As the node's loop runs them: a pass ends where a batch ended at a state message, and a
    joint_states sample due at a batch's first step is taken before it. Whatever the first
    pass's phase, the 1200 steps then take one batch per 10-step state period (not 9 + 1 steps,
    or 1 + 9 around each joint_states sample) and per guard snapshot, and give the Python path's
    results bit for bit."""
    # first_state PERIOD: the states after the steps ending at 10, 20, .. ms, the joint_states
    # samples at the steps starting at 20, 40, .. ms: the step after a state message
    ref = run(False, first_state=first_state)
    fast = run(True, whole=False, first=first, first_state=first_state)
    assert fast.fast.steps == fast.world.iterations == 1200
    assert ref.log == fast.log and ref.snapshot() == fast.snapshot()
    # + the guard's snapshot every 50 steps, which ends a batch wherever it falls
    snapshots = 1200 // int(fast.world.physics_params["snapshot_interval"])
    assert fast.fast.batches <= 1200 // 10 + snapshots + 2, "%d batches" % fast.fast.batches
    # the same steps in whole passes of 10 started off the state period's phase are cut in two
    cut = run(True, first=first, first_state=first_state) if first != 10 else None
    if cut is not None:
        assert ref.log == cut.log and ref.snapshot() == cut.snapshot()
        assert cut.fast.batches > fast.fast.batches


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
def test_guard_restorations_in_batches_equal_the_python_path():
    ref, fast = run(False, guard_speed=1.0), run(True, guard_speed=1.0)
    events = ref.world.pop_events()
    assert len(events) > 3, "the guard never fired"
    assert events == fast.world.pop_events()
    assert ref.log == fast.log and ref.snapshot() == fast.snapshot()
    assert fast.fast.steps > 0.5 * fast.world.iterations


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
def test_a_step_that_needs_python_is_not_batched():
    rig = Rig(True)
    # the yaw controller's state message is subscribed and due at its first update
    rig.plugin.adapters["yaw"].state_pub = types.SimpleNamespace(get_num_connections=lambda: 1)
    rig.fast.step(1)
    assert rig.fast.steps == 0 and rig.world.iterations == 1
    rig.fast.step(9)                          # the next 9 updates have no state message due
    assert rig.fast.steps == 9 and rig.world.iterations == 10
    rig.world.add_step_hook(after=lambda t, dt: None)   # a hook the node does not know
    rig.fast.step(20)
    assert rig.fast.steps == 9 and rig.world.iterations == 30


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
def test_the_c_loops_clock_bytes_are_rospys():
    """/clock from the C loop at every step: the bytes rospy serialises for the Clock that
    StatePublishers.publish_clock builds from the World's time after that step."""
    import ctypes
    io = pytest.importorskip("io")
    Clock = pytest.importorskip("rosgraph_msgs.msg").Clock
    got = []
    proto = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.POINTER(ctypes.c_ubyte), ctypes.c_uint32)
    fn = proto(lambda _h, data, size: got.append(bytes(data[:size])) or 0)
    rig = Rig(True)
    rig.world.time = 7.0 - 0.0105           # whole seconds and nanosecond rounding on the way
    rig.next_t = 1e9
    clock = types.SimpleNamespace(publish=ctypes.cast(fn, ctypes.c_void_p).value, handle=None, period=0.0,
                                  last=0.0)
    rig.fast.outputs.batch_clock = lambda: clock
    t0 = rig.world.time
    rig.fast.step(30)
    assert rig.fast.steps >= 25 and len(got) == rig.fast.steps

    def rospy_bytes(t):
        msg = Clock()
        c = msg.clock
        c.secs = int(t)
        c.nsecs = int(round((t - c.secs) * 1e9))
        if c.nsecs >= 1000000000:
            c.secs, c.nsecs = c.secs + 1, c.nsecs - 1000000000
        buf = io.BytesIO()
        msg.serialize(buf)
        return buf.getvalue()
    expected, t = [], t0
    for _ in range(30):
        t = t + rig.world.time_step
        expected.append(rospy_bytes(t))
    assert expected[-1] == rospy_bytes(rig.world.time)
    assert len(set(got)) == len(got) and set(got) <= set(expected)
    assert got[0][:4] == (6).to_bytes(4, "little") and got[-1][:4] == (7).to_bytes(4, "little")


@pytest.mark.skipif(not native_batch._RUN, reason="the C loop (with mr_run_batch) is not built")
def test_the_c_loop_publishes_clock_at_steps_whose_after_hooks_are_due():
    """/clock every step: the C loop publishes it at every step it makes, the steps whose
    after-step hooks are due included, and says so (``sent``) for the node's after-step hook."""
    import ctypes
    got = []
    proto = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.POINTER(ctypes.c_ubyte), ctypes.c_uint32)
    fn = proto(lambda _h, data, size: got.append(bytes(data[:size])) or 0)
    rig = Rig(True)
    clock = types.SimpleNamespace(publish=ctypes.cast(fn, ctypes.c_void_p).value, handle=None, period=0.0,
                                  last=0.0, sent=False)
    rig.fast.outputs.batch_clock = lambda: clock
    rig.fast.step(95)
    assert rig.fast.steps == rig.world.iterations == 95
    assert sum(1 for e in rig.log if e[0] == "states") == 10
    assert len(got) == 95 and len(set(got)) == 95 and clock.sent
