"""Trajectory sampling (ros_controllers' spline rules) and the trajectory controllers' goal
handling: tolerances, unknown joints, preemption, cancel."""
import math

import pytest

from modrob_sim.ros_control.controllers.joint_trajectory import (
    GOAL_TOLERANCE_VIOLATED, INVALID_GOAL, INVALID_JOINTS, PATH_TOLERANCE_VIOLATED, TrajectoryPoint)
from modrob_sim.ros_control.hardware import RobotHWSim
from modrob_sim.ros_control.manager import ControllerManager
from modrob_sim.ros_control.testing import IntegratorJoint, IntegratorModel, simple_transmissions
from modrob_sim.ros_control.trajectory import State, Trajectory, hold_trajectory

JOINTS = ["a", "b", "c"]


def test_linear_cubic_quintic_hit_their_end_conditions():
    lin = Trajectory(0.0, State([0.0]), [(2.0, State([1.0]))])
    assert lin.segments[0].order == 1
    assert lin.sample(1.0)[0][0] == pytest.approx(0.5) and lin.sample(1.0)[1][0] == pytest.approx(0.5)
    cub = Trajectory(0.0, State([0.0], [0.0]), [(2.0, State([1.0], [0.0]))])
    assert cub.segments[0].order == 3
    p, v, a = cub.sample(1.0)
    assert p[0] == pytest.approx(0.5) and v[0] == pytest.approx(0.75)
    assert cub.sample(2.0 - 1e-9)[1][0] == pytest.approx(0.0, abs=1e-6)
    qui = Trajectory(0.0, State([0.0], [1.0], [0.0]), [(1.0, State([2.0], [-1.0], [3.0]))])
    assert qui.segments[0].order == 5
    seg = qui.segments[0]
    p, v, a = seg.sample(1.0)
    assert (p[0], v[0], a[0]) == pytest.approx((2.0, -1.0, 3.0))
    p, v, a = seg.sample(0.0)
    assert (p[0], v[0], a[0]) == pytest.approx((0.0, 1.0, 0.0))


def test_sampling_is_continuous_across_points_and_holds_after_the_end():
    traj = Trajectory(0.0, State([0.0], [0.0]), [(1.0, State([1.0], [0.5])), (2.0, State([1.5], [0.0]))])
    for t in (1.0, 2.0):
        left, right = traj.sample(t - 1e-7), traj.sample(t + 1e-7)
        assert left[0][0] == pytest.approx(right[0][0], abs=1e-5)
    assert traj.sample(5.0) == ([1.5], [0.0], [0.0])
    assert traj.sample(-1.0)[0] == [0.0]


def test_hold_trajectory_decelerates_over_stop_duration():
    h = hold_trajectory(0.0, [1.0], [2.0], stop_duration=0.5)
    assert h.sample(0.5)[0][0] == pytest.approx(1.5) and h.sample(0.5)[1][0] == 0.0
    assert hold_trajectory(0.0, [1.0], [2.0]).sample(1.0)[0] == [1.0]


def rig(kind="position_controllers/JointTrajectoryController", extra=None, iface="PositionJointInterface"):
    joints = [IntegratorJoint(name=n, inertia=0.05, damping=0.1, lower=-3.0, upper=3.0, effort_limit=50.0,
                              velocity_limit=10.0) for n in JOINTS]
    hw = RobotHWSim({j.name: j for j in joints}, simple_transmissions({n: iface for n in JOINTS}))
    mgr = ControllerManager(hw, "/arm")
    params = {"type": kind, "joints": JOINTS,
              "constraints": {"goal_time": 0.5, "stopped_velocity_tolerance": 0.05,
                              "a": {"trajectory": 0.2, "goal": 0.01}}}
    params.update(extra or {})
    ctl = mgr.load("arm_controller", params)
    assert mgr.switch(["arm_controller"], [], 2)[0]
    return joints, mgr, ctl, IntegratorModel(joints)


def three_points():
    return [TrajectoryPoint([0.2, -0.1, 0.3], time_from_start=0.5),
            TrajectoryPoint([0.5, 0.2, 0.6], time_from_start=1.0),
            TrajectoryPoint([0.4, 0.4, 0.8], [0.0, 0.0, 0.0], time_from_start=1.5)]


def run_until_event(ctl, mgr, model, seconds):
    events = []

    def grab(t):
        events.extend(ctl.events)
        del ctl.events[:]
    model.run(mgr, seconds, record=grab)
    return events


def test_position_goal_succeeds_and_ends_within_tolerance():
    joints, mgr, ctl, model = rig()
    ok, code, text = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    assert ok, text
    events = run_until_event(ctl, mgr, model, 2.5)
    assert events == [("g1", "succeeded", 0, "")]
    for j, target in zip(joints, [0.4, 0.4, 0.8]):
        assert j.position == pytest.approx(target, abs=0.01)
    assert ctl.pending["joint_names"] == JOINTS


def test_effort_trajectory_controller_tracks_with_gains():
    gains = {n: {"p": 400.0, "d": 20.0} for n in JOINTS}
    joints, mgr, ctl, model = rig("effort_controllers/JointTrajectoryController", {"gains": gains},
                                  iface="EffortJointInterface")
    ok, _, text = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    assert ok, text
    events = run_until_event(ctl, mgr, model, 2.5)
    assert events[0][:2] == ("g1", "succeeded")
    assert joints[0].position == pytest.approx(0.4, abs=0.01)


def test_unknown_joint_is_rejected_by_name():
    joints, mgr, ctl, model = rig()
    ok, code, text = ctl.submit(["a", "b", "wrist"], three_points(), 0.0, 0.0, goal_id="g")
    assert not ok and code == INVALID_JOINTS and "'wrist'" in text and "arm_controller" in text
    ok, code, text = ctl.submit(["a", "b"], [TrajectoryPoint([0, 0], time_from_start=1)], 0.0, 0.0,
                                goal_id="g")
    assert not ok and code == INVALID_JOINTS and "'c'" in text


def test_malformed_points_are_invalid_goals():
    joints, mgr, ctl, model = rig()
    bad = [TrajectoryPoint([0.1, 0.2, 0.3], time_from_start=1.0), TrajectoryPoint([0.1, 0.2, 0.3],
                                                                                  time_from_start=1.0)]
    assert ctl.submit(JOINTS, bad, 0.0, 0.0, goal_id="g")[1] == INVALID_GOAL
    assert ctl.submit(JOINTS, [TrajectoryPoint([0.1], time_from_start=1.0)], 0.0, 0.0, "g")[1] == INVALID_GOAL
    nan = [TrajectoryPoint([0.1, float("nan"), 0.3], time_from_start=1.0)]
    ok, code, text = ctl.submit(JOINTS, nan, 0.0, 0.0, goal_id="g")
    assert code == INVALID_GOAL and "NaN" in text
    for t in (-1.0, -0.5):  # -0.5 s was accepted, -1 s refused as "point 0 at -1 s follows -1 s"
        past = [TrajectoryPoint([0.1, 0.2, 0.3], time_from_start=t)]
        ok, code, text = ctl.submit(JOINTS, past, 0.0, 5.0, goal_id="g")
        assert not ok and code == INVALID_GOAL
        assert "point 0 has a negative time_from_start (%g s)" % t in text


def test_new_goal_preempts_the_old_one():
    joints, mgr, ctl, model = rig()
    assert ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")[0]
    model.run(mgr, 0.3)
    assert ctl.submit(JOINTS, [TrajectoryPoint([0.0, 0.0, 0.0], time_from_start=0.5)], 0.0, model.time,
                      goal_id="g2")[0]
    events = run_until_event(ctl, mgr, model, 1.5)
    assert ("g1", "preempted") == ctl_first(events, "g1")
    assert ("g2", "succeeded") == ctl_first(events, "g2")


def ctl_first(events, gid):
    for e in events:
        if e[0] == gid:
            return e[:2]
    return None


def effort_rig():
    gains = {n: {"p": 400.0, "d": 20.0} for n in JOINTS}
    return rig("effort_controllers/JointTrajectoryController", {"gains": gains}, iface="EffortJointInterface")


def test_path_tolerance_violation_aborts_and_holds():
    joints, mgr, ctl, model = effort_rig()
    mgr.hw.joints["a"].effort_limit = 0.01      # joint a is too weak to follow: path error grows
    ok, _, _ = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    assert ok
    events = run_until_event(ctl, mgr, model, 2.0)
    assert events and events[0][1] == "aborted" and events[0][2] == PATH_TOLERANCE_VIOLATED
    assert "'a'" in events[0][3] and "0.2" in events[0][3]


def test_goal_tolerance_violation_after_goal_time():
    joints, mgr, ctl, model = effort_rig()
    mgr.hw.joints["c"].effort_limit = 0.02      # c lags far behind; c has no path tolerance
    tol = [type("T", (), {"name": "c", "position": 0.02, "velocity": 0.0, "acceleration": 0.0})()]
    ok, _, _ = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1", goal_tolerance=tol)
    assert ok
    events = run_until_event(ctl, mgr, model, 3.0)
    assert events[0][1] == "aborted" and events[0][2] == GOAL_TOLERANCE_VIOLATED
    assert "'c'" in events[0][3] and "after the trajectory's end" in events[0][3]


def test_goal_time_tolerance_from_the_goal_overrides_the_default():
    joints, mgr, ctl, model = effort_rig()
    ok, _, _ = ctl.submit(JOINTS, three_points(), 0.0, 0.0, goal_id="g1", goal_time_tolerance=2.0)
    assert ok and ctl.goal.goal_time == 2.0 and ctl.goal.goal[0].position == 0.01
    assert ctl.goal.goal[1].velocity == 0.05 and ctl.goal.path[0].position == 0.2


def test_cancel_holds_and_reports():
    joints, mgr, ctl, model = rig()
    ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    model.run(mgr, 0.4)
    assert ctl.cancel("g1", model.time)
    held = [j.position for j in joints]
    model.run(mgr, 0.5)
    assert [j.position for j in joints] == pytest.approx(held, abs=0.02)
    assert ctl.events[-1][:2] == ("g1", "canceled")


def test_continuous_joint_trajectory_starts_the_short_way():
    joints = [IntegratorJoint(name="w", type_="continuous", inertia=0.05, effort_limit=50.0, position=3.0)]
    hw = RobotHWSim({"w": joints[0]}, simple_transmissions({"w": "PositionJointInterface"}))
    mgr = ControllerManager(hw, "/r")
    ctl = mgr.load("t", {"type": "position_controllers/JointTrajectoryController", "joints": ["w"]})
    mgr.switch(["t"], [], 2)
    model = IntegratorModel(joints)
    ctl.submit(["w"], [TrajectoryPoint([-3.0], time_from_start=1.0)], 0.0, 0.0)
    rec = []
    model.run(mgr, 1.2, record=lambda t: rec.append(joints[0].position))
    assert min(rec) > 2.99 and rec[-1] == pytest.approx(2 * math.pi - 3.0, abs=1e-6)


def test_missing_gains_for_effort_type_names_the_path():
    from modrob_sim.errors import ControllerError
    with pytest.raises(ControllerError, match="/arm/arm_controller/gains"):
        rig("effort_controllers/JointTrajectoryController", iface="EffortJointInterface")


def _reference_build(ctl, joint_names, points, start, now):
    """The trajectory built point by point, as the controller did before it prepared segments off
    the loop thread (the semantics the prepared form must keep)."""
    from modrob_sim.ros_control import angles
    index = {j: i for i, j in enumerate(joint_names)}
    cur_pos, cur_vel, cur_acc = ctl._current_desired(now)
    offsets = [0.0] * ctl.n
    for c, j in enumerate(ctl.joints):
        if j.type == "continuous" and j.name in index:
            first = points[0].positions[index[j.name]]
            offsets[c] = cur_pos[c] + angles.shortest_angular_distance(cur_pos[c], first) - first
    out = []
    for p in points:
        if start + p.time_from_start <= now:
            continue
        pos, vel, acc = [], [], []
        for c, j in enumerate(ctl.joint_names):
            if j in index:
                i = index[j]
                pos.append(p.positions[i] + offsets[c])
                vel.append(p.velocities[i] if p.velocities else None)
                acc.append(p.accelerations[i] if p.accelerations else None)
            else:
                pos.append(cur_pos[c])
                vel.append(0.0 if p.velocities else None)
                acc.append(0.0 if p.accelerations else None)
        out.append((start + p.time_from_start, State(pos, None if vel[0] is None else vel,
                                                     None if acc[0] is None else acc)))
    return Trajectory(now, State(cur_pos, cur_vel, cur_acc), out)


@pytest.mark.parametrize("kind", ["linear", "cubic", "quintic"])
@pytest.mark.parametrize("partial", [False, True])
def test_a_trajectory_prepared_off_the_loop_samples_as_one_built_point_by_point(kind, partial):
    import random
    rng = random.Random(7)
    joints, mgr, ctl, model = rig(extra={"allow_partial_joints_goal": True})
    joints[1].type = "continuous"
    model.run(mgr, 0.3)
    names = ["c", "b"] if partial else ["c", "a", "b"]
    points, t = [], 0.0
    for _ in range(300):
        t += rng.uniform(0.001, 0.02)
        k = len(names)
        vel = [rng.uniform(-1, 1) for _ in range(k)] if kind != "linear" else []
        acc = [rng.uniform(-1, 1) for _ in range(k)] if kind == "quintic" else []
        points.append(TrajectoryPoint([rng.uniform(-3, 3) for _ in range(k)], vel, acc, t))   # in the limits
    assert ctl.check_points(names, points)[0]
    prepared = ctl.prepare(names, points)          # what the ROS callback does, any thread
    now = mgr.time
    for start in (now - 1.234, now, now + 0.5):   # points in the past are skipped
        placed = ctl._build(names, points, start, now, prepared)
        ref = _reference_build(ctl, names, points, start, now)
        assert placed.end_time == ref.end_time
        for i in range(2000):
            ts = now - 0.1 + i * (t + 0.7) / 2000.0
            a, b = placed.sample(ts), ref.sample(ts)
            for x, y in zip(a, b):
                # relative vs absolute segment times: rounding, amplified in accelerations
                assert x == pytest.approx(y, rel=1e-6, abs=1e-7), (start, ts)
    everything_past = ctl._build(names, points, now - 100.0, now, prepared)  # jumps to the last point
    assert everything_past.sample(now)[0] == pytest.approx(ref.sample(ref.end_time)[0], abs=1e-12)


def test_the_loop_only_places_a_prepared_trajectory_in_time():
    joints, mgr, ctl, model = rig()
    points = [TrajectoryPoint([0.001 * i, 0.0, 0.0], time_from_start=0.001 * (i + 1)) for i in range(20000)]
    prepared = ctl.prepare(JOINTS, points)
    assert len(prepared.segments) == len(points) - 1
    calls = []
    import modrob_sim.ros_control.trajectory as tmod
    real = tmod.Segment.__init__

    def counting(self, *a):
        calls.append(1)
        real(self, *a)
    tmod.Segment.__init__ = counting
    try:
        ok, _code, _text = ctl.submit(JOINTS, points, 0.0, mgr.time, goal_id="g", checked=True,
                                      prepared=prepared)
    finally:
        tmod.Segment.__init__ = real
    assert ok
    assert len(calls) == 1  # the segment from the current state only: nothing O(points) in the loop
    model.run(mgr, 0.5)
    assert joints[0].position == pytest.approx(0.499 - 0.001, abs=0.02)


def _samples_during_goal(extra, goal_at, seconds):
    """Times of the state samples and of the action feedback while a goal runs that was accepted
    at ``goal_at`` (off the state samples' grid)."""
    joints, mgr, ctl, model = rig(extra=extra)
    model.run(mgr, goal_at)
    ok, _, text = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    assert ok, text
    states, feedback = [], []

    def grab(t):
        if ctl.pending is not None:
            states.append(ctl.pending["stamp"])
            ctl.pending = None
        if ctl.pending_feedback is not None:
            feedback.append(ctl.pending_feedback[1]["stamp"])
            ctl.pending_feedback = None
    model.run(mgr, seconds, record=grab)
    return states, feedback


def test_action_feedback_comes_with_state_samples_at_its_rate_on_average():
    # defaults: state 50 Hz, feedback 20 Hz. A feedback between two state samples would end a batch
    # of native steps of its own, so it is taken at state sample times, 20 Hz on average
    states, feedback = _samples_during_goal(None, 0.0137, 1.4)
    assert len(states) == pytest.approx(1.4 * 50, abs=1)
    assert set(feedback) <= set(states)
    assert feedback[0] - 0.0137 <= 0.02 + 1e-9          # the goal's first feedback: the next sample
    gaps = [b - a for a, b in zip(feedback, feedback[1:])]
    assert max(gaps) <= 0.06 + 1e-9 and min(gaps) >= 0.04 - 1e-9
    assert (feedback[-1] - feedback[0]) / (len(feedback) - 1) == pytest.approx(0.05, abs=0.003)


def test_action_feedback_faster_than_the_state_keeps_its_own_times():
    states, feedback = _samples_during_goal({"state_publish_rate": 10.0, "action_monitor_rate": 20.0},
                                            0.0137, 1.0)
    assert len(states) == pytest.approx(10, abs=1)
    gaps = [b - a for a, b in zip(feedback, feedback[1:])]
    assert gaps and all(g == pytest.approx(0.05, abs=1.5e-3) for g in gaps)


def test_goals_outside_the_joint_limits_or_not_representable_are_refused_by_name():
    joints, mgr, ctl, model = rig()
    beyond = [TrajectoryPoint([0.2, 3.5, 0.3], time_from_start=1.0)]
    ok, code, text = ctl.submit(JOINTS, beyond, 0.0, 0.0, goal_id="g")
    assert not ok and code == INVALID_GOAL
    assert text == ("point 0: position 3.5 of joint 'b' is outside its limits [-3, 3] (URDF <limit lower "
                    "upper>); the joint cannot get there")
    # the 1e308 goal that used to be accepted (the state topic then carried inf)
    huge = [TrajectoryPoint([0.1, 0.1, 0.1], time_from_start=0.5), TrajectoryPoint([1e308, 0.1, 0.1],
                                                                                   time_from_start=1.0)]
    ok, code, text = ctl.submit(JOINTS, huge, 0.0, 0.0, goal_id="g")
    assert not ok and "point 1: position 1e+308 of joint 'a' is outside its limits [-3, 3]" in text
    fast = [TrajectoryPoint([0.1, 0.1, 0.1], [0.0, 1e200, 0.0], time_from_start=1.0)]
    ok, code, text = ctl.submit(JOINTS, fast, 0.0, 0.0, goal_id="g")
    assert not ok and "velocity 1e+200 of joint 'b' is beyond +-1e+06" in text
    # within a milliradian of the limit is the limit (a joint resting on its stop reads beyond it)
    assert ctl.submit(JOINTS, [TrajectoryPoint([3.0005, 0.0, 0.0], time_from_start=1.0)], 0.0, 0.0,
                      goal_id="g")[0]
    assert not ctl.submit(JOINTS, [TrajectoryPoint([3.002, 0.0, 0.0], time_from_start=1.0)], 0.0, 0.0,
                          goal_id="g")[0]
    assert ctl.pending is None or all(map(math.isfinite, ctl.pending["desired"][0]))


def test_a_continuous_joint_has_no_limits_but_refuses_unrepresentable_positions():
    joints = [IntegratorJoint(name="w", type_="continuous", inertia=0.05)]
    hw = RobotHWSim({"w": joints[0]}, simple_transmissions({"w": "PositionJointInterface"}))
    mgr = ControllerManager(hw, "/r")
    ctl = mgr.load("c", {"type": "position_controllers/JointTrajectoryController", "joints": ["w"]})
    mgr.switch(["c"], [], 2)
    assert ctl.submit(["w"], [TrajectoryPoint([40.0], time_from_start=1.0)], 0.0, 0.0, goal_id="g")[0]
    ok, code, text = ctl.submit(["w"], [TrajectoryPoint([1e308], time_from_start=1.0)], 0.0, 0.0, goal_id="g")
    assert not ok and code == INVALID_GOAL and "position 1e+308 of joint 'w' is beyond +-1e+06" in text


def test_velocity_trajectory_controller_tracks_through_the_velocity_interface():
    gains = {n: {"p": 10.0} for n in JOINTS}
    joints, mgr, ctl, model = rig("velocity_controllers/JointTrajectoryController",
                                  {"gains": gains, "velocity_ff": {n: 1.0 for n in JOINTS}},
                                  iface="VelocityJointInterface")
    assert ctl.claimed_resources == [("hardware_interface::VelocityJointInterface", JOINTS)]
    ok, _, text = ctl.submit(JOINTS, three_points(), 0.0, model.time, goal_id="g1")
    assert ok, text
    events = run_until_event(ctl, mgr, model, 2.5)
    assert events[0][:2] == ("g1", "succeeded")
    for j, target in zip(joints, [0.4, 0.4, 0.8]):
        assert j.position == pytest.approx(target, abs=0.01)
    assert mgr.hw.joints["a"].command == pytest.approx(0.0, abs=0.05)     # a velocity, near rest
