"""modrob_sim.waits: limits in wall time, whatever the simulated clock does."""
import time

from modrob_sim import waits


class FakeClient(object):
    """A SimpleActionClient whose server appears after ``ready_after`` looks (None: never)."""

    def __init__(self, ready_after):
        self.ready_after = ready_after
        self.looks = 0

    def wait_for_server(self, timeout):
        self.looks += 1
        return self.ready_after is not None and self.looks > self.ready_after


def test_servers_that_come_up_late_are_waited_for():
    arm, gripper = FakeClient(3), FakeClient(0)
    assert waits.wait_for_action_servers(((arm, "arm"), (gripper, "gripper")), 10.0) is None
    assert arm.looks == 4 and gripper.looks == 1


def test_a_missing_server_is_named_after_the_wall_clock_limit():
    arm, gripper = FakeClient(0), FakeClient(None)
    start = time.monotonic()
    assert waits.wait_for_action_servers(((arm, "arm"), (gripper, "gripper")), 0.2) == "gripper"
    assert time.monotonic() - start >= 0.2
    assert gripper.looks > 1


def test_wait_until():
    calls = []
    assert waits.wait_until(lambda: calls.append(1) or len(calls) > 2, 10.0)
    assert len(calls) == 3
    assert not waits.wait_until(lambda: False, 0.1)


def test_stop_following_clock_drops_rospys_clock_subscription_once(monkeypatch):
    from rospy.impl import simtime
    dropped = []
    sub = type("Sub", (), {"unregister": lambda self: dropped.append(1)})()
    monkeypatch.setattr(simtime, "_clock_sub", sub, raising=False)
    assert waits.stop_following_clock() is True
    assert dropped == [1] and simtime._clock_sub is None
    assert waits.stop_following_clock() is False and dropped == [1]
