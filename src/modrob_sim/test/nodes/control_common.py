"""Helpers shared by the control_*_check.py rostest nodes: waiting on simulated time and on the
controller manager, collecting /rosout."""
import threading
import time

import rospy
from controller_manager_msgs.srv import ListControllers
from rosgraph_msgs.msg import Log

from modrob_sim import waits


def wait_until(pred, wall_timeout, what, period=0.01):
    start = time.monotonic()
    while time.monotonic() - start < wall_timeout and not rospy.is_shutdown():
        if pred():
            return True
        time.sleep(period)
    raise AssertionError("timed out after %.0f s waiting for %s" % (wall_timeout, what))


def wait_for_action_server(client, wall_timeout, what):
    """``client.wait_for_server`` in wall time (modrob_sim.waits): actionlib's timeout is simulated
    time, which at real_time_factor 0 runs out in a fraction of a wall second."""
    if waits.wait_for_action_servers(((client, what),), wall_timeout) is not None:
        raise AssertionError("timed out after %.0f s waiting for %s" % (wall_timeout, what))


def controller_states(ns):
    rospy.wait_for_service(ns + "/controller_manager/list_controllers", timeout=60)
    srv = rospy.ServiceProxy(ns + "/controller_manager/list_controllers", ListControllers)
    return {c.name: c.state for c in srv().controller}


def wait_running(ns, names, timeout=60):
    wait_until(lambda: all(controller_states(ns).get(n) == "running" for n in names), timeout,
               "controllers %s running in %s" % (names, ns), period=0.2)


def sim_sleep(seconds, wall_timeout=60):
    """Wait ``seconds`` of simulated time."""
    end = rospy.get_time() + seconds
    wait_until(lambda: rospy.get_time() >= end, wall_timeout, "%.1f s of simulated time" % seconds)


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
        wait_until(lambda: self.find(*needles), timeout, "a log message containing %s" % (needles,))
        return self.find(*needles)[0]


def Latest(topic, cls):
    """modrob_sim.waits.Latest keeping every message (the checks read histories)."""
    return waits.Latest(topic, cls, keep=True)
