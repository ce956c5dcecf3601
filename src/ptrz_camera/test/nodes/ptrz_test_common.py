"""Helpers of the ptrz_camera rostest nodes: waiting on wall and simulated time, controllers,
the joint states (the latest message of other topics: modrob_sim.waits.Latest)."""
import time

import rospy
from controller_manager_msgs.srv import ListControllers
from sensor_msgs.msg import JointState

from modrob_sim import waits

CONTROLLERS = ["joint_state_controller", "roll_position_controller", "tilt_position_controller",
               "pan_position_controller"]


def wait_until(pred, wall_timeout, what, period=0.01):
    start = time.monotonic()
    while time.monotonic() - start < wall_timeout and not rospy.is_shutdown():
        if pred():
            return True
        time.sleep(period)
    raise AssertionError("timed out after %.0f s waiting for %s" % (wall_timeout, what))


def wait_running(ns, names=CONTROLLERS, timeout=60):
    rospy.wait_for_service(ns + "/controller_manager/list_controllers", timeout=timeout)
    srv = rospy.ServiceProxy(ns + "/controller_manager/list_controllers", ListControllers)
    wait_until(lambda: all({c.name: c.state for c in srv().controller}.get(n) == "running" for n in names),
               timeout, "controllers %s running in %s" % (names, ns), period=0.2)


def sim_sleep(seconds, wall_timeout=60):
    end = rospy.get_time() + seconds
    wait_until(lambda: rospy.get_time() >= end, wall_timeout, "%.1f s of simulated time" % seconds)


class Joints(waits.Latest):
    """/<ns>/joint_states, every message kept (modrob_sim.waits.Latest: it does not fall behind a
    simulator at real_time_factor 0)."""

    def __init__(self, ns):
        waits.Latest.__init__(self, ns + "/joint_states", JointState, keep=True)

    def position(self, joint):
        msg = self.msg
        return msg.position[msg.name.index(joint)]

    def positions_since(self, joint, t0):
        """``joint``'s positions in the messages stamped at simulated time ``t0`` or later."""
        self.after(t0)
        return [m.position[m.name.index(joint)] for m in self.history if m.header.stamp.to_sec() >= t0]
