"""RosArm.settle judges the arm on joint_states stamped after the wait began and times out on their
stamps: a stream that reaches the scenario seconds of simulated time late (a loaded machine) must
delay the verdict, not fail a run on positions from before the arm got there."""
import threading

import numpy as np
import pytest

from modrob_motion.bulbs_and_slides import ros_robot


class Info(object):
    robot_id = 0
    arm_joints = ["j1", "j2"]


class FakeSim(object):
    """The scenario's clock and a joint_states stream ``lag`` s behind it: the arm reaches its
    target at ``arrive`` s; each sim_sleep advances the clock and delivers the sample stamped
    ``lag`` earlier."""

    def __init__(self, arm, arrive, lag, target):
        self.arm, self.arrive, self.lag, self.target = arm, arrive, lag, np.asarray(target)
        self.now = 10.0
        self.deliver()

    def q_at(self, t):
        return self.target if t >= self.arrive else self.target + 0.09

    def deliver(self):
        stamp = self.now - self.lag
        self.arm.js_stamp = stamp
        self.arm.q.update(zip(Info.arm_joints, self.q_at(stamp)))

    def sleep(self, dt, *args):
        self.now += dt
        self.deliver()


def make_arm(monkeypatch, arrive, lag, silent_after=None):
    arm = ros_robot.RosArm.__new__(ros_robot.RosArm)
    arm.info, arm._lock, arm.q, arm.recorder = Info(), threading.Lock(), {}, None
    arm.cmd = {"j1": 0.5, "j2": -0.2}
    sim = FakeSim(arm, arrive, lag, [0.5, -0.2])
    if silent_after is not None:        # the stream stops: only the clock moves on
        real = sim.deliver
        sim.deliver = lambda: real() if sim.now < silent_after else None
    monkeypatch.setattr(ros_robot.rospy, "get_time", lambda: sim.now)
    monkeypatch.setattr(ros_robot, "sim_sleep", sim.sleep)
    return arm, sim


def test_a_late_stream_delays_the_verdict(monkeypatch):
    # the arm is there at 10.5 s; its joint_states arrive 3 s late. Counted on the clock, 3 s of
    # waiting would have ended at 13.0 s with the sample stamped 10.0 s: 0.09 rad off
    arm, sim = make_arm(monkeypatch, arrive=10.5, lag=3.0)
    err = arm.settle(tol=0.004, timeout=3.0)
    assert err < 0.004
    assert sim.now == pytest.approx(13.5, abs=0.02)


def test_an_arm_that_never_gets_there_times_out_on_the_stamps(monkeypatch):
    arm, sim = make_arm(monkeypatch, arrive=1e9, lag=1.0)
    err = arm.settle(tol=0.004, timeout=3.0)
    assert err == pytest.approx(0.09)
    assert sim.now == pytest.approx(14.0, abs=0.02)     # 3 s of stamps after 10.0, 1 s late


def test_no_fresh_joint_states_ends_at_the_wall_guard(monkeypatch):
    arm, sim = make_arm(monkeypatch, arrive=0.0, lag=0.5, silent_after=10.0)
    warned = []
    monkeypatch.setattr(ros_robot.rospy, "logwarn", lambda *a: warned.append(a[0] % a[1:]))
    err = arm.settle(tol=0.004, timeout=3.0, wall_guard=0.05)
    assert err == float("inf")
    assert warned and "no joint_states" in warned[0]


class FastSimSlowCommand(object):
    """The simulation at real-time factor ``rtf`` while the gripper command reaches the simulator
    ``latency`` wall s after it was sent (motion_publisher, another process, on a loaded machine):
    the fingers stand open until then, then stop closed on the bulb at the grip force."""

    def __init__(self, arm, rtf, latency, monkeypatch):
        self.arm, self.rtf, self.latency = arm, rtf, latency
        self.now, self.wall = 10.0, 1000.0
        self.sent = self.wall
        monkeypatch.setattr(ros_robot.rospy, "get_time", lambda: self.now)
        monkeypatch.setattr(ros_robot.time, "time", lambda: self.wall)
        monkeypatch.setattr(ros_robot, "sim_sleep", self.sleep)
        self.deliver()

    def closed(self):
        return self.wall - self.sent >= self.latency

    def deliver(self):
        self.arm.js_stamp = self.now

    def sleep(self, dt, *args):
        self.wall += dt / self.rtf
        self.now += dt
        self.deliver()


def make_gripper(monkeypatch, rtf, latency):
    arm = ros_robot.RosArm.__new__(ros_robot.RosArm)
    arm.info, arm._lock, arm.q, arm.recorder = Info(), threading.Lock(), {}, None
    sim = FastSimSlowCommand(arm, rtf, latency, monkeypatch)
    arm.measured = lambda names: np.array([0.0295, 0.0295]) if sim.closed() else np.array([0.05, 0.05])
    arm.efforts = lambda names: np.array([-3.0, -3.0]) if sim.closed() else np.array([-0.6, -0.6])
    arm._finger_effort_limits = lambda names: np.array([3.0, 3.0])
    return arm, sim


def test_a_gripper_command_late_in_wall_time_is_waited_for(monkeypatch):
    # 11x real time: 10 simulated s are 0.9 wall s, less than the command took to land (2 s); the
    # wait used to give up then and the lift left the bulb on the slide
    arm, sim = make_gripper(monkeypatch, rtf=11.0, latency=2.0)
    assert arm._wait_fingers("close", ["f1", "f2"], np.array([0.014, 0.014]), timeout=10.0, wall_min=5.0)
    assert 2.0 <= sim.wall - sim.sent < 2.1


def test_a_gripper_that_never_moves_gives_up_after_both_timeouts(monkeypatch):
    arm, sim = make_gripper(monkeypatch, rtf=11.0, latency=1e9)
    warned = []
    monkeypatch.setattr(ros_robot.rospy, "logwarn", lambda *a: warned.append(a[0] % a[1:]))
    assert not arm._wait_fingers("close", ["f1", "f2"], np.array([0.014, 0.014]), timeout=10.0, wall_min=5.0)
    assert 5.0 <= sim.wall - sim.sent < 5.1 and sim.now - 10.0 > 10.0
    assert warned and "did not close" in warned[0]
