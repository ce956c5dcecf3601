#!/usr/bin/env python3
"""rostest node for mobile_stack.test."""
import math
import threading
import unittest

import rospy
import rostest
import tf2_ros
from controller_manager_msgs.srv import ListControllers
from diagnostic_msgs.msg import DiagnosticArray
from gazebo_msgs.msg import ModelStates
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_msgs.msg import Bool
from visualization_msgs.msg import InteractiveMarkerFeedback

from modrob_sim.waits import Latest, sim_sleep, wait_until

REST = 0.005        # m/s and rad/s: below both the robot stands


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


class MobileStack(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("mobile_stack_check")
        cls.lock = threading.Lock()
        cls.truth = cls.ekf = cls.speed = cls.ekf_speed = cls.ekf_stamp = None
        rospy.Subscriber("/gazebo/model_states", ModelStates, cls._on_states, queue_size=1)
        rospy.Subscriber("/odometry/filtered", Odometry, cls._on_ekf, queue_size=1)
        cls.diagnostics = Latest("/diagnostics", DiagnosticArray, keep=True)
        cls.tf = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf)
        cls.cmd = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        cls.estop = rospy.Publisher("/e_stop", Bool, queue_size=1, latch=True)
        cls.feedback = rospy.Publisher("/twist_marker_server/feedback", InteractiveMarkerFeedback,
                                       queue_size=1)
        rospy.wait_for_service("/controller_manager/list_controllers", timeout=60)
        listing = rospy.ServiceProxy("/controller_manager/list_controllers", ListControllers)
        wait_until(lambda: {c.state for c in listing().controller} == {"running"}
                   and len(listing().controller) == 2, 60, "the controllers running")
        wait_until(lambda: cls.truth is not None and cls.ekf is not None, 60,
                   "the truth and odometry/filtered")
        for p in (cls.cmd, cls.estop, cls.feedback):
            wait_until(lambda: p.get_num_connections() > 0, 30, "a subscriber of %s" % p.resolved_name)

    @classmethod
    def _on_states(cls, msg):
        if "diffbot" in msg.name:
            i = msg.name.index("diffbot")
            p, v = msg.pose[i], msg.twist[i]
            cls.truth = (p.position.x, p.position.y, yaw_of(p.orientation))
            cls.speed = (math.hypot(v.linear.x, v.linear.y), abs(v.angular.z))

    @classmethod
    def _on_ekf(cls, msg):
        p = msg.pose.pose
        v = msg.twist.twist
        cls.ekf = (p.position.x, p.position.y, yaw_of(p.orientation))
        cls.ekf_speed = (math.hypot(v.linear.x, v.linear.y), abs(v.angular.z))
        cls.ekf_stamp = msg.header.stamp.to_sec()

    def drive(self, publish, seconds):
        """``publish()`` at 20 Hz of simulated time for ``seconds``; returns once the robot stands (the
        controller's cmd_vel_timeout after the last command that reached it, then braking)."""
        publish()
        timer = rospy.Timer(rospy.Duration(0.05), lambda event: publish())
        sim_sleep(seconds, 120)
        timer.shutdown()
        wait_until(lambda: max(self.speed) < REST, 60, "diffbot standing after the drive")

    def locked(self, lock):
        """twist_mux's /diagnostics has reported ``lock`` locked (it has taken the lock's message)."""
        return any(kv.key == "lock " + lock and kv.value.startswith("locked")
                   for m in self.diagnostics.history for s in m.status for kv in s.values)

    def twist(self, linear, angular):
        t = Twist()
        t.linear.x, t.angular.z = linear, angular
        return lambda: self.cmd.publish(t)

    def test_1_cmd_vel_drives_and_the_estimate_follows(self):
        t0, e0 = self.truth, self.ekf
        self.drive(self.twist(0.4, 0.3), 4.0)
        t1, stood = self.truth, rospy.get_time()
        # the estimate of a time after the robot stood, settled: the filter node may be behind the
        # simulation on a loaded machine (its messages queued, its ticks late)
        wait_until(lambda: self.ekf_stamp >= stood and max(self.ekf_speed) < REST, 60,
                   "odometry/filtered of a time after diffbot stood (%.3f s), with the robot at rest" % stood)
        e1 = self.ekf
        moved = math.hypot(t1[0] - t0[0], t1[1] - t0[1])
        # 0.4 m/s and 0.3 rad/s for 4 s, and up to 0.25 s more until the controller's
        # cmd_vel_timeout (less when the loaded machine leaves gaps in the test's 20 Hz)
        self.assertGreater(moved, 1.2)
        self.assertGreater(t1[2] - t0[2], 1.0)
        self.assertLess(t1[2] - t0[2], 0.3 * 4.25 + 0.06)
        # the EKF's displacement and heading change agree with the truth's
        d_truth = (t1[0] - t0[0], t1[1] - t0[1])
        d_ekf = (e1[0] - e0[0], e1[1] - e0[1])
        report = ("truth moved (%.3f, %.3f) and turned %.3f; the estimate (%.3f, %.3f) and %.3f"
                  % (d_truth + (t1[2] - t0[2],) + d_ekf + (e1[2] - e0[2],)))
        rospy.loginfo("mobile_stack: " + report)
        # within 5 cm (the EKF's bound over 20 m in test_ekf.py; here 1.6 m with a turn, on a machine
        # whose load delays messages: 0.2 to 2.2 cm seen with the load at 6-7). Read at the stand
        # itself, the estimate could be one from before it: 13 cm and 0.19 rad short once
        self.assertLess(math.hypot(d_truth[0] - d_ekf[0], d_truth[1] - d_ekf[1]), 0.05, report)
        self.assertAlmostEqual(e1[2] - e0[2], t1[2] - t0[2], delta=0.05)
        tf = self.tf.lookup_transform("odom", "base_link", rospy.Time(0), rospy.Duration(5.0))
        self.assertAlmostEqual(tf.transform.translation.x, e1[0], delta=0.02)
        self.assertAlmostEqual(tf.transform.translation.y, e1[1], delta=0.02)

    def test_2_the_marker_outranks_cmd_vel(self):
        fb = InteractiveMarkerFeedback(client_id="mobile_stack_check", marker_name="robot_twist_marker",
                                       control_name="move_x",
                                       event_type=InteractiveMarkerFeedback.POSE_UPDATE)
        fb.header.frame_id = "base_link"
        fb.pose.position.x = -0.3            # backwards at 0.3 m/s, while /cmd_vel says forwards
        fb.pose.orientation.w = 1.0
        forward = self.twist(0.3, 0.0)
        y0 = self.truth[2]
        start = self.truth

        def both():
            forward()
            self.feedback.publish(fb)
        self.drive(both, 2.0)
        heading = (math.cos(y0), math.sin(y0))
        along = (self.truth[0] - start[0]) * heading[0] + (self.truth[1] - start[1]) * heading[1]
        self.assertLess(along, -0.3)

    def test_3_e_stop_stops_everything(self):
        self.estop.publish(Bool(True))
        wait_until(lambda: self.locked("e_stop"), 30, "twist_mux's /diagnostics reporting e_stop locked")
        start = self.truth
        self.drive(self.twist(0.4, 0.0), 2.0)
        self.assertLess(math.hypot(self.truth[0] - start[0], self.truth[1] - start[1]), 0.005)
        self.estop.publish(Bool(False))


if __name__ == "__main__":
    rostest.rosrun("robot_localization", "mobile_stack_check", MobileStack)
