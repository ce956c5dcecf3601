"""Where the World stops for Python as the /gazebo node steps it (docs/simulator.md, "How it
works"): the loop's passes end at the hooks' stops (World.advance), the states ride on whatever
stop comes first in their period, a PID controller's state nobody listens to makes no stop, and
the guard's snapshots are taken in C. A 100 Hz joint_state_controller on another phase than the
10 ms grid of the loop's passes and of the states used to stop the World up to four times in every
10 ms, and the guard's snapshots twice in every 100 ms; now once in every 10 ms."""
import os

import pytest
import rospy

from modrob_sim import physics
from modrob_sim.errors import InputError
from modrob_sim.gazebo_ros import state_publishers
from modrob_sim.gazebo_ros.node_params import Params
from modrob_sim.gazebo_ros.testing import ControlRig
from modrob_sim.physics import native as native_mod
from modrob_sim.ros_control.manager import STRICT

FIX = os.path.join(os.path.dirname(__file__), "..", "fixtures")
needs_c = pytest.mark.skipif(native_mod.LIB is None, reason="the C loop is not built")


class FakePublisher(object):
    """Records the simulated time of each message (a ModelStates has no stamp)."""
    world = None

    def __init__(self, topic, msg_class, queue_size=1, latch=False, **kw):
        self.topic, self.times, self.connections = topic, [], 1

    def get_num_connections(self):
        return self.connections

    def publish(self, msg):
        self.times.append(round(FakePublisher.world.time, 6))

    def unregister(self):
        pass


def _count_stops(world):
    """Counts the native stretches (each one ends with a stop for Python)."""
    backend = world._backend
    run = backend.run
    stops = []

    def counting(*args):
        r = run(*args)
        if r is not None:
            stops.append(round(r.time, 6))
        return r
    backend.run = counting
    return stops


class NodeRig(ControlRig):
    """The 3-joint arm under a 100 Hz joint_state_controller and three effort position PIDs, with
    the node's StatePublishers (100 Hz states, 10 Hz markers) on the same hooks as the node's."""

    def __init__(self, monkeypatch, pid_state_wanted=False):
        monkeypatch.setattr(rospy, "Publisher", FakePublisher)
        monkeypatch.setattr(state_publishers, "publisher", FakePublisher)
        with open(os.path.join(FIX, "control", "arm_3dof.urdf")) as f:
            xml = f.read().replace("PositionJointInterface", "EffortJointInterface")
        super(NodeRig, self).__init__(xml)
        FakePublisher.world = self.world
        self.out = state_publishers.StatePublishers(self.world, Params())
        self.world.step(3)              # the controllers start at 3 ms: their phase is not the grid's
        self.ctl = {"jsc": self.joint_state_controller(publish_rate=100)}
        for j in ("yaw", "shoulder", "elbow"):
            self.ctl[j] = self.mgr.load(j, {"type": "effort_controllers/JointPositionController", "joint": j,
                                            "pid": {"p": 100.0, "i": 0.0, "d": 5.0}})
            self.ctl[j].state_wanted = lambda: pid_state_wanted
            self.adapter(j)
        assert self.mgr.switch(list(self.ctl), [], STRICT)[0]
        out = self.out
        self.start(True, batch_after_due=out.after_due, after=lambda t, dt: out.after_step())

    def run_passes(self, seconds, batch=10):
        """The simulation loop's passes (SimulationLoop.run_once at real_time_factor 0: the node's
        _step), for ``seconds`` of simulated time; returns the passes' lengths."""
        lengths = []
        end = self.world.time + seconds - 1e-9
        while self.world.time < end:
            lengths.append(self.world.advance(batch))
            self.out.after_pass()
        return lengths


@needs_c
def test_the_world_stops_once_per_controller_update(monkeypatch):
    rig = NodeRig(monkeypatch)
    rig.run_passes(0.1)             # the controllers' first updates, the grid's first states
    stops = _count_stops(rig.world)
    states = rig.out._model_states_pub.times
    del states[:]
    counted = rig.world.stops
    lengths = rig.run_passes(0.5)
    assert rig.world.stops - counted == len(stops)
    # the joint_state_controller's updates at .xx3 are the only stops (the guard takes its snapshots
    # in C); the passes end there too
    assert len(stops) == 50 and all(round(t * 1000) % 10 == 3 for t in stops), stops[:12]
    assert lengths == [10] * 50, lengths[:12]
    # one state message per 10 ms period of simulated time, from the period's first stop
    assert states == stops
    assert len(rig.log) >= 50            # the joint_state_controller's 100 Hz samples
    # the World counts its stops, and the node's real-time factor line gives them per simulated s
    logged = []
    monkeypatch.setattr(rospy, "loginfo", logged.append)
    rig.out._last_rtf_log = -1e9
    rig.out._rtf_log_from = (rig.world.stops - 100, rig.world.time - 1.0)
    rig.out.publish_rtf(9.5, rig.world.time, False)
    assert logged == ["sim time %.2f s, real-time factor 9.50, hooks in Python at 100 steps per simulated s"
                      % rig.world.time]


@needs_c
def test_a_pid_state_with_a_listener_is_collected_after_its_update(monkeypatch):
    rig = NodeRig(monkeypatch, pid_state_wanted=True)
    rig.run_passes(0.1)
    stops = _count_stops(rig.world)
    collected = []
    collect = rig.ctl["elbow"].collect

    def counting():
        collect()
        collected.append((rig.world.time, rig.ctl["elbow"].pending["stamp"]))
    rig.ctl["elbow"].collect = counting
    rig.run_passes(0.5)
    # every 10th update of the PID (each 10 ms) also stops after its step, to read what it did
    assert len(collected) == 50
    assert all(abs(t - stamp - 0.001) < 1e-9 for t, stamp in collected)
    assert len(stops) == 100


@needs_c
def test_a_pid_state_nobody_listens_to_is_not_collected(monkeypatch):
    rig = NodeRig(monkeypatch)
    collected = []
    rig.ctl["elbow"].collect = lambda: collected.append(rig.world.time)
    rig.run_passes(0.3)
    assert collected == [] and rig.ctl["elbow"].pending is None


def _falling_boxes(native):
    world = physics.World(time_step=0.001, native=native)
    with open(os.path.join(FIX, "physics", "box.urdf")) as f:
        xml = f.read()
    for i in range(3):
        world.add_urdf("box%d" % i, xml, pose=((0.3 * i, 0.0, 0.2 + 0.1 * i), (0.0, 0.0, 0.0, 1.0)))
    return world


@needs_c
def test_advance_ends_at_the_first_stop_for_python_and_makes_the_steps_of_step():
    a, b = _falling_boxes(None), _falling_boxes(None)
    seen = []
    for w, log in ((a, seen), (b, [])):
        state = {"next": 0.0045}

        def after(t, dt, state=state, log=log):
            if t + 1e-9 >= state["next"]:
                state["next"] += 0.007
                log.append(round(t, 6))
        w.add_step_hook(after=after, after_due=lambda state=state: state["next"])
    lengths = []
    while a.iterations < 200:
        lengths.append(a.advance(min(10, 200 - a.iterations)))
    b.step(200)
    # the hook's times (5, 12, 19 .. ms) end the passes; in between the passes run their 10 steps
    assert lengths[:4] == [5, 7, 7, 7], lengths
    assert a.time == pytest.approx(b.time) and a.iterations == b.iterations == 200
    for m in a.models:
        assert a.models[m].pose == b.models[m].pose
    assert seen[:3] == [0.005, 0.012, 0.019]


@pytest.mark.parametrize("native", [None, False])
def test_a_hook_due_at_every_step_keeps_passes_of_n(native):
    """A hook without a due time stops the World at every step (natively: stretches of one step;
    on the pure-Python backend: every step in Python): a pass still makes its n steps (one pass
    per step would only add the loop's own work)."""
    if native is None and native_mod.LIB is None:
        pytest.skip("the C loop is not built")
    w = _falling_boxes(native)
    calls = []
    w.add_step_hook(after=lambda t, dt: calls.append(t))
    assert [w.advance(10) for _ in range(5)][1:] == [10] * 4
    assert w.iterations == len(calls) == w.stops and w.iterations >= 41
    with pytest.raises(InputError):
        w.advance(0)


SPINNER = """<robot name="spinner"><link name="world"/>
  <link name="rod"><inertial><origin xyz="0 0 -0.25"/><mass value="1.0"/>
    <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.0001"/></inertial>
    <collision><origin xyz="0 0 -0.25"/><geometry><box size="0.02 0.02 0.5"/></geometry></collision></link>
  <joint name="spin" type="continuous"><parent link="world"/><child link="rod"/>
    <origin xyz="0 0 1.5"/><axis xyz="0 1 0"/><limit effort="0" velocity="100"/></joint>
</robot>"""


def _spun_then_blown(native):
    """A rod driven around its pivot for turns (its joint counts them), then by an absurd effort:
    the guard restores it to its last snapshot. ``native``: the C loop steps the World (and takes
    the snapshots), else the pure-Python backend (the World's guard takes them)."""
    from modrob_sim.physics import actuators
    w = physics.World(time_step=0.001, native=native)
    w.set_physics_params(snapshot_interval=100)
    m = w.add_urdf("spinner", SPINNER)
    a = w.add_actuator(m.joints["spin"], actuators.EFFORT)
    a.command = 20.0
    w.step(699)
    stretches = w.native_steps + w.hooked_steps
    a.command = 1e12
    w.step(30)
    a.command = 0.0
    w.step(100)
    return w, m, stretches


@needs_c
def test_the_guard_restores_the_c_loops_snapshot_as_its_own():
    fast, m, stretches = _spun_then_blown(None)
    slow, ms, _ = _spun_then_blown(False)
    assert fast.native and not slow.native
    assert stretches == 699             # no step made in Python for the guard's 6 snapshots
    events = fast.pop_events()
    assert [(e.model, e.time) for e in events] == [(e.model, e.time) for e in slow.pop_events()]
    assert events and "runaway" in events[0].reason
    # restored to the snapshot at step 600 (with the turns counted then, two fewer than at the
    # blow-up), then the same steps
    assert m.joints["spin"].position == ms.joints["spin"].position
    assert abs(m.joints["spin"].position) > 2 * 3.141592653589793
    assert fast.state_digest() == slow.state_digest()
