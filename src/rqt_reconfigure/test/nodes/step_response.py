"""Step responses of a JointPositionController from its state topic (header stamps = sim time)."""
import threading
import time

import rospy
from control_msgs.msg import JointControllerState
from std_msgs.msg import Float64


class StepProbe(object):
    def __init__(self, controller):
        self.lock = threading.Lock()
        self.msgs = []
        self.pub = rospy.Publisher(controller + "/command", Float64, queue_size=1, latch=True)
        # every message kept: at real_time_factor 0 the state comes at 100 Hz of simulated time, far
        # faster than wall time, and a busy test process (the GUI's event loop) fell behind a queue
        # of 200, which dropped the messages around the rise and made it look seconds long
        self.sub = rospy.Subscriber(controller + "/state", JointControllerState, self._cb, queue_size=None)

    def _cb(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def latest(self):
        with self.lock:
            return self.msgs[-1] if self.msgs else None

    def step(self, target, duration, pump=lambda: None, wall_timeout=60):
        """Command ``target``; return the state messages of the next ``duration`` s of sim time
        from the first one that carries the new set point."""
        with self.lock:
            start = len(self.msgs)
        self.pub.publish(Float64(target))
        deadline = time.monotonic() + wall_timeout
        while True:
            pump()
            with self.lock:
                new = [m for m in self.msgs[start:] if m.set_point == target]
                if new and (new[-1].header.stamp - new[0].header.stamp).to_sec() >= duration:
                    t0 = new[0].header.stamp
                    return [m for m in new if (m.header.stamp - t0).to_sec() <= duration]
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise AssertionError("no %.1f s of %s state after commanding %s"
                                     % (duration, self.sub.name, target))
            time.sleep(0.005)


def rise_time(msgs, start, target, max_gap=0.03):
    """Seconds from the first message until the process value covered 90 % of the step; None when
    the messages around that moment are more than ``max_gap`` s of simulated time apart (the
    state comes every 0.01 s; at real_time_factor 0 a publisher's queue can drop a burst of them,
    and the crossing then lies somewhere in the gap); inf when it never got there."""
    t0 = msgs[0].header.stamp
    before = msgs[0]
    for m in msgs:
        if abs(m.process_value - start) >= 0.9 * abs(target - start):
            if m is not msgs[0] and (m.header.stamp - before.header.stamp).to_sec() > max_gap:
                return None
            return (m.header.stamp - t0).to_sec()
        before = m
    return float("inf")


def measure_rise(probe, rest, target, duration, pump=lambda: None, tries=4):
    """The rise time of a step from ``rest`` (held ``duration`` s first) to ``target`` and the
    step's messages, the pair of steps made again while the crossing fell into a gap of lost
    messages (AssertionError after ``tries``)."""
    for _ in range(tries):
        start = probe.step(rest, duration, pump)[-1].process_value
        msgs = probe.step(target, duration, pump)
        rise = rise_time(msgs, start, target)
        if rise is not None:
            return rise, msgs
    raise AssertionError("%s: the state messages around the 90 %% crossing were lost in %d steps in a row"
                         % (probe.sub.name, tries))
