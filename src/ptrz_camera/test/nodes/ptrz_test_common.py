"""Helpers of the ptrz_camera rostest nodes: the controllers of a camera, its joint states (waits on
wall and simulated time, and the latest message of other topics: modrob_sim.waits)."""
from sensor_msgs.msg import JointState

from modrob_sim import waits

# the controllers a camera's spawner starts (modrob_sim.waits.wait_running(ns, CONTROLLERS))
CONTROLLERS = ["joint_state_controller", "roll_position_controller", "tilt_position_controller",
               "pan_position_controller"]


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
