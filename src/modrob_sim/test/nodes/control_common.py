"""Helpers shared by the control_*_check.py rostest nodes: an action server's wait that fails the
test, /rosout collected (the waits, on wall and simulated time and on the controller manager, are
modrob_sim.waits')."""
import threading

import rospy
from rosgraph_msgs.msg import Log

from modrob_sim import waits


def wait_for_action_server(client, wall_timeout, what):
    """``client.wait_for_server`` in wall time (modrob_sim.waits): actionlib's timeout is simulated
    time, which at real_time_factor 0 runs out in a fraction of a wall second."""
    if waits.wait_for_action_servers(((client, what),), wall_timeout) is not None:
        raise AssertionError("timed out after %.0f s waiting for %s" % (wall_timeout, what))


class RosoutCollector(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.msgs = []
        self.sub = rospy.Subscriber("/rosout", Log, self._cb, queue_size=1000)

    def _cb(self, msg):
        with self.lock:
            self.msgs.append(msg.msg)

    def find(self, *needles):
        with self.lock:
            return [m for m in self.msgs if all(n in m for n in needles)]

    def wait_for(self, *needles, timeout=20):
        waits.wait_until(lambda: self.find(*needles), timeout, "a log message containing %s" % (needles,))
        return self.find(*needles)[0]


def Latest(topic, cls):
    """modrob_sim.waits.Latest keeping every message (the checks read histories)."""
    return waits.Latest(topic, cls, keep=True)
