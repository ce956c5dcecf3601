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
        self.sub = rospy.Subscriber(controller + "/state", JointControllerState, self._cb, queue_size=200)

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


def rise_time(msgs, start, target):
    """Seconds from the first message until the process value covered 90 % of the step."""
    t0 = msgs[0].header.stamp
    for m in msgs:
        if abs(m.process_value - start) >= 0.9 * abs(target - start):
            return (m.header.stamp - t0).to_sec()
    return float("inf")
