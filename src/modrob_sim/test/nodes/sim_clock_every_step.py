#!/usr/bin/env python3
"""rostest node: with /clock at every step, as fast as possible, and the topics published through
roscpp (the C loop's batches hand their /clock messages over together when each batch ends), a
subscriber that keeps every message receives /clock in order, each time once, on the 1 ms grid,
from the paused time to the time at which the simulation was paused again. Not every step's message: the
publisher's queue holds 10 messages per subscriber (as Gazebo's /clock), and roscpp drops the oldest
when its transport thread falls that far behind (test_native_pub.py checks completeness where the
pace allows it). A box falls meanwhile, so that batches end at the states' schedule too."""
import sys
import threading
import unittest

import rosnode
import rospy
import rostest
from rosgraph_msgs.msg import Clock

from modrob_sim.waits import wait_until

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from sim_helpers import Gazebo  # noqa: E402

STEP_NS = 1000000


class SimClockEveryStep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.gz = Gazebo()
        cls.lock = threading.Lock()
        cls.got = []

    @classmethod
    def _cb(cls, msg):
        with cls.lock:
            cls.got.append(msg.clock.to_nsec())

    def received(self):
        with self.lock:
            return list(self.got)

    def test_every_step_once_in_order(self):
        self.assertIn("/gazebo_roscpp", rosnode.get_node_names(), "the node does not publish through roscpp")
        self.assertTrue(self.gz.spawn("box", "box.urdf", z=2.0).success)
        # a queue that holds everything (/use_sim_time is false here: this process's rospy does not
        # subscribe to /clock itself, which would make the one connection's queue 1 message)
        sub = rospy.Subscriber("/clock", Clock, self._cb, queue_size=None)
        self.assertTrue(wait_until(lambda: self.received(), 20.0), "no latched /clock")
        start = self.received()[-1]
        self.gz.unpause_physics()
        wait_until(lambda: self.received()[-1] >= start + 3 * 10 ** 9, 60.0)
        self.gz.pause_physics()
        end = int(round(self.gz.sim_time() * 1e9))
        self.assertTrue(wait_until(lambda: self.received()[-1] == end, 20.0),
                        "the paused time %d never arrived (last %d)" % (end, self.received()[-1]))
        sub.unregister()
        got = self.received()
        run = got[got.index(start):]
        while len(run) > 1 and run[-1] == run[-2] == end:
            run.pop()           # pause_physics publishes the paused time once more
        self.assertGreater(end - start, 3 * 10 ** 9 - 1)
        self.assertEqual(run, sorted(set(run)), "/clock out of order or repeated")
        self.assertEqual([t for t in run if t % STEP_NS], [], "/clock off the step grid")
        self.assertEqual(run[-1], end)
        # a stream, not a trickle (here about half of the steps' messages reach this subscriber)
        self.assertGreater(len(run), (end - start) // STEP_NS // 100,
                           "%d messages for %d steps" % (len(run), (end - start) // STEP_NS))


if __name__ == "__main__":
    rospy.init_node("sim_clock_every_step", anonymous=True)
    rostest.rosrun("modrob_sim", "sim_clock_every_step", SimClockEveryStep)
