"""The can stacker waits for its actions' results in wall time (modrob_sim.waits): at
real_time_factor 0 actionlib's simulated-time limit runs out in wall milliseconds."""
import threading
import time
import types

from actionlib import SimpleGoalState
from actionlib_msgs.msg import GoalStatus

from katana_sim.stacker import ArmInterface

Q = [0.0, 1.0, -1.0, 0.5, 0.0]


class FakeClient(object):
    """A SimpleActionClient whose goal is done at the ``done_after``-th look (None: never) and whose
    own wait_for_result says "no result" at once, as a simulated-time limit at real_time_factor 0."""

    def __init__(self, done_after):
        self.done_after, self.looks, self.gh, self.cancelled = done_after, 0, None, False
        self.action_client = types.SimpleNamespace(ns="/fake")

    def send_goal(self, goal):
        self.gh, self.goal = object(), goal

    @property
    def simple_state(self):
        self.looks += 1
        done = self.done_after is not None and self.looks >= self.done_after
        return SimpleGoalState.DONE if done else SimpleGoalState.ACTIVE

    def wait_for_result(self, timeout):
        return False

    def cancel_goal(self):
        self.cancelled = True

    def get_result(self):
        return types.SimpleNamespace(error_code=0, error_string="")

    def get_state(self):
        return GoalStatus.SUCCEEDED

    def get_goal_status_text(self):
        return ""


def arm_interface(arm, gripper, wait):
    a = ArmInterface.__new__(ArmInterface)   # without the ROS wiring of __init__
    a.lock, a.wait, a.desired = threading.Lock(), wait, None
    a.arm, a.gripper = arm, gripper
    return a


def test_a_move_and_a_grip_that_end_after_a_few_looks_succeed():
    a = arm_interface(FakeClient(3), FakeClient(2), 10.0)
    assert a.follow([(0.5, Q), (1.0, Q)]) == (True, 0, "")
    assert a.arm.looks == 3 and not a.arm.cancelled
    ok, _, _ = a.grip(0.2, 0.5)
    assert ok and a.gripper.looks == 2


def test_no_result_within_the_wall_limit_cancels_the_goal_and_says_so():
    a = arm_interface(FakeClient(None), FakeClient(None), 0.2)
    start = time.monotonic()
    ok, code, text = a.follow([(0.3, Q)])
    assert time.monotonic() - start >= 0.5        # the move's 0.3 s plus wait
    assert not ok and code is None and a.arm.cancelled
    assert text.startswith("no result within") and text.endswith("wall seconds")
    ok, _, text = a.grip(0.2, 0.5)
    assert not ok and a.gripper.cancelled and "wall seconds" in text
