#!/usr/bin/env python3
"""rostest node for control_diff_drive.test: diffbot driven through
/diffbot_velocity_controller/cmd_vel."""
import math
import os
import re
import sys
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
import tf2_ros
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Twist, TwistStamped
from nav_msgs.msg import Odometry

from modrob_sim import waits
from modrob_sim.physics.due import IDLE_LOOK
from modrob_sim.waits import sim_sleep, wait_running, wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from control_common import Latest, RosoutCollector  # noqa: E402

NS = "/diffbot_velocity_controller"
STOPS = re.compile(r"hooks in Python at (\d+) steps per simulated s")


class Truth(object):
    """diffbot's pose from /gazebo/model_states: (x, y, yaw), and its speeds (linear, angular)."""
    REST = 0.005        # m/s and rad/s: below both the robot stands

    def __init__(self):
        self.pose = self.speed = None
        self.sub = rospy.Subscriber("/gazebo/model_states", ModelStates, self._cb, queue_size=1)

    def _cb(self, msg):
        if "diffbot" in msg.name:
            i = msg.name.index("diffbot")
            p, v = msg.pose[i], msg.twist[i]
            q = p.orientation
            self.pose = (p.position.x, p.position.y,
                         math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)))
            self.speed = (math.hypot(v.linear.x, v.linear.y), abs(v.angular.z))

    def wait_standing(self):
        """Until the robot stands: after its last command the controller's cmd_vel_timeout (0.25 s of
        simulated time from that command's arrival), then braking."""
        wait_until(lambda: max(self.speed) < self.REST, 60, "diffbot standing")


class Driver(object):
    """Publishes one Twist at 20 Hz of simulated time (a teleop node in the simulation) until
    halted; in wall time the rate would depend on the real-time factor, and gaps longer than
    cmd_vel_timeout would make the controller brake between commands."""

    def __init__(self, pub, linear, angular):
        self.pub, self.msg = pub, Twist()
        self.msg.linear.x, self.msg.angular.z = linear, angular
        self.pub.publish(self.msg)
        self.timer = rospy.Timer(rospy.Duration(0.05), lambda event: self.pub.publish(self.msg))

    def halt(self):
        self.timer.shutdown()


class DiffDrive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("control_diff_drive_check")
        cls.log = RosoutCollector()
        cls.truth = Truth()
        cls.odom = Latest(NS + "/odom", Odometry)
        cls.cmd_out = Latest(NS + "/cmd_vel_out", TwistStamped)
        cls.tf = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf)
        wait_running("/", ["diffbot_joint_publisher", "diffbot_velocity_controller"])
        cls.cmd = waits.command_publisher(NS + "/cmd_vel", Twist, 20)
        wait_until(lambda: cls.truth.pose is not None and cls.odom.msg is not None, 30,
                   "model states and odom")

    def assert_rate(self, msgs, period):
        """``msgs`` are ``period`` of simulated time apart: every gap a whole number of periods
        (at real_time_factor 0 a publisher's queue can overflow and lose one), most of them one."""
        gaps = [(b.header.stamp - a.header.stamp).to_sec() for a, b in zip(msgs, msgs[1:])]
        periods = [max(1, round(g / period)) for g in gaps]
        self.assertTrue(all(abs(g - k * period) < 1.5e-3 for g, k in zip(gaps, periods)), gaps)
        self.assertGreater(periods.count(1), len(gaps) / 2, gaps)

    def test_1_odometry_message(self):
        sim_sleep(1.0)
        msgs = list(self.odom.history)
        m = msgs[-1]
        self.assertEqual((m.header.frame_id, m.child_frame_id), ("odom", "base_link"))
        self.assertEqual([m.pose.covariance[7 * i] for i in range(6)], [0.001, 0.001, 1e6, 1e6, 1e6, 0.03])
        self.assertEqual([m.twist.covariance[7 * i] for i in range(6)], [0.001, 0.001, 1e6, 1e6, 1e6, 0.03])
        self.assert_rate(msgs[-20:], 0.02)     # publish_rate 50

    def test_2_drives_forward_and_odometry_follows_the_truth(self):
        x0, y0, _ = self.truth.pose
        o0 = self.odom.msg.pose.pose.position
        drive = Driver(self.cmd, 0.3, 0.0)
        sim_sleep(3.0)
        drive.halt()
        self.truth.wait_standing()
        x1, y1, _ = self.truth.pose
        o1 = self.odom.fresh().pose.pose.position
        moved = math.hypot(x1 - x0, y1 - y0)
        self.assertGreater(moved, 0.8)          # about 3 s at 0.3 m/s, depending on the wall clock
        odo = math.hypot(o1.x - o0.x, o1.y - o0.y)
        self.assertLess(abs(odo - moved), 0.02 * moved, "truth %.4f m, odometry %.4f m" % (moved, odo))
        self.assertTrue(any(abs(m.twist.linear.x - 0.3) < 1e-9 for m in self.cmd_out.history))
        # the commands stopped: the robot stands
        sim_sleep(0.5)
        self.assertLess(math.hypot(self.truth.pose[0] - x1, self.truth.pose[1] - y1), 0.005)

    def test_3_turns_and_tf_carries_the_odometry(self):
        _, _, yaw0 = self.truth.pose
        drive = Driver(self.cmd, 0.0, 1.0)
        sim_sleep(1.5)
        drive.halt()
        self.truth.wait_standing()
        turned = math.atan2(math.sin(self.truth.pose[2] - yaw0), math.cos(self.truth.pose[2] - yaw0))
        self.assertGreater(turned, 1.0)
        o = self.odom.msg
        tf = self.tf.lookup_transform("odom", "base_link", rospy.Time(0), rospy.Duration(5.0))
        self.assertAlmostEqual(tf.transform.translation.x, o.pose.pose.position.x, delta=0.01)
        self.assertAlmostEqual(tf.transform.rotation.z, o.pose.pose.orientation.z, delta=0.01)

    def test_5_dynamic_reconfigure_changes_the_publish_rate(self):
        client = dynamic_reconfigure.client.Client(NS, timeout=30)
        self.assertEqual(client.get_configuration(timeout=30)["publish_rate"], 50.0)
        client.update_configuration({"publish_rate": 10.0})
        n = len(self.odom.history)
        wait_until(lambda: len(self.odom.history) >= n + 8, 60, "odometry after the change")
        self.assert_rate(self.odom.history[-6:], 0.1)
        client.update_configuration({"publish_rate": 50.0})

    def stops_per_second(self, lines):
        """The node's figure of hooks in Python per simulated second from the line that comes
        after ``lines`` more (the first of them may cover time before the caller's change)."""
        n = len(self.log.find("hooks in Python at"))
        wait_until(lambda: len(self.log.find("hooks in Python at")) >= n + lines, 60,
                   "%d lines of the node's real-time factor" % lines)
        return int(STOPS.search(self.log.find("hooks in Python at")[n + lines - 1]).group(1))

    def test_6_cmd_vel_out_costs_updates_in_python_only_while_subscribed(self):
        """publish_cmd: cmd_vel_out at every update (1 ms steps) while someone subscribes; with
        nobody subscribed the World stops for Python only for the odometry (its 50 Hz with the
        window's 2 + 1 updates before each), the joint states and the model states, not at every
        step; a new subscriber gets every update's message from at most IDLE_LOOK after it came."""
        self.cmd_out.wait_connected()
        self.cmd_out.clear()
        sim_sleep(0.5)
        stamps = [m.header.stamp.to_sec() for m in self.cmd_out.history]
        steps = [round((b - a) / 0.001) for a, b in zip(stamps, stamps[1:])]
        self.assertGreater(len(stamps), 400)
        self.assertTrue(all(k >= 1 for k in steps) and steps.count(1) > 0.9 * len(steps), steps)
        busy = self.stops_per_second(2)
        self.cmd_out.sub.unregister()
        idle = self.stops_per_second(3)
        self.assertGreater(busy, 900)
        self.assertLess(idle, 400, "hooks in Python at %d steps per simulated s without a subscriber "
                                   "(%d with one)" % (idle, busy))
        again = Latest(NS + "/cmd_vel_out", TwistStamped).wait_connected()
        came = rospy.get_time()
        wait_until(lambda: len(again.history) > 300, 60, "cmd_vel_out again")
        stamps = [m.header.stamp.to_sec() for m in again.history]
        self.assertLess(stamps[0], came + IDLE_LOOK + 0.05)
        steps = [round((b - a) / 0.001) for a, b in zip(stamps, stamps[1:])]
        self.assertTrue(all(k >= 1 for k in steps) and steps.count(1) > 0.9 * len(steps), steps)
        again.sub.unregister()

    def test_4_nan_is_ignored_with_a_warning(self):
        bad = Twist()
        bad.linear.x = float("nan")
        self.cmd.publish(bad)
        self.log.wait_for(NS + "/cmd_vel", "not finite")


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "control_diff_drive", DiffDrive)
