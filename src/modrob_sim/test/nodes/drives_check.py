#!/usr/bin/env python3
"""rostest node: a mobile robot driven through /cmd_vel on the /gazebo node (drives_*.test).
``drives_check.py diff_bot|skid_bot|planar_bot|trike_bot``: the robot rests level at its wheel
radius, 0.1 m/s for 5 simulated seconds moves it 0.5 m, /odom agrees with ground truth
(/gazebo/model_states) within 2 % of the distance, the odom -> base -> wheel tf chain is
complete; the diff bot's /scan and /imu publish in their frames; the planar base stops by itself
its cmdTimeout after the last command; the tricycle's wheel joint states publish."""
import math
import os
import sys
import unittest

import rospy
import rostest
import tf2_ros
from gazebo_msgs.msg import ModelStates
from gazebo_msgs.srv import GetModelState
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, JointState, LaserScan

from modrob_sim.waits import wait_until

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_helpers import Latest  # noqa: E402

ROBOT = sys.argv[1] if len(sys.argv) > 1 and not sys.argv[1].startswith("_") else "diff_bot"
# rest height of the root link, base frame of /odom, a wheel link at the end of the tf chain
SPEC = {"diff_bot": (-0.001, "base_footprint", "wheel_left_link"),
        "skid_bot": (0.129, "base_link", "front_left_wheel_link"),
        "planar_bot": (-0.001, "base_footprint", "base_footprint"),
        "trike_bot": (-0.001, "base_link", "front_wheel")}


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class DrivesCheck(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("drives_check")
        cls.states = Latest("/gazebo/model_states", ModelStates)
        cls.odom = Latest("/odom", Odometry)
        cls.cmd = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
        cls.tf = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.tf)
        assert wait_until(lambda: cls.odom.count > 0 and cls.truth() is not None, 60.0), "no /odom"

    @classmethod
    def truth(cls):
        msg = cls.states.get()
        if msg is None or ROBOT not in msg.name:
            return None
        return msg.pose[msg.name.index(ROBOT)], msg.twist[msg.name.index(ROBOT)]

    def wait_sim(self, seconds):
        end = rospy.Time.now() + rospy.Duration(seconds)
        self.assertTrue(wait_until(lambda: rospy.Time.now() >= end, 120.0), "simulated time stands still")

    def send(self, v, w):
        """One command (none of the fixtures' drives needs it repeated: planar_bot's cmdTimeout
        is longer than a drive here)."""
        t = Twist()
        t.linear.x, t.angular.z = v, w
        self.cmd.publish(t)

    def test_1_rests_level_at_its_wheel_radius(self):
        self.wait_sim(1.5)
        pose, twist = self.truth()
        q = pose.orientation
        roll = math.atan2(2.0 * (q.w * q.x + q.y * q.z), 1.0 - 2.0 * (q.x * q.x + q.y * q.y))
        pitch = math.asin(max(-1.0, min(1.0, 2.0 * (q.w * q.y - q.z * q.x))))
        self.assertLess(abs(roll), 0.003)
        self.assertLess(abs(pitch), 0.003)
        self.assertAlmostEqual(pose.position.z, SPEC[ROBOT][0], delta=0.0015)
        self.assertLess(math.hypot(twist.linear.x, twist.linear.y), 0.002)

    def test_2_drives_and_odom_follows_ground_truth(self):
        """0.1 m/s: 0.5 m in 5 simulated s, measured on /odom's own stamps (the node runs many
        times faster than real time, so when a command lands is not the test's business); then
        stopped, /odom agrees with ground truth."""
        wait_until(lambda: self.cmd.get_num_connections() > 0, 20.0)
        samples = []

        def keep(m):
            p = m.pose.pose.position
            samples.append((m.header.stamp.to_sec(), p.x, p.y, m.twist.twist.linear.x))
        sub = rospy.Subscriber("/odom", Odometry, keep)
        # The window starts 0.5 s after the first odometry at speed, by its stamp, and the
        # subscription is connected before the command: at real_time_factor 0 the simulator runs
        # seconds of simulated time while this process connects or waits for the CPU, and the
        # planar base stops by itself 8 s after its command (a fresh-clone CI run measured 0.13 m
        # of the 0.5: its window, started from the newest sample when the test looked, held only
        # the drive's last 1.3 s)
        self.assertTrue(wait_until(lambda: sub.get_num_connections() > 0, 20.0), "no /odom connection")
        self.send(0.1, 0.0)
        self.assertTrue(wait_until(lambda: len(samples) > 1 and samples[-1][3] > 0.09, 60.0),
                        "it does not move")
        t0 = next(s[0] for s in samples if s[3] > 0.09) + 0.5
        self.assertTrue(wait_until(lambda: samples[-1][0] > t0 + 5.2, 120.0))
        sub.unregister()
        a = min(samples, key=lambda s: abs(s[0] - t0))
        b = min(samples, key=lambda s: abs(s[0] - (t0 + 5.0)))
        distance = math.hypot(b[1] - a[1], b[2] - a[2]) * 5.0 / (b[0] - a[0])
        self.assertAlmostEqual(distance, 0.5, delta=0.03 * 0.5)
        self.send(0.0, 0.0)
        self.assertTrue(wait_until(lambda: abs(self.odom.get().twist.twist.linear.x) < 1e-3, 60.0))
        self.wait_sim(0.5)
        # the pose now (the service's answer), and odometry from then on: the last messages taken
        # can be a simulated second old at real_time_factor 0 (CI: 0.061 m apart)
        now = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)(model_name=ROBOT)
        self.assertTrue(now.success, now.status_message)
        end = now.pose
        odom = self.odom.after(now.header.stamp.to_sec())
        err = math.hypot(odom.pose.pose.position.x - end.position.x,
                         odom.pose.pose.position.y - end.position.y)
        self.assertLess(err, 0.02 * math.hypot(end.position.x, end.position.y))
        self.assertEqual(odom.header.frame_id, "odom")
        self.assertEqual(odom.child_frame_id, SPEC[ROBOT][1])
        self.assertAlmostEqual(yaw_of(odom.pose.pose.orientation), yaw_of(end.orientation), delta=0.01)

    def test_3_tf_chain_from_odom_to_a_wheel(self):
        base, wheel = SPEC[ROBOT][1], SPEC[ROBOT][2]
        ok = wait_until(lambda: self.tf.can_transform("odom", wheel, rospy.Time(0)), 30.0)
        self.assertTrue(ok, "no tf odom -> %s: %s" % (wheel, self.tf.all_frames_as_string()))
        # the transform at the odometry's own time: the newest of each can be seconds of simulated
        # time apart at real_time_factor 0 (CI: this process's tf listener 2.3 s behind /odom)
        odom = self.odom.get()
        stamp = odom.header.stamp
        ok = wait_until(lambda: self.tf.can_transform("odom", base, stamp), 30.0)
        self.assertTrue(ok, "no tf odom -> %s at the odometry's time %.3f" % (base, stamp.to_sec()))
        tr = self.tf.lookup_transform("odom", base, stamp)
        self.assertAlmostEqual(tr.transform.translation.x, odom.pose.pose.position.x, delta=0.01)

    @unittest.skipUnless(ROBOT == "diff_bot", "the diff bot carries the lidar and the IMU")
    def test_4_scan_imu_and_wheel_joint_states_publish(self):
        scans, imus = Latest("/scan", LaserScan), Latest("/imu", Imu)
        joints = Latest("/joint_states", JointState)
        self.assertTrue(wait_until(lambda: scans.count > 1 and imus.count > 1 and joints.count > 0, 60.0))
        self.assertEqual(scans.get().header.frame_id, "base_scan")
        self.assertEqual(len(scans.get().ranges), 360)
        self.assertEqual(imus.get().header.frame_id, "imu_link")
        self.assertAlmostEqual(imus.get().linear_acceleration.z, 9.81, delta=0.3)
        self.assertEqual(sorted(joints.get().name), ["wheel_left_joint", "wheel_right_joint"])

    @unittest.skipUnless(ROBOT == "planar_bot", "the planar base has a cmdTimeout")
    def test_5_planar_base_stops_its_cmd_timeout_after_the_last_command(self):
        """One command of 0.1 m/s sideways: the base moves for cmdTimeout (8 s), then stops by
        itself: 0.8 m on /odom (the distance, not when readings arrive, measures the time)."""
        before = self.odom.get().pose.pose.position.y
        t = Twist()
        t.linear.y = 0.1
        self.cmd.publish(t)
        self.assertTrue(wait_until(lambda: self.odom.get().twist.twist.linear.y > 0.05, 60.0),
                        "it does not move")
        self.assertTrue(wait_until(lambda: abs(self.odom.get().twist.twist.linear.y) < 1e-3, 120.0),
                        "it does not stop by itself")
        self.assertAlmostEqual(self.odom.get().pose.pose.position.y - before, 0.8, delta=0.015)

    @unittest.skipUnless(ROBOT == "trike_bot", "the tricycle publishes its wheels' joint states")
    def test_6_tricycle_wheel_joint_states(self):
        joints = Latest("/joint_states", JointState)
        self.assertTrue(wait_until(lambda: joints.count > 1, 60.0))
        self.assertEqual(sorted(joints.get().name), ["front_steering_joint", "front_wheel_joint",
                                                     "left_wheel_joint", "right_wheel_joint"])


if __name__ == "__main__":
    rostest.rosrun("modrob_sim", "drives_check", DrivesCheck)
